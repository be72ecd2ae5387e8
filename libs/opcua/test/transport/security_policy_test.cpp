// The channel code with a policy that signs and encrypts: a toy policy (NOT cryptography: a
// keyed checksum and a reversible XOR with block expansion) that has the shapes of the real
// ones — RSA-like asymmetric blocks (11 → 16 bytes, extra padding byte), AES-like symmetric
// blocks, signatures, nonces, derived keys — so the chunk layout, padding, key derivation and
// certificate checks that the OpenSSL policies plug into are exercised without them.
#include "sf/opcua/transport/security_policy.hpp"

#include <gtest/gtest.h>

#include "channel_harness.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::test {
namespace {

using Kind = ChannelEvent::Kind;
constexpr std::string_view kToyUri = "urn:smartfactory:test:SecurityPolicy#Toy";

Bytes toy_hash(ByteSpan key, ByteSpan data, std::size_t n) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const auto mix = [&h](std::uint8_t b) {
    h ^= b;
    h *= 0x100000001b3ULL;
  };
  for (const auto b : key) {
    mix(b);
  }
  mix(0x5a);
  for (const auto b : data) {
    mix(b);
  }
  Bytes out(n);
  for (std::size_t i = 0; i < n; ++i) {
    mix(static_cast<std::uint8_t>(i));
    out[i] = static_cast<std::uint8_t>(h >> 56U);
  }
  return out;
}

