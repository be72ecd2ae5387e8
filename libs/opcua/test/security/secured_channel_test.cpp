// A client and a server SecureChannel with the real OpenSSL policies: every policy in Sign and
// SignAndEncrypt carries messages of many sizes and renews its token; and what an attacker may
// send is refused with an ERR and a closed channel, never a crash (OPC 10000-6 §6.7.2): tampered
// signatures and ciphertext, replayed and out-of-order sequence numbers, bad padding under a
// valid signature, an OPN encrypted for another key; each refusal is logged.
#include <gtest/gtest.h>

#include <algorithm>

#include "../log_capture.hpp"
#include "../transport/channel_harness.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/status_codes.hpp"
#include "test_keys.hpp"

namespace sf::opcua::security::test {
namespace {

using opcua::test::Harness;
using Kind = ChannelEvent::Kind;

const SecurityCredentials& server_credentials() {
  static const SecurityCredentials c = app_certificate("urn:test:server", "server");
  return c;
}
const SecurityCredentials& client_credentials() {
  static const SecurityCredentials c = app_certificate("urn:test:client", "client");
  return c;
}

SecureChannelConfig secured_server(std::shared_ptr<const SecurityPolicyRegistry> policies = full_registry()) {
  SecureChannelConfig s = opcua::test::server_config();
  s.policies = std::move(policies);
  s.credentials = server_credentials();
  return s;
}

SecureChannelConfig secured_client(std::string_view policy, MessageSecurityMode mode,
                                   std::shared_ptr<const SecurityPolicyRegistry> policies = full_registry()) {
  SecureChannelConfig c = opcua::test::client_config();
  c.policies = std::move(policies);
  c.security_policy_uri = std::string(policy);
  c.security_mode = mode;
  c.credentials = client_credentials();
  c.server_certificate = server_credentials().certificate;
  return c;
}

bool contains(const Bytes& haystack, std::string_view needle) {
  return std::search(haystack.begin(), haystack.end(), needle.begin(), needle.end()) != haystack.end();
}

// The server refuses `wire` with an ERR and closes the channel (Harness::server_rejects) and
// logs a warning with the status.
ErrorMessage refused_and_logged(Harness& h, ByteSpan wire) {
  const opcua::test::LogCapture log;
  ErrorMessage err = h.server_rejects(wire);
  EXPECT_TRUE(log.warned(to_string(err.error))) << to_string(err.error) << " was not logged";
  return err;
}

struct Case {
  std::string policy;
  MessageSecurityMode mode;
};

class SecuredChannel : public ::testing::TestWithParam<Case> {};

TEST_P(SecuredChannel, CarriesMessagesOfEverySizeAndRenews) {
  const Case& c = GetParam();
  Harness h(secured_client(c.policy, c.mode), secured_server());
  h.open();
  EXPECT_EQ(h.server.security_policy_uri(), c.policy);
  EXPECT_EQ(h.server.security_mode(), c.mode);
  EXPECT_EQ(h.server.peer_certificate(), client_credentials().certificate);
  const bool encrypt = c.mode == MessageSecurityMode::SignAndEncrypt;
  for (std::size_t size : {0U, 1U, 15U, 16U, 17U, 65'000U, 300'000U}) {
    ReadRequest request = opcua::test::read_request(5);
    request.request_header.audit_entry_id = String("audit-text-on-the-wire");
    auto id = h.client.send_request(request);
    ASSERT_TRUE(id.ok());
    const Bytes wire = h.client.take_output();
    EXPECT_EQ(contains(wire, "audit-text-on-the-wire"), !encrypt);
    h.server.receive(wire);
    h.collect();
    const ChannelEvent* got = opcua::test::last(h.server_events, Kind::ServiceMessage);
    ASSERT_NE(got, nullptr) << size;
    EXPECT_EQ(std::get<ReadRequest>(*got->message), request);
    ASSERT_TRUE(h.server.send_response(*id, opcua::test::read_response(5, size)).ok());
    h.pump();
    const ChannelEvent* answer = opcua::test::last(h.client_events, Kind::ServiceMessage);
    ASSERT_NE(answer, nullptr) << size;
    EXPECT_EQ(std::get<ReadResponse>(*answer->message), opcua::test::read_response(5, size));
  }
  h.clock.advance(std::chrono::seconds{45});
  h.client.on_timer();
  h.pump();
  EXPECT_EQ(h.client.token().token_id, 2U);
  auto id = h.client.send_request(opcua::test::read_request(6));
  ASSERT_TRUE(id.ok());
  h.pump();
  ASSERT_TRUE(h.server.send_response(*id, opcua::test::read_response(6, 100)).ok());
  h.pump();
  EXPECT_TRUE(h.client.is_open() && h.server.is_open());
}

TEST_P(SecuredChannel, TamperedChunksAreRefused) {
  const Case& c = GetParam();
  Harness h(secured_client(c.policy, c.mode), secured_server());
  h.open();
  ASSERT_TRUE(h.client.send_request(opcua::test::read_request(1)).ok());
  Bytes wire = h.client.take_output();
  wire[wire.size() / 2] ^= 0x01U;  // in the body (plain or encrypted): the signature no longer fits
  EXPECT_EQ(refused_and_logged(h, wire).error, status::BadSecurityChecksFailed);
}

TEST_P(SecuredChannel, TamperedSignaturesAreRefused) {
  const Case& c = GetParam();
  Harness h(secured_client(c.policy, c.mode), secured_server());
  h.open();
  ASSERT_TRUE(h.client.send_request(opcua::test::read_request(1)).ok());
  Bytes wire = h.client.take_output();
  wire[wire.size() - 1] ^= 0x80U;  // the last signature byte (or the last cipher block)
  EXPECT_EQ(refused_and_logged(h, wire).error, status::BadSecurityChecksFailed);
}

TEST_P(SecuredChannel, ReplayedChunksAreRefused) {
  const Case& c = GetParam();
  Harness h(secured_client(c.policy, c.mode), secured_server());
  h.open();
  ASSERT_TRUE(h.client.send_request(opcua::test::read_request(1)).ok());
  const Bytes first = h.client.take_output();
  h.server.receive(first);
  h.collect();
  ASSERT_EQ(opcua::test::count(h.server_events, Kind::ServiceMessage), 1U);
  // The same, correctly signed chunk again: its sequence number was used (§6.7.2.4).
  EXPECT_EQ(refused_and_logged(h, first).error, status::BadSequenceNumberInvalid);
  EXPECT_EQ(opcua::test::count(h.server_events, Kind::ServiceMessage), 1U);
}

TEST_P(SecuredChannel, OutOfOrderChunksAreRefused) {
  const Case& c = GetParam();
  Harness h(secured_client(c.policy, c.mode), secured_server());
  h.open();
  ASSERT_TRUE(h.client.send_request(opcua::test::read_request(1)).ok());
  const Bytes first = h.client.take_output();
  ASSERT_TRUE(h.client.send_request(opcua::test::read_request(2)).ok());
  const Bytes second = h.client.take_output();
  EXPECT_EQ(refused_and_logged(h, second).error, status::BadSequenceNumberInvalid);
  EXPECT_EQ(opcua::test::count(h.server_events, Kind::ServiceMessage), 0U);
  (void)first;
}

TEST_P(SecuredChannel, OpenEncryptedForAnotherServerIsRefused) {
  const Case& c = GetParam();
  SecureChannelConfig client = secured_client(c.policy, c.mode);
  const SecurityCredentials other = app_certificate("urn:test:other", "other");
  client.server_certificate = other.certificate;  // thumbprint and encryption key are another's
  Harness h(client, secured_server());
  h.client.start();
  h.pump();
  EXPECT_TRUE(h.server.is_closed());
  EXPECT_EQ(opcua::test::last(h.server_events, Kind::Closed)->status, status::BadCertificateInvalid);
}

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (const auto& uri : secure_policy_uris()) {
    out.push_back({uri, MessageSecurityMode::Sign});
    out.push_back({uri, MessageSecurityMode::SignAndEncrypt});
  }
  return out;
}

INSTANTIATE_TEST_SUITE_P(PoliciesAndModes, SecuredChannel, ::testing::ValuesIn(all_cases()),
                         [](const auto& p) {
                           return std::string(policy_name(p.param.policy)) +
                                  (p.param.mode == MessageSecurityMode::Sign ? "_Sign" : "_SignAndEncrypt");
                         });

// Wraps the client's sending crypto: while armed, `value` is added to the padding's last byte before the
// chunk is signed and encrypted, so the signature is valid and only the padding check can
// notice (OPC 10000-6 §6.7.2.5). What the receiver says must not depend on the padding's value:
// signature first, then padding, one status for both (no padding oracle).
class BadPaddingCrypto final : public MessageCrypto {
 public:
  BadPaddingCrypto(std::shared_ptr<const MessageCrypto> inner, std::shared_ptr<int> armed, std::uint8_t value)
      : inner_(std::move(inner)), armed_(std::move(armed)), value_(value) {}
  [[nodiscard]] std::size_t signature_size() const override { return inner_->signature_size(); }
  [[nodiscard]] bool encrypts() const override { return inner_->encrypts(); }
  [[nodiscard]] std::size_t plain_block_size() const override { return inner_->plain_block_size(); }
  [[nodiscard]] std::size_t cipher_block_size() const override { return inner_->cipher_block_size(); }
  [[nodiscard]] bool extra_padding_byte() const override { return inner_->extra_padding_byte(); }
  Result<Bytes> sign(ByteSpan data) const override {
    Bytes copy(data.begin(), data.end());
    if (*armed_ != 0) {
      copy.back() = static_cast<std::uint8_t>(copy.back() + value_);
    }
    return inner_->sign(copy);
  }
  Result<Bytes> encrypt(ByteSpan plain) const override {
    Bytes copy(plain.begin(), plain.end());
    if (*armed_ != 0) {
      auto& last = copy[copy.size() - signature_size() - 1];
      last = static_cast<std::uint8_t>(last + value_);
      *armed_ = 0;
    }
    return inner_->encrypt(copy);
  }
  Result<Bytes> decrypt(ByteSpan cipher) const override { return inner_->decrypt(cipher); }
  Status verify(ByteSpan data, ByteSpan signature) const override { return inner_->verify(data, signature); }

