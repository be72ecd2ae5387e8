#include "sf/opcua/transport/security_policy.hpp"

#include <fmt/format.h>

#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {
namespace {

// No signature, no encryption: SecurityPolicy None, and mode None of any policy.
class PlainCrypto final : public MessageCrypto {
 public:
  [[nodiscard]] std::size_t signature_size() const override { return 0; }
  [[nodiscard]] bool encrypts() const override { return false; }
  [[nodiscard]] std::size_t plain_block_size() const override { return 1; }
  [[nodiscard]] std::size_t cipher_block_size() const override { return 1; }
  [[nodiscard]] bool extra_padding_byte() const override { return false; }
  Result<Bytes> sign(ByteSpan) const override { return Bytes{}; }
  Result<Bytes> encrypt(ByteSpan plain) const override { return Bytes(plain.begin(), plain.end()); }
  Result<Bytes> decrypt(ByteSpan cipher) const override { return Bytes(cipher.begin(), cipher.end()); }
  Status verify(ByteSpan, ByteSpan signature) const override {
    if (!signature.empty()) {
      return status_error(status::BadSecurityChecksFailed, "unexpected signature");
    }
    return {};
  }
};

ChannelCrypto plain_pair() {
  return ChannelCrypto{SecurityPolicyNone::plain(), SecurityPolicyNone::plain()};
}

// Splits PRF output into the three keys (§6.7.5: signing key, encrypting key, IV in that order).
Result<SymmetricKeys> derive_side(const SecurityPolicy& policy, const ByteString& secret,
                                  const ByteString& seed) {
  const std::size_t sign = policy.signing_key_length();
  const std::size_t enc = policy.encrypting_key_length();
  const std::size_t iv = policy.encrypting_block_size();
  SymmetricKeys keys;
  if (sign + enc == 0) {
    return keys;  // None: nothing to derive
  }
  auto material = policy.derive(secret.span(), seed.span(), sign + enc + iv);
  if (!material.ok()) {
    return material.error();
  }
  if (material->size() != sign + enc + iv) {
    return status_error(status::BadInternalError, "key derivation returned the wrong length");
  }
  const auto* p = material->data();
  keys.signing_key.assign(p, p + sign);
  keys.encrypting_key.assign(p + sign, p + sign + enc);
  keys.initialization_vector.assign(p + sign + enc, p + sign + enc + iv);
  return keys;
}

}  // namespace

void encode_binary(Encoder& e, const AsymmetricSecurityHeader& v) {
  encode_binary(e, v.security_policy_uri);
  encode_binary(e, v.sender_certificate);
  encode_binary(e, v.receiver_certificate_thumbprint);
}

void decode_binary(Decoder& d, AsymmetricSecurityHeader& v) {
  decode_binary(d, v.security_policy_uri);
  decode_binary(d, v.sender_certificate);
  decode_binary(d, v.receiver_certificate_thumbprint);
}

Result<ChannelCrypto> make_symmetric_crypto(const SecurityPolicy& policy, MessageSecurityMode mode,
                                            bool is_client, const ByteString& client_nonce,
                                            const ByteString& server_nonce) {
  if (mode == MessageSecurityMode::None) {
    return plain_pair();
  }
  const std::size_t want = policy.nonce_length();
  if (client_nonce.size() != want || server_nonce.size() != want) {
    return status_error(status::BadNonceInvalid,
                        fmt::format("nonces of {} and {} bytes, policy {} needs {}", client_nonce.size(),
                                    server_nonce.size(), policy.uri(), want));
  }
  auto client_keys = derive_side(policy, server_nonce, client_nonce);
  if (!client_keys.ok()) {
    return client_keys.error();
  }
  auto server_keys = derive_side(policy, client_nonce, server_nonce);
  if (!server_keys.ok()) {
    return server_keys.error();
  }
  return is_client ? policy.symmetric(mode, *client_keys, *server_keys)
                   : policy.symmetric(mode, *server_keys, *client_keys);
}

Bytes p_hash(const HmacFunction& hmac, ByteSpan secret, ByteSpan seed, std::size_t length) {
  Bytes out;
  out.reserve(length);
  Bytes a(seed.begin(), seed.end());  // A(0)
  while (out.size() < length) {
    a = hmac(secret, a);  // A(i)
    Bytes input = a;
    input.insert(input.end(), seed.begin(), seed.end());
    const Bytes block = hmac(secret, input);
    if (block.empty()) {
      break;  // a broken HMAC must not loop forever
    }
    const std::size_t take = std::min(block.size(), length - out.size());
    out.insert(out.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(take));
  }
  return out;
}

Result<ByteString> SecurityPolicyNone::create_nonce() const {
  return ByteString(Bytes{});
}

Result<Bytes> SecurityPolicyNone::derive(ByteSpan, ByteSpan, std::size_t length) const {
  if (length != 0) {
    return status_error(status::BadSecurityPolicyRejected, "SecurityPolicy None derives no keys");
  }
  return Bytes{};
}

Result<ByteString> SecurityPolicyNone::thumbprint(const ByteString&) const {
  return ByteString{};
}

Result<ChannelCrypto> SecurityPolicyNone::asymmetric(const SecurityCredentials&, const ByteString&) const {
  return plain_pair();
}

Result<ChannelCrypto> SecurityPolicyNone::symmetric(MessageSecurityMode mode, const SymmetricKeys&,
                                                    const SymmetricKeys&) const {
  if (mode != MessageSecurityMode::None) {
    return status_error(status::BadSecurityModeRejected,
                        fmt::format("SecurityPolicy None allows mode None only, not {}", to_string(mode)));
  }
  return plain_pair();
}

std::shared_ptr<const MessageCrypto> SecurityPolicyNone::plain() {
  static const auto crypto = std::make_shared<const PlainCrypto>();
  return crypto;
}

std::shared_ptr<const SecurityPolicyRegistry> SecurityPolicyRegistry::standard() {
  static const auto registry = [] {
    auto r = std::make_shared<SecurityPolicyRegistry>();
    r->add(std::make_shared<SecurityPolicyNone>());
    return std::shared_ptr<const SecurityPolicyRegistry>(r);
  }();
  return registry;
}

void SecurityPolicyRegistry::add(std::shared_ptr<const SecurityPolicy> policy) {
  std::string uri(policy->uri());
  policies_[uri] = std::move(policy);
}

std::shared_ptr<const SecurityPolicy> SecurityPolicyRegistry::find(std::string_view uri) const {
  const auto it = policies_.find(uri);
  return it == policies_.end() ? nullptr : it->second;
}

Result<std::shared_ptr<const SecurityPolicy>> SecurityPolicyRegistry::get(std::string_view uri) const {
  auto policy = find(uri);
  if (!policy) {
    return status_error(status::BadSecurityPolicyRejected,
                        fmt::format("security policy '{}' is not supported", uri));
  }
  return policy;
}

std::vector<std::string> SecurityPolicyRegistry::uris() const {
  std::vector<std::string> out;
  out.reserve(policies_.size());
  for (const auto& [uri, policy] : policies_) {
    out.push_back(uri);
  }
  return out;
}

}  // namespace sf::opcua