ByteSpan text(std::string_view s) {
  return ByteSpan(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
}

class ToyCrypto final : public MessageCrypto {
 public:
  ToyCrypto(Bytes sign_key, Bytes encrypt_key, std::size_t sig, bool encrypts, std::size_t plain,
            std::size_t cipher, bool extra)
      : sign_key_(std::move(sign_key)),
        encrypt_key_(std::move(encrypt_key)),
        sig_(sig),
        encrypts_(encrypts),
        plain_(plain),
        cipher_(cipher),
        extra_(extra) {}

  [[nodiscard]] std::size_t signature_size() const override { return sig_; }
  [[nodiscard]] bool encrypts() const override { return encrypts_; }
  [[nodiscard]] std::size_t plain_block_size() const override { return encrypts_ ? plain_ : 1; }
  [[nodiscard]] std::size_t cipher_block_size() const override { return encrypts_ ? cipher_ : 1; }
  [[nodiscard]] bool extra_padding_byte() const override { return extra_; }
  Result<Bytes> sign(ByteSpan data) const override { return toy_hash(sign_key_, data, sig_); }
  Status verify(ByteSpan data, ByteSpan signature) const override {
    const Bytes expected = toy_hash(sign_key_, data, sig_);
    if (!std::equal(expected.begin(), expected.end(), signature.begin(), signature.end())) {
      return status_error(status::BadSecurityChecksFailed, "toy signature mismatch");
    }
    return {};
  }
  Result<Bytes> encrypt(ByteSpan plain) const override {
    if (plain.size() % plain_ != 0) {
      return status_error(status::BadInternalError, "not whole blocks");
    }
    const Bytes stream = toy_hash(encrypt_key_, {}, plain_);
    Bytes out;
    for (std::size_t b = 0; b < plain.size(); b += plain_) {
      for (std::size_t i = 0; i < plain_; ++i) {
        out.push_back(static_cast<std::uint8_t>(plain[b + i] ^ stream[i]));
      }
      out.insert(out.end(), cipher_ - plain_, 0xEE);
    }
    return out;
  }
  Result<Bytes> decrypt(ByteSpan cipher) const override {
    if (cipher.size() % cipher_ != 0) {
      return status_error(status::BadSecurityChecksFailed, "not whole blocks");
    }
    const Bytes stream = toy_hash(encrypt_key_, {}, plain_);
    Bytes out;
    for (std::size_t b = 0; b < cipher.size(); b += cipher_) {
      for (std::size_t i = 0; i < plain_; ++i) {
        out.push_back(static_cast<std::uint8_t>(cipher[b + i] ^ stream[i]));
      }
      for (std::size_t i = plain_; i < cipher_; ++i) {
        if (cipher[b + i] != 0xEE) {
          return status_error(status::BadSecurityChecksFailed, "toy block marker");
        }
      }
    }
    return out;
  }

 private:
  Bytes sign_key_;
  Bytes encrypt_key_;
  std::size_t sig_;
  bool encrypts_;
  std::size_t plain_;
  std::size_t cipher_;
  bool extra_;
};

class ToyPolicy final : public SecurityPolicy {
 public:
  [[nodiscard]] std::string_view uri() const override { return kToyUri; }
  [[nodiscard]] bool uses_certificates() const override { return true; }
  [[nodiscard]] std::size_t nonce_length() const override { return 16; }
  [[nodiscard]] std::size_t signing_key_length() const override { return 8; }
  [[nodiscard]] std::size_t encrypting_key_length() const override { return 16; }
  [[nodiscard]] std::size_t encrypting_block_size() const override { return 16; }
  Result<ByteString> create_nonce() const override {
    ++counter_;
    return ByteString(
        toy_hash(text("nonce"), ByteSpan(reinterpret_cast<const std::uint8_t*>(&counter_), 4), 16));
  }
  Result<Bytes> derive(ByteSpan secret, ByteSpan seed, std::size_t length) const override {
    return p_hash([](ByteSpan key, ByteSpan data) { return toy_hash(key, data, 32); }, secret, seed, length);
  }
  Result<ByteString> thumbprint(const ByteString& certificate) const override {
    return ByteString(toy_hash({}, certificate.span(), 20));
  }
  Result<ChannelCrypto> asymmetric(const SecurityCredentials& local, const ByteString& peer) const override {
    // Sign with the own key, encrypt for the peer; receive the other way round.
    auto sending =
        std::make_shared<ToyCrypto>(local.certificate.bytes(), peer.bytes(), 8, true, 11, 16, true);
    auto receiving =
        std::make_shared<ToyCrypto>(peer.bytes(), local.certificate.bytes(), 8, true, 11, 16, true);
    return ChannelCrypto{sending, receiving};
  }
  Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& sending,
                                  const SymmetricKeys& receiving) const override {
    const bool encrypt = mode == MessageSecurityMode::SignAndEncrypt;
    const auto key = [](const SymmetricKeys& k) {
      Bytes b = k.encrypting_key;
      b.insert(b.end(), k.initialization_vector.begin(), k.initialization_vector.end());
      return b;
    };
    return ChannelCrypto{
        std::make_shared<ToyCrypto>(sending.signing_key, key(sending), 4, encrypt, 16, 16, false),
        std::make_shared<ToyCrypto>(receiving.signing_key, key(receiving), 4, encrypt, 16, 16, false)};
  }

 private:
  mutable std::uint32_t counter_ = 0;
};

std::shared_ptr<const SecurityPolicyRegistry> toy_registry() {
  auto r = std::make_shared<SecurityPolicyRegistry>();
  r->add(std::make_shared<SecurityPolicyNone>());
  r->add(std::make_shared<ToyPolicy>());
  return r;
}

SecureChannelConfig toy_server() {
  SecureChannelConfig s = server_config();
  s.policies = toy_registry();
  s.credentials.certificate = ByteString::from_text("server-certificate");
  return s;
}

SecureChannelConfig toy_client(MessageSecurityMode mode) {
  SecureChannelConfig c = client_config();
  c.policies = toy_registry();
  c.security_policy_uri = std::string(kToyUri);
  c.security_mode = mode;
  c.credentials.certificate = ByteString::from_text("client-certificate");
  c.server_certificate = ByteString::from_text("server-certificate");
  return c;
}

bool contains(const Bytes& haystack, std::string_view needle) {
  return std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end()) != haystack.end();
}

TEST(SecurityPolicy, RegistryFindsPoliciesByUri) {
  const auto standard = SecurityPolicyRegistry::standard();
  ASSERT_NE(standard->find(kSecurityPolicyNoneUri), nullptr);
  EXPECT_EQ(standard->uris(), std::vector<std::string>{std::string(kSecurityPolicyNoneUri)});
  auto missing = standard->get(kToyUri);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(status_of(missing.error()), status::BadSecurityPolicyRejected);
  EXPECT_NE(toy_registry()->find(kToyUri), nullptr);
}

