// The policy table and the session-level asymmetric operations: CreateSession/ActivateSession
// signatures (OPC 10000-4 §5.6.2, §5.6.3, §7.36) and encrypted user token secrets (§7.41.2.2).
#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "openssl.hpp"
#include "policy_spec.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace {

constexpr std::string_view kRsaSha256 = "http://www.w3.org/2001/04/xmldsig-more#rsa-sha256";
constexpr std::string_view kRsaPssSha256 = "http://opcfoundation.org/UA/security/rsa-pss-sha2-256";
constexpr std::string_view kRsaOaep = "http://www.w3.org/2001/04/xmlenc#rsa-oaep";
constexpr std::string_view kRsaOaepSha256 = "http://opcfoundation.org/UA/security/rsa-oaep-sha2-256";

// OPC 10000-7 §6.6.161 (Basic256Sha256), §6.6.164 (Aes128_Sha256_RsaOaep), §6.6.166
// (Aes256_Sha256_RsaPss).
const std::array<PolicySpec, 3> kPolicies = {{
    {kBasic256Sha256Uri, 32, ossl::Signature::Pkcs1v15Sha256, ossl::Encryption::OaepSha1, kRsaSha256,
     kRsaOaep, 2048, 4096, 2},
    {kAes128Sha256RsaOaepUri, 16, ossl::Signature::Pkcs1v15Sha256, ossl::Encryption::OaepSha1, kRsaSha256,
     kRsaOaep, 2048, 4096, 1},
    {kAes256Sha256RsaPssUri, 32, ossl::Signature::PssSha256, ossl::Encryption::OaepSha256, kRsaPssSha256,
     kRsaOaepSha256, 2048, 4096, 3},
}};

// A policy's algorithms and the key an operation needs: our private key (PKCS#8) or the public
// key of a certificate (the leaf of a chain).
struct Keyed {
  const PolicySpec* spec = nullptr;
  ossl::Key key;
};

Result<Keyed> keyed(std::string_view policy_uri, ByteSpan key_or_certificate, bool is_private) {
  const PolicySpec* spec = find_policy_spec(policy_uri);
  if (spec == nullptr) {
    return status_error(status::BadSecurityPolicyRejected,
                        fmt::format("'{}' has no asymmetric algorithms", policy_uri));
  }
  auto key =
      is_private ? ossl::load_private_key(key_or_certificate) : ossl::public_key_of(key_or_certificate);
  if (!key) {
    return key.error();
  }
  return Keyed{spec, std::move(*key)};
}

}  // namespace

const PolicySpec* find_policy_spec(std::string_view uri) {
  for (const auto& spec : kPolicies) {
    if (spec.uri == uri) {
      return &spec;
    }
  }
  return nullptr;
}

std::string_view signature_algorithm_uri(std::string_view policy_uri) {
  const PolicySpec* spec = find_policy_spec(policy_uri);
  return spec == nullptr ? std::string_view() : spec->signature_uri;
}

std::string_view encryption_algorithm_uri(std::string_view policy_uri) {
  const PolicySpec* spec = find_policy_spec(policy_uri);
  return spec == nullptr ? std::string_view() : spec->encryption_uri;
}

Result<SignatureData> sign(std::string_view policy_uri, ByteSpan private_key, ByteSpan data) {
  auto k = keyed(policy_uri, private_key, true);
  if (!k) {
    return k.error();
  }
  auto signature = ossl::sign(k->key.get(), k->spec->signature, data);
  if (!signature) {
    return signature.error();
  }
  SignatureData out;
  out.algorithm = String(k->spec->signature_uri);
  out.signature = ByteString(std::move(*signature));
  return out;
}

Status verify(std::string_view policy_uri, const ByteString& certificate, ByteSpan data,
              const SignatureData& signature) {
  auto k = keyed(policy_uri, certificate.span(), false);
  if (!k) {
    return k.error();
  }
  if (signature.algorithm.view() != k->spec->signature_uri) {
    return status_error(status::BadSecurityChecksFailed,
                        fmt::format("signature algorithm '{}', {} uses '{}'", signature.algorithm.view(),
                                    policy_name(policy_uri), k->spec->signature_uri));
  }
  return ossl::verify(k->key.get(), k->spec->signature, data, signature.signature.span());
}

Result<ByteString> encrypt_secret(std::string_view policy_uri, const ByteString& certificate, ByteSpan secret,
                                  ByteSpan nonce) {
  auto k = keyed(policy_uri, certificate.span(), false);
  if (!k) {
    return k.error();
  }
  ByteWriter plain;
  plain.u32(static_cast<std::uint32_t>(secret.size() + nonce.size()));
  plain.bytes(secret);
  plain.bytes(nonce);
  auto cipher = ossl::encrypt(k->key.get(), k->spec->encryption, plain.data(), false);
  if (!cipher) {
    return cipher.error();
  }
  return ByteString(std::move(*cipher));
}

Result<Bytes> decrypt_secret(std::string_view policy_uri, ByteSpan private_key, ByteSpan cipher,
                             ByteSpan nonce) {
  auto k = keyed(policy_uri, private_key, true);
  if (!k) {
    return k.error();
  }
  auto plain = ossl::decrypt(k->key.get(), k->spec->encryption, cipher);
  if (!plain) {
    return status_error(status::BadIdentityTokenInvalid, "the token secret does not decrypt");
  }
  ByteReader reader(*plain);
  const std::uint32_t length = reader.u32();
  if (!reader.ok() || length > reader.remaining() || length < nonce.size()) {
    return status_error(status::BadIdentityTokenInvalid, "the token secret has the wrong length");
  }
  const ByteSpan data = reader.rest().first(length);
  // §7.41.2.2: a client should not pad after the nonce; if it does, every padding byte is zero.
  const ByteSpan padding = reader.rest().subspan(length);
  if (std::any_of(padding.begin(), padding.end(), [](std::uint8_t b) { return b != 0; })) {
    return status_error(status::BadIdentityTokenInvalid, "the token secret's padding is not zero");
  }
  const ByteSpan tail = data.subspan(data.size() - nonce.size());
  if (!std::equal(tail.begin(), tail.end(), nonce.begin(), nonce.end())) {
    // §7.41.2.2: the secret carries the last server nonce, so an old token cannot be replayed.
    return status_error(status::BadIdentityTokenInvalid, "the token secret carries another server nonce");
  }
  return Bytes(data.begin(), data.end() - static_cast<std::ptrdiff_t>(nonce.size()));
}

}  // namespace sf::opcua::security