 private:
  std::shared_ptr<const MessageCrypto> inner_;
  std::shared_ptr<int> armed_;
  std::uint8_t value_;
};

class BadPaddingPolicy final : public ForwardingSecurityPolicy {
 public:
  BadPaddingPolicy(std::shared_ptr<const SecurityPolicy> inner, std::shared_ptr<int> armed,
                   std::uint8_t value)
      : ForwardingSecurityPolicy(std::move(inner)), armed_(std::move(armed)), value_(value) {}
  Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& s,
                                  const SymmetricKeys& r) const override {
    auto crypto = ForwardingSecurityPolicy::symmetric(mode, s, r);
    if (crypto.ok()) {
      crypto->sending = std::make_shared<BadPaddingCrypto>(crypto->sending, armed_, value_);
    }
    return crypto;
  }

 private:
  std::shared_ptr<int> armed_;
  std::uint8_t value_;
};

class BadPadding : public ::testing::TestWithParam<std::uint8_t> {};

TEST_P(BadPadding, UnderAValidSignatureIsRefused) {
  for (const auto& uri : secure_policy_uris()) {
    auto armed = std::make_shared<int>(0);
    auto registry = std::make_shared<SecurityPolicyRegistry>();
    registry->add(std::make_shared<BadPaddingPolicy>(make_security_policy(uri), armed, GetParam()));
    Harness h(secured_client(uri, MessageSecurityMode::SignAndEncrypt, registry), secured_server());
    h.open();
    // A good message first: the decorator changes nothing while disarmed.
    auto good = h.client.send_request(opcua::test::read_request(1));
    ASSERT_TRUE(good.ok());
    h.pump();
    ASSERT_EQ(opcua::test::count(h.server_events, Kind::ServiceMessage), 1U) << uri;
    *armed = 1;
    ASSERT_TRUE(h.client.send_request(opcua::test::read_request(2)).ok());
    const auto err = refused_and_logged(h, h.client.take_output());
    EXPECT_EQ(err.error, status::BadSecurityChecksFailed) << uri;
    EXPECT_NE(err.reason.find("padding"), std::string::npos) << err.reason;
    EXPECT_EQ(opcua::test::count(h.server_events, Kind::ServiceMessage), 1U);
  }
}

// The padding size claims one byte more, one less, or far more than the padding bytes carry.
INSTANTIATE_TEST_SUITE_P(Deltas, BadPadding, ::testing::Values(0x01, 0xFF, 0x80));

}  // namespace
}  // namespace sf::opcua::security::test