TEST(SecurityPolicy, NoneHasNoNoncesAndOnlyModeNone) {
  const SecurityPolicyNone none;
  auto nonce = none.create_nonce();
  ASSERT_TRUE(nonce.ok());
  EXPECT_TRUE(nonce->empty());
  auto crypto = make_symmetric_crypto(none, MessageSecurityMode::None, true, {}, {});
  ASSERT_TRUE(crypto.ok());
  EXPECT_EQ(crypto->sending->signature_size(), 0U);
  EXPECT_FALSE(crypto->sending->encrypts());
  auto sign = none.symmetric(MessageSecurityMode::Sign, {}, {});
  ASSERT_FALSE(sign.ok());
  EXPECT_EQ(status_of(sign.error()), status::BadSecurityModeRejected);
}

TEST(SecurityPolicy, PHashChainsTheHmacAsRfc5246Says) {
  // A "HMAC" that is easy to follow: key bytes then data bytes, cut to 4.
  const HmacFunction hmac = [](ByteSpan key, ByteSpan data) {
    Bytes out(key.begin(), key.end());
    out.insert(out.end(), data.begin(), data.end());
    out.resize(4, 0);
    return out;
  };
  const Bytes secret{1, 2};
  const Bytes seed{9};
  // A(1) = hmac(secret, seed) = 01 02 09 00; block 1 = hmac(secret, A(1) + seed) = 01 02 01 02
  // A(2) = hmac(secret, A(1)) = 01 02 01 02; block 2 = hmac(secret, A(2) + seed) = 01 02 01 02
  EXPECT_EQ(p_hash(hmac, secret, seed, 6), (Bytes{1, 2, 1, 2, 1, 2}));
  EXPECT_EQ(p_hash(hmac, secret, seed, 0), Bytes{});
}

TEST(SecurityPolicy, SymmetricKeysOfBothSidesMatch) {
  const ToyPolicy policy;
  const ByteString client_nonce = *policy.create_nonce();
  const ByteString server_nonce = *policy.create_nonce();
  auto client =
      make_symmetric_crypto(policy, MessageSecurityMode::SignAndEncrypt, true, client_nonce, server_nonce);
  auto server =
      make_symmetric_crypto(policy, MessageSecurityMode::SignAndEncrypt, false, client_nonce, server_nonce);
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(server.ok());
  const Bytes plain(32, 0x42);
  auto cipher = client->sending->encrypt(plain);
  ASSERT_TRUE(cipher.ok());
  EXPECT_NE(*cipher, plain);
  EXPECT_EQ(*server->receiving->decrypt(*cipher), plain);
  EXPECT_TRUE(server->receiving->verify(plain, *client->sending->sign(plain)).ok());
  EXPECT_FALSE(client->receiving->verify(plain, *client->sending->sign(plain)).ok());  // directions differ

  auto bad =
      make_symmetric_crypto(policy, MessageSecurityMode::Sign, true, ByteString(Bytes{1}), server_nonce);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(status_of(bad.error()), status::BadNonceInvalid);
}

