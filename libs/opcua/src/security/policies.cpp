// Basic256Sha256, Aes128_Sha256_RsaOaep and Aes256_Sha256_RsaPss (OPC 10000-7) as secure-channel
// plug-ins: asymmetric crypto for OPN chunks, symmetric crypto for MSG/CLO chunks (OPC 10000-6
// §6.7.2, §6.7.5).
#include "sf/opcua/security/policies.hpp"

#include <openssl/crypto.h>

#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "openssl.hpp"
#include "policy_spec.hpp"
#include "sf/core/text.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace {

constexpr std::size_t kNonceLength = 32;
constexpr std::size_t kSigningKeyLength = 32;
constexpr std::size_t kAesBlock = 16;
constexpr std::size_t kHmacSize = 32;
// OPC 10000-6 §6.7.2.5: an ExtraPaddingSize byte follows when the key is larger than 2048 bits.
constexpr std::size_t kExtraPaddingAbove = 256;

// One direction of OPN chunks: sign with one key, encrypt for the other (OPC 10000-6 §6.7.2).
class AsymmetricCrypto final : public MessageCrypto {
 public:
  // Sending: sign_key = own private key, cipher_key = peer public key. Receiving: sign_key =
  // peer public key (verifies), cipher_key = own private key (decrypts).
  AsymmetricCrypto(const PolicySpec& spec, ossl::Key sign_key, ossl::Key cipher_key)
      : spec_(spec),
        sign_key_(std::move(sign_key)),
        cipher_key_(std::move(cipher_key)),
        signature_size_(ossl::rsa_bytes(sign_key_.get())),
        cipher_block_(ossl::rsa_bytes(cipher_key_.get())),
        plain_block_(ossl::oaep_plain_block(cipher_block_, spec.encryption)) {}

  [[nodiscard]] std::size_t signature_size() const override { return signature_size_; }
  [[nodiscard]] bool encrypts() const override { return true; }
  [[nodiscard]] std::size_t plain_block_size() const override { return plain_block_; }
  [[nodiscard]] std::size_t cipher_block_size() const override { return cipher_block_; }
  [[nodiscard]] bool extra_padding_byte() const override { return cipher_block_ > kExtraPaddingAbove; }
  Result<Bytes> sign(ByteSpan data) const override {
    return ossl::sign(sign_key_.get(), spec_.signature, data);
  }
  Status verify(ByteSpan data, ByteSpan signature) const override {
    return ossl::verify(sign_key_.get(), spec_.signature, data, signature);
  }
  Result<Bytes> encrypt(ByteSpan plain) const override {
    return ossl::encrypt(cipher_key_.get(), spec_.encryption, plain);
  }
  Result<Bytes> decrypt(ByteSpan cipher) const override {
    return ossl::decrypt(cipher_key_.get(), spec_.encryption, cipher);
  }

 private:
  const PolicySpec& spec_;
  ossl::Key sign_key_;
  ossl::Key cipher_key_;
  std::size_t signature_size_;
  std::size_t cipher_block_;
  std::size_t plain_block_;
};

// One direction of MSG/CLO chunks with the keys derived for one token (OPC 10000-6 §6.7.5):
// HMAC-SHA256 signatures, AES-CBC with the derived IV for every chunk.
class SymmetricCrypto final : public MessageCrypto {
 public:
  SymmetricCrypto(const SymmetricKeys& keys, bool encrypt)
      : hmac_(keys.signing_key),
        key_(keys.encrypting_key),
        iv_(keys.initialization_vector),
        encrypt_(encrypt) {}

  [[nodiscard]] std::size_t signature_size() const override { return kHmacSize; }
  [[nodiscard]] bool encrypts() const override { return encrypt_; }
  [[nodiscard]] std::size_t plain_block_size() const override { return encrypt_ ? kAesBlock : 1; }
  [[nodiscard]] std::size_t cipher_block_size() const override { return encrypt_ ? kAesBlock : 1; }
  [[nodiscard]] bool extra_padding_byte() const override { return false; }
  Result<Bytes> sign(ByteSpan data) const override {
    Bytes mac = hmac_.mac(data);
    if (mac.size() != kHmacSize) {
      return status_error(status::BadInternalError, "HMAC-SHA256 failed");
    }
    return mac;
  }
  Status verify(ByteSpan data, ByteSpan signature) const override {
    const Bytes expected = hmac_.mac(data);
    // Constant time, so the comparison tells an attacker nothing about the expected value.
    if (expected.size() != kHmacSize || signature.size() != kHmacSize ||
        CRYPTO_memcmp(expected.data(), signature.data(), kHmacSize) != 0) {
      return status_error(status::BadSecurityChecksFailed, "the HMAC-SHA256 signature does not match");
    }
    return {};
  }
  Result<Bytes> encrypt(ByteSpan plain) const override { return ossl::aes_cbc(true, key_, iv_, plain); }
  Result<Bytes> decrypt(ByteSpan cipher) const override { return ossl::aes_cbc(false, key_, iv_, cipher); }

 private:
  ossl::HmacSha256 hmac_;
  Bytes key_;
  Bytes iv_;
  bool encrypt_;
};

class RsaAesPolicy final : public SecurityPolicy {
 public:
  explicit RsaAesPolicy(const PolicySpec& spec) : spec_(spec) {}

