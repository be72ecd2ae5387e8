// Security from settings as a user writes them (the opcua commands, the cloud's configuration):
// modes and policies by name, a PKI folder made with its own certificate on first use, endpoints,
// anonymous access and the client's endpoint choice.
#include <gtest/gtest.h>

#include <filesystem>

#include "sf/opcua/client/security_setup.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/security/provisioning.hpp"
#include "sf/opcua/server/security_setup.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::opcua {
namespace {

using security::kBasic256Sha256Uri;

TEST(SecurityNames, ModesAndPoliciesByName) {
  EXPECT_EQ(security::parse_security_mode("SignAndEncrypt").value(), MessageSecurityMode::SignAndEncrypt);
  EXPECT_EQ(
      security::parse_security_modes("sign, encrypt,sign").value(),
      (std::vector<MessageSecurityMode>{MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}));
  EXPECT_FALSE(security::parse_security_modes("").ok());
  EXPECT_FALSE(security::parse_security_modes("none,secret").ok());
  EXPECT_EQ(security::parse_security_policies("Basic256Sha256").value(),
            (std::vector<std::string>{std::string(kBasic256Sha256Uri)}));
  const auto none = security::parse_security_policies("None");
  ASSERT_FALSE(none.ok());  // None is a mode, not a policy of secured endpoints
  EXPECT_NE(none.error().message.find("unknown security policy"), std::string::npos);
}

TEST(SecurityNames, OwnCertificateNamesThisHostAndTheAdvertisedOne) {
  const auto request = security::own_certificate_request("10.1.2.3");
  EXPECT_TRUE(request.application_uri.starts_with("urn:"));
  EXPECT_NE(std::find(request.ip_addresses.begin(), request.ip_addresses.end(), "10.1.2.3"),
            request.ip_addresses.end());
  const auto named = security::own_certificate_request("plc7.example");
  EXPECT_NE(std::find(named.dns_names.begin(), named.dns_names.end(), "plc7.example"), named.dns_names.end());
}

TEST(ServerSecuritySetup, SecuredEndpointsWithAnOwnCertificateMadeOnFirstUse) {
  testing::TempDir dir;
  server::ServerSecuritySettings settings;
  settings.pki = (dir.path() / "pki").string();
  settings.policies = "Basic256Sha256";
  server::ServerConfig config;
  const auto applied = server::configure_server_security(settings, false, config);
  ASSERT_TRUE(applied.ok()) << applied.error().describe();
  EXPECT_TRUE(config.security.offers(kBasic256Sha256Uri, MessageSecurityMode::Sign));
  EXPECT_TRUE(config.security.offers(kBasic256Sha256Uri, MessageSecurityMode::SignAndEncrypt));
  EXPECT_FALSE(config.security.offers(kSecurityPolicyNoneUri, MessageSecurityMode::None));
  EXPECT_FALSE(config.security.credentials.certificate.empty());
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "pki" / "own" / "certs" / "cert.der"));
  EXPECT_TRUE(config.security.allow_anonymous);
  EXPECT_EQ(config.security.anonymous_role, "viewer");
  EXPECT_TRUE(config.identity.application_uri.starts_with("urn:"));
}

TEST(ServerSecuritySetup, NoneAloneNeedsNoPkiAndAnUnknownAnonymousRoleIsRefused) {
  testing::TempDir dir;
  server::ServerSecuritySettings settings;
  settings.pki = (dir.path() / "pki").string();
  settings.modes = "none";
  server::ServerConfig config;
  ASSERT_TRUE(server::configure_server_security(settings, true, config).ok());
  EXPECT_EQ(config.security.anonymous_role, "operator");  // the demo's anonymous users may write
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "pki"));
  settings.anonymous = "root";
  EXPECT_FALSE(server::configure_server_security(settings, false, config).ok());
}

TEST(ClientSecuritySetup, NoneAutoOrAPolicyAndMode) {
  testing::TempDir dir;
  ClientSecuritySettings settings;
  settings.pki = (dir.path() / "pki").string();
  settings.security = "none";
  ClientConfig config;
  ASSERT_TRUE(configure_client_security(settings, config).ok());
  EXPECT_EQ(config.security.policy_uri, kSecurityPolicyNoneUri);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "pki"));

  settings.security = "basic256sha256:sign";
  settings.user = "alice";
  settings.password = "secret";
  ASSERT_TRUE(configure_client_security(settings, config).ok());
  EXPECT_EQ(config.security.policy_uri, kBasic256Sha256Uri);
  EXPECT_EQ(config.security.mode, MessageSecurityMode::Sign);
  EXPECT_FALSE(config.security.credentials.certificate.empty());
  EXPECT_TRUE(config.security.validate_server_certificate != nullptr);

  settings.security = "auto";
  ASSERT_TRUE(configure_client_security(settings, config).ok());
  EXPECT_TRUE(config.security.policy_uri.empty());  // asks the server (GetEndpoints)

  settings.security = "Rot13:Sign";
  EXPECT_FALSE(configure_client_security(settings, config).ok());
}

}  // namespace
}  // namespace sf::opcua