TEST(SecurityPolicy, SignAndEncryptChannelCarriesLargeMessagesAndRenews) {
  Harness h(toy_client(MessageSecurityMode::SignAndEncrypt), toy_server());
  h.open();
  EXPECT_EQ(h.server.security_policy_uri(), kToyUri);
  EXPECT_EQ(h.server.security_mode(), MessageSecurityMode::SignAndEncrypt);
  EXPECT_EQ(h.server.peer_certificate(), ByteString::from_text("client-certificate"));
  for (std::size_t size : {0U, 1U, 15U, 16U, 17U, 65'000U, 400'000U}) {
    ReadRequest request = read_request(5);
    request.request_header.audit_entry_id = String("secret-audit-text");
    auto id = h.client.send_request(request);
    ASSERT_TRUE(id.ok());
    const Bytes wire = h.client.take_output();
    EXPECT_FALSE(contains(wire, "secret-audit-text"));  // encrypted on the wire
    for (const auto& [header, chunk] : split_chunks(wire)) {
      EXPECT_LE(header.size, h.client.negotiated_limits().send_chunk_size);
      EXPECT_EQ((chunk.size() - 16) % 16, 0U);
    }
    h.server.receive(wire);
    h.collect();
    ASSERT_NE(last(h.server_events, Kind::ServiceMessage), nullptr);
    EXPECT_EQ(std::get<ReadRequest>(*last(h.server_events, Kind::ServiceMessage)->message), request);
    ASSERT_TRUE(h.server.send_response(*id, read_response(5, size)).ok());
    h.pump();
    ASSERT_NE(last(h.client_events, Kind::ServiceMessage), nullptr) << size;
    EXPECT_EQ(std::get<ReadResponse>(*last(h.client_events, Kind::ServiceMessage)->message),
              read_response(5, size));
  }
  h.clock.advance(std::chrono::seconds{45});
  h.client.on_timer();
  h.pump();
  EXPECT_EQ(h.client.token().token_id, 2U);
  auto id = h.client.send_request(read_request(6));
  ASSERT_TRUE(id.ok());
  h.pump();
  ASSERT_TRUE(h.server.send_response(*id, read_response(6, 100)).ok());
  h.pump();
  EXPECT_TRUE(h.client.is_open());
  EXPECT_TRUE(h.server.is_open());
}

TEST(SecurityPolicy, SignOnlyChannelIsReadableButSigned) {
  Harness h(toy_client(MessageSecurityMode::Sign), toy_server());
  h.open();
  ReadRequest request = read_request(5);
  request.request_header.audit_entry_id = String("visible-audit-text");
  ASSERT_TRUE(h.client.send_request(request).ok());
  Bytes wire = h.client.take_output();
  EXPECT_TRUE(contains(wire, "visible-audit-text"));
  // Tampering breaks the signature: ERR + closed.
  wire[wire.size() - 10] ^= 0x01U;
  EXPECT_EQ(h.server_rejects(wire).error, status::BadSecurityChecksFailed);
}

TEST(SecurityPolicy, WrongServerCertificateIsRejected) {
  SecureChannelConfig c = toy_client(MessageSecurityMode::SignAndEncrypt);
  c.server_certificate = ByteString::from_text("some-other-server");
  Harness h(c, toy_server());
  h.client.start();
  h.pump();
  EXPECT_TRUE(h.server.is_closed());
  EXPECT_EQ(last(h.server_events, Kind::Closed)->status, status::BadCertificateInvalid);
  EXPECT_EQ(last(h.client_events, Kind::Closed)->status, status::BadCertificateInvalid);
}

TEST(SecurityPolicy, CertificateValidatorCanRefuseTheClient) {
  SecureChannelConfig s = toy_server();
  s.validate_certificate = [](const ByteString&) {
    return Status(status_error(status::BadCertificateUntrusted, "not in the trust list"));
  };
  Harness h(toy_client(MessageSecurityMode::Sign), s);
  h.client.start();
  h.pump();
  EXPECT_EQ(last(h.client_events, Kind::Closed)->status, status::BadCertificateUntrusted);
}

TEST(SecurityPolicy, ModeNoneIsRefusedForASigningPolicy) {
  Harness h(toy_client(MessageSecurityMode::None), toy_server());
  h.client.start();
  h.pump();
  EXPECT_EQ(last(h.server_events, Kind::Closed)->status, status::BadSecurityModeRejected);
}

TEST(SecurityPolicy, ServerWithoutThePolicyRejectsIt) {
  Harness h(toy_client(MessageSecurityMode::Sign), server_config());
  h.client.start();
  h.pump();
  EXPECT_EQ(last(h.server_events, Kind::Closed)->status, status::BadSecurityPolicyRejected);
  EXPECT_EQ(last(h.client_events, Kind::Closed)->status, status::BadSecurityPolicyRejected);
}

}  // namespace
}  // namespace sf::opcua::test