  [[nodiscard]] std::string_view uri() const override { return spec_.uri; }
  [[nodiscard]] bool uses_certificates() const override { return true; }
  [[nodiscard]] std::size_t nonce_length() const override { return kNonceLength; }
  [[nodiscard]] std::size_t signing_key_length() const override { return kSigningKeyLength; }
  [[nodiscard]] std::size_t encrypting_key_length() const override { return spec_.symmetric_key_length; }
  [[nodiscard]] std::size_t encrypting_block_size() const override { return kAesBlock; }

  Result<ByteString> create_nonce() const override {
    auto nonce = ossl::random_bytes(kNonceLength);
    if (!nonce) {
      return nonce.error();
    }
    return ByteString(std::move(*nonce));
  }

  Result<Bytes> derive(ByteSpan secret, ByteSpan seed, std::size_t length) const override {
    const ossl::HmacSha256 hmac(secret);
    // P_SHA256 (OPC 10000-6 §6.7.5): the secret is fixed, so one keyed HMAC serves every round.
    return p_hash([&hmac](ByteSpan, ByteSpan data) { return hmac.mac(data); }, secret, seed, length);
  }

  Result<ByteString> thumbprint(const ByteString& certificate) const override {
    std::size_t used = 0;
    auto leaf = ossl::load_certificate(certificate.span(), &used);
    if (!leaf) {
      return leaf.error();
    }
    return ByteString(ossl::sha1(certificate.span().first(used)));
  }

  Result<ChannelCrypto> asymmetric(const SecurityCredentials& local,
                                   const ByteString& peer_certificate) const override {
    auto own = ossl::load_private_key(local.private_key);
    if (!own) {
      return own.error();
    }
    auto peer = ossl::public_key_of(peer_certificate.span());
    if (!peer) {
      return peer.error();
    }
    SF_TRY(check_key(own->get(), "our"));
    SF_TRY(check_key(peer->get(), "the peer's"));
    return ChannelCrypto{std::make_shared<AsymmetricCrypto>(spec_, *own, *peer),
                         std::make_shared<AsymmetricCrypto>(spec_, *peer, *own)};
  }

  Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& sending,
                                  const SymmetricKeys& receiving) const override {
    if (mode != MessageSecurityMode::Sign && mode != MessageSecurityMode::SignAndEncrypt) {
      return status_error(status::BadSecurityModeRejected,
                          fmt::format("{} needs mode Sign or SignAndEncrypt", policy_name(spec_.uri)));
    }
    const bool encrypt = mode == MessageSecurityMode::SignAndEncrypt;
    return ChannelCrypto{std::make_shared<SymmetricCrypto>(sending, encrypt),
                         std::make_shared<SymmetricCrypto>(receiving, encrypt)};
  }

 private:
  // OPC 10000-7: MinAsymmetricKeyLength 2048, MaxAsymmetricKeyLength 4096 bits.
  [[nodiscard]] Status check_key(EVP_PKEY* key, std::string_view whose) const {
    const std::size_t bits = ossl::rsa_bytes(key) * 8;
    if (bits < spec_.min_key_bits || bits > spec_.max_key_bits) {
      return status_error(status::BadCertificatePolicyCheckFailed,
                          fmt::format("{} key has {} bits; {} needs RSA keys of {} to {} bits", whose, bits,
                                      policy_name(spec_.uri), spec_.min_key_bits, spec_.max_key_bits));
    }
    return {};
  }

  const PolicySpec& spec_;
};

}  // namespace

std::vector<std::string> secure_policy_uris() {
  return {std::string(kAes256Sha256RsaPssUri), std::string(kBasic256Sha256Uri),
          std::string(kAes128Sha256RsaOaepUri)};
}

std::shared_ptr<const SecurityPolicy> make_security_policy(std::string_view uri) {
  if (uri == kSecurityPolicyNoneUri) {
    return std::make_shared<SecurityPolicyNone>();
  }
  const PolicySpec* spec = find_policy_spec(uri);
  return spec == nullptr ? nullptr : std::make_shared<RsaAesPolicy>(*spec);
}

Result<std::shared_ptr<const SecurityPolicyRegistry>> make_registry(const std::vector<std::string>& uris) {
  auto registry = std::make_shared<SecurityPolicyRegistry>();
  registry->add(std::make_shared<SecurityPolicyNone>());
  for (const auto& uri : uris) {
    auto policy = make_security_policy(uri);
    if (!policy) {
      return status_error(status::BadSecurityPolicyRejected,
                          fmt::format("unknown security policy '{}'", uri));
    }
    registry->add(std::move(policy));
  }
  return std::shared_ptr<const SecurityPolicyRegistry>(registry);
}

std::shared_ptr<const SecurityPolicyRegistry> full_registry() {
  static const auto registry = *make_registry(secure_policy_uris());
  return registry;
}

Result<std::string> policy_uri_from_name(std::string_view name) {
  const std::string wanted = lower(name);
  std::vector<std::string> all = secure_policy_uris();
  all.emplace_back(kSecurityPolicyNoneUri);
  for (const auto& uri : all) {
    if (wanted == lower(uri) || wanted == lower(policy_name(uri))) {
      return uri;
    }
  }
  return status_error(
      status::BadSecurityPolicyRejected,
      fmt::format("unknown security policy '{}' (None, Basic256Sha256, Aes128_Sha256_RsaOaep, "
                  "Aes256_Sha256_RsaPss)",
                  name));
}

std::string_view policy_name(std::string_view uri) {
  const auto hash = uri.rfind('#');
  return hash == std::string_view::npos ? uri : uri.substr(hash + 1);
}

int policy_strength(std::string_view uri) {
  const PolicySpec* spec = find_policy_spec(uri);
  return spec == nullptr ? 0 : spec->strength;
}

}  // namespace sf::opcua::security
