// The client's choice of endpoint (OPC 10000-4 §5.4.4) and its user token over a None channel
// against a server that names its certificate only in the endpoint (§5.6.2, §7.41.2).
#include <gtest/gtest.h>

#include "../security/test_keys.hpp"
#include "fake_server.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/client/client_security.hpp"
#include "sf/opcua/security/policies.hpp"

namespace sf::opcua {
namespace {

using security::test::app_certificate;
using test::FakeServer;

EndpointDescription endpoint(std::string_view policy, MessageSecurityMode mode, std::uint8_t level) {
  EndpointDescription e;
  e.endpoint_url = "opc.tcp://127.0.0.1:4840";
  e.security_policy_uri = std::string(policy);
  e.security_mode = mode;
  e.security_level = level;
  UserTokenPolicy anonymous;
  anonymous.policy_id = "anonymous";
  anonymous.token_type = UserTokenType::Anonymous;
  e.user_identity_tokens.push_back(anonymous);
  return e;
}

// A server that gives every endpoint the same securityLevel (as some do): SignAndEncrypt wins
// over Sign, then the stronger policy, whatever the order of the list.
TEST(SelectEndpoint, TiesGoToTheStrongerModeThenPolicy) {
  using security::kAes128Sha256RsaOaepUri;
  using security::kAes256Sha256RsaPssUri;
  using security::kBasic256Sha256Uri;
  const std::vector<EndpointDescription> same_level = {
      endpoint(kSecurityPolicyNoneUri, MessageSecurityMode::None, 1),
      endpoint(kAes256Sha256RsaPssUri, MessageSecurityMode::Sign, 1),
      endpoint(kAes128Sha256RsaOaepUri, MessageSecurityMode::SignAndEncrypt, 1),
      endpoint(kBasic256Sha256Uri, MessageSecurityMode::Sign, 1),
      endpoint(kBasic256Sha256Uri, MessageSecurityMode::SignAndEncrypt, 1),
  };
  auto any = select_endpoint(same_level, "", MessageSecurityMode::None);
  ASSERT_TRUE(any.ok()) << any.error().message;
  EXPECT_EQ(any->security_mode, MessageSecurityMode::SignAndEncrypt);
  EXPECT_EQ(any->security_policy_uri.view(), kBasic256Sha256Uri);
  auto signing = select_endpoint(same_level, "", MessageSecurityMode::Sign);
  ASSERT_TRUE(signing.ok());
  EXPECT_EQ(signing->security_policy_uri.view(), kAes256Sha256RsaPssUri);

  // The server's securityLevel still comes first.
  const std::vector<EndpointDescription> ranked = {
      endpoint(kAes256Sha256RsaPssUri, MessageSecurityMode::SignAndEncrypt, 5),
      endpoint(kAes128Sha256RsaOaepUri, MessageSecurityMode::Sign, 9),
  };
  auto preferred = select_endpoint(ranked, "", MessageSecurityMode::None);
  ASSERT_TRUE(preferred.ok());
  EXPECT_EQ(preferred->security_policy_uri.view(), kAes128Sha256RsaOaepUri);
}

class PasswordOverNone : public ::testing::Test {
 protected:
  static const SecurityCredentials& server() {
    static const SecurityCredentials c = app_certificate("urn:test:fake-server", "server");
    return c;
  }
  static const SecurityCredentials& client() {
    static const SecurityCredentials c = app_certificate("urn:test:client", "client");
    return c;
  }
  void SetUp() override {
    server_.offer_user_name(server().certificate, std::string(security::kBasic256Sha256Uri));
    ASSERT_TRUE(server_.start());
  }
  ClientConfig config() const {
    ClientConfig c;
    c.endpoint_url = server_.url();
    c.application_uri = "urn:test:client";
    c.request_timeout = std::chrono::seconds(5);
    c.auto_reconnect = false;
    c.security.credentials = client();
    c.user = UserIdentity::user("alice", "wonderland");
    return c;
  }

  FakeServer server_;
};

// The password is encrypted for the endpoint's certificate when CreateSession names none, the
// server certificate is checked first, and our certificate goes into CreateSession.
TEST_F(PasswordOverNone, UsesTheEndpointCertificateWhenCreateSessionNamesNone) {
  std::vector<ByteString> checked;
  ClientConfig c = config();
  c.security.validate_server_certificate = [&checked](const ByteString& certificate) -> Status {
    checked.push_back(certificate);
    return {};
  };
  SyncClient sync(c);
  const Status connected = sync.connect();
  ASSERT_TRUE(connected.ok()) << connected.error().describe();
  ASSERT_EQ(checked.size(), 1U);
  EXPECT_EQ(checked[0], server().certificate);

  const auto created = server_.requests_of<CreateSessionRequest>();
  ASSERT_EQ(created.size(), 1U);
  EXPECT_EQ(created[0].client_certificate, client().certificate);
  const auto activated = server_.requests_of<ActivateSessionRequest>();
  ASSERT_EQ(activated.size(), 1U);
  const auto* token = activated[0].user_identity_token.get_if<UserNameIdentityToken>();
  ASSERT_NE(token, nullptr);
  EXPECT_EQ(token->user_name.view(), "alice");
  EXPECT_EQ(token->encryption_algorithm.view(),
            security::encryption_algorithm_uri(security::kBasic256Sha256Uri));
  auto password = security::decrypt_secret(security::kBasic256Sha256Uri, server().private_key,
                                           token->password.span(), FakeServer::server_nonce().span());
  ASSERT_TRUE(password.ok()) << password.error().message;
  EXPECT_EQ(std::string(password->begin(), password->end()), "wonderland");
}

TEST_F(PasswordOverNone, AnUntrustedServerCertificateGetsNoPassword) {
  ClientConfig c = config();
  c.security.validate_server_certificate = [](const ByteString&) -> Status {
    return status_error(status::BadCertificateUntrusted, "not in trusted/");
  };
  SyncClient sync(c);
  const Status connected = sync.connect();
  ASSERT_FALSE(connected.ok());
  EXPECT_EQ(status_of(connected.error()), status::BadCertificateUntrusted) << connected.error().describe();
  EXPECT_TRUE(server_.requests_of<ActivateSessionRequest>().empty());
}

}  // namespace
}  // namespace sf::opcua
