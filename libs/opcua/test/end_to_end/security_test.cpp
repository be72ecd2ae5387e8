// Our client against our server over loopback with security (OPC 10000-2 §4): every policy in Sign and
// SignAndEncrypt with anonymous, user name and certificate logins; wrong passwords, untrusted
// client certificates (refused, then trusted from rejected/ without a restart), roles (a viewer
// cannot write or call; a user who may not read a node cannot monitor it), endpoints that are not
// offered, and a server whose certificate the client does not trust.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "../security/test_keys.hpp"
#include "sf/examples/opcua_demo.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/server/server.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {
namespace {

using security::test::app_certificate;
using security::test::TempDir;
namespace fs = std::filesystem;

constexpr std::string_view kServerUri = "urn:smartfactory:test:secure-server";
constexpr std::string_view kClientUri = "urn:smartfactory:test:secure-client";
const security::PasswordHashParams kFastHash{10, 8, 1};

const SecurityCredentials& server_credentials() {
  static const SecurityCredentials c = app_certificate(std::string(kServerUri), "server");
  return c;
}
const SecurityCredentials& client_credentials() {
  static const SecurityCredentials c = app_certificate(std::string(kClientUri), "client");
  return c;
}
const SecurityCredentials& robot_credentials() {
  static const SecurityCredentials c = app_certificate("urn:smartfactory:test:robot", "robot");
  return c;
}

std::shared_ptr<security::UserDatabase> users() {
  // A role of the users file's own: everything but the temperature may be read.
  auto parsed = security::UserDatabase::parse(
      "roles:\n"
      "  no-temperature:\n"
      "    read: ['!nsu=urn:smartfactory:demo;s=Demo.Temperature', '*']\n");
  EXPECT_TRUE(parsed.ok());
  auto db =
      std::make_shared<security::UserDatabase>(parsed.ok() ? *std::move(parsed) : security::UserDatabase());
  EXPECT_TRUE(db->put({"alice", *security::hash_password("wonderland", kFastHash), "", {"operator"}}).ok());
  EXPECT_TRUE(db->put({"victor", *security::hash_password("viewer-pass", kFastHash), "", {"viewer"}}).ok());
  EXPECT_TRUE(
      db->put({"nora", *security::hash_password("nora-pass", kFastHash), "", {"no-temperature"}}).ok());
  const auto robot = security::inspect_certificate(robot_credentials().certificate.span());
  EXPECT_TRUE(db->put({"robot", "", robot->thumbprint, {"engineer"}}).ok());
  return db;
}

class SecureEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    server_pki_ = std::make_unique<security::PkiStore>(dir_.path() / "server-pki");
    client_pki_ = std::make_unique<security::PkiStore>(dir_.path() / "client-pki");
    ASSERT_TRUE(server_pki_->create_folders().ok());
    ASSERT_TRUE(client_pki_->create_folders().ok());
  }

  void start(std::vector<server::EndpointSecurity> endpoints) {
    server::ServerConfig config;
    config.identity.application_uri = std::string(kServerUri);
    config.transport.host = "127.0.0.1";
    config.transport.port = 0;
    config.advertised_host = "127.0.0.1";
    config.security.endpoints = std::move(endpoints);
    config.security.credentials = server_credentials();
    config.security.validator = std::make_shared<security::CertificateValidator>(*server_pki_);
    config.security.users = users();
    config.security.anonymous_role = "viewer";
    server_ = std::make_unique<server::Server>(config);
    ASSERT_TRUE(examples::add_demo_model(*server_).ok());
    ASSERT_TRUE(server_->start().ok());
  }
  void start_all() {
    start(server::ServerSecurity::endpoints_for(
        security::secure_policy_uris(), {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}));
  }
  // Both sides trust each other (what `opcua pki trust` or copying files does).
  void trust_both() {
    ASSERT_TRUE(server_pki_->add(security::PkiStore::Folder::Trusted, client_credentials().certificate).ok());
    ASSERT_TRUE(client_pki_->add(security::PkiStore::Folder::Trusted, server_credentials().certificate).ok());
  }

  ClientConfig client(std::string_view policy, MessageSecurityMode mode, UserIdentity user = {}) {
    ClientConfig config;
    config.endpoint_url = "opc.tcp://127.0.0.1:" + std::to_string(server_->port());
    config.application_uri = std::string(kClientUri);
    config.auto_reconnect = false;
    config.request_timeout = std::chrono::seconds(10);
    config.security.policy_uri = std::string(policy);
    config.security.mode = mode;
    config.security.credentials = client_credentials();
    auto validator = std::make_shared<security::CertificateValidator>(*client_pki_);
    config.security.validate_server_certificate = [validator](const ByteString& c) {
      return validator->validate(c);
    };
    config.user = std::move(user);
    return config;
  }

  NodeId demo(SyncClient& c, const char* name) {
    auto ns = c.namespace_index(examples::kDemoNamespaceUri);
    EXPECT_TRUE(ns.ok());
    return NodeId(ns.ok() ? *ns : 0, String(name));
  }

  TempDir dir_;
  std::unique_ptr<security::PkiStore> server_pki_;
  std::unique_ptr<security::PkiStore> client_pki_;
  std::unique_ptr<server::Server> server_;
};

TEST_F(SecureEndToEnd, EveryPolicyAndModeWithAnonymousUserNameAndCertificateLogins) {
  start_all();
  trust_both();
  for (const auto& policy : security::secure_policy_uris()) {
    for (const auto mode : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
      SCOPED_TRACE(std::string(security::policy_name(policy)) + " " + std::string(to_string(mode)));
      {
        SyncClient anonymous(client(policy, mode));
        ASSERT_TRUE(anonymous.connect().ok());
        auto temperature = anonymous.read_value(demo(anonymous, "Demo.Temperature"));
        ASSERT_TRUE(temperature.ok());
        EXPECT_TRUE(temperature->value.get_if<double>() != nullptr);
      }
      {
        SyncClient alice(client(policy, mode, UserIdentity::user("alice", "wonderland")));
        ASSERT_TRUE(alice.connect().ok());
        const NodeId counter = demo(alice, "Demo.Counter");
        ASSERT_TRUE(alice.write_value(counter, Variant(std::int32_t{4242})).ok());
        EXPECT_EQ(alice.read_value(counter)->value, Variant(std::int32_t{4242}));
        auto product = alice.call_method(demo(alice, "Demo"), demo(alice, "Demo.Multiply"),
                                         {Variant(6.0), Variant(7.0)});
        ASSERT_TRUE(product.ok());
        EXPECT_EQ(product->at(0), Variant(42.0));
      }
      {
        SyncClient robot(client(policy, mode, UserIdentity::x509(robot_credentials())));
        ASSERT_TRUE(robot.connect().ok());
        EXPECT_TRUE(robot.write_value(demo(robot, "Demo.Counter"), Variant(std::int32_t{7})).ok());
      }
    }
  }
  EXPECT_EQ(server_pki_->certificates().size(), 1U);  // the trusted client; nothing rejected
}

TEST_F(SecureEndToEnd, WrongPasswordIsBadUserAccessDenied) {
  start_all();
  trust_both();
  SyncClient mallory(client(security::kBasic256Sha256Uri, MessageSecurityMode::SignAndEncrypt,
                            UserIdentity::user("alice", "not-wonderland")));
  auto st = mallory.connect();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadUserAccessDenied);
  SyncClient nobody(client(security::kBasic256Sha256Uri, MessageSecurityMode::SignAndEncrypt,
                           UserIdentity::user("nobody", "wonderland")));
  st = nobody.connect();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadUserAccessDenied);
}

TEST_F(SecureEndToEnd, UntrustedClientIsRejectedThenTrustedWithoutRestart) {
  start_all();
  ASSERT_TRUE(client_pki_->add(security::PkiStore::Folder::Trusted, server_credentials().certificate).ok());
  SyncClient first(client(security::kAes256Sha256RsaPssUri, MessageSecurityMode::SignAndEncrypt));
  auto st = first.connect();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadSecurityChecksFailed);
  const auto rejected = server_pki_->certificates();
  ASSERT_EQ(rejected.size(), 1U);
  EXPECT_EQ(rejected[0].folder, security::PkiStore::Folder::Rejected);
  EXPECT_EQ(rejected[0].info.application_uri, kClientUri);
  // The operator moves it to trusted/ (`smartfactory opcua pki trust <thumbprint>`).
  ASSERT_TRUE(server_pki_
                  ->move(rejected[0].info.thumbprint, security::PkiStore::Folder::Rejected,
                         security::PkiStore::Folder::Trusted)
                  .ok());
  SyncClient again(client(security::kAes256Sha256RsaPssUri, MessageSecurityMode::SignAndEncrypt));
  EXPECT_TRUE(again.connect().ok());
}

TEST_F(SecureEndToEnd, ClientRefusesAnUntrustedServer) {
  start_all();
  ASSERT_TRUE(server_pki_->add(security::PkiStore::Folder::Trusted, client_credentials().certificate).ok());
  SyncClient c(client(security::kBasic256Sha256Uri, MessageSecurityMode::Sign));
  auto st = c.connect();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadCertificateUntrusted);
  EXPECT_EQ(client_pki_->certificates().size(), 1U);  // the server's, in the client's rejected/
}

TEST_F(SecureEndToEnd, ViewerCannotWriteOrCall) {
  start_all();
  trust_both();
  for (auto user : {UserIdentity::user("victor", "viewer-pass"), UserIdentity::anonymous()}) {
    SyncClient viewer(client(security::kBasic256Sha256Uri, MessageSecurityMode::SignAndEncrypt, user));
    ASSERT_TRUE(viewer.connect().ok());
    const NodeId counter = demo(viewer, "Demo.Counter");
    EXPECT_TRUE(viewer.read_value(counter).ok());
    auto written = viewer.write_value(counter, Variant(std::int32_t{1}));
    ASSERT_FALSE(written.ok());
    EXPECT_EQ(status_of(written.error()), status::BadUserAccessDenied);
    auto called =
        viewer.call_method(demo(viewer, "Demo"), demo(viewer, "Demo.Multiply"), {Variant(1.0), Variant(2.0)});
    ASSERT_FALSE(called.ok());
    EXPECT_EQ(status_of(called.error()), status::BadUserAccessDenied);
    // UserAccessLevel says so too (OPC 10000-3 §5.6.2).
    auto level = viewer.read({ReadValueId{counter, 18, String(), QualifiedName()}});
    ASSERT_TRUE(level.ok());
    EXPECT_EQ(level->at(0).value, Variant(std::uint8_t{1}));  // CurrentRead only
  }
}

TEST_F(SecureEndToEnd, MonitoringNeedsReadPermission) {
  start_all();
  trust_both();
  SyncClient nora(client(security::kBasic256Sha256Uri, MessageSecurityMode::SignAndEncrypt,
                         UserIdentity::user("nora", "nora-pass")));
  ASSERT_TRUE(nora.connect().ok());
  const NodeId temperature = demo(nora, "Demo.Temperature");
  auto read = nora.read_value(temperature);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(status_of(read.error()), status::BadUserAccessDenied);
  auto subscription = nora.create_subscription({});
  ASSERT_TRUE(subscription.ok());
  // CreateMonitoredItems (OPC 10000-4 §5.12.2) creates no item the user may not read.
  auto denied = nora.monitor_value(*subscription, value_of(temperature), {}, [](const DataValue&) {});
  ASSERT_FALSE(denied.ok());
  EXPECT_EQ(status_of(denied.error()), status::BadUserAccessDenied);
  EXPECT_TRUE(
      nora.monitor_value(*subscription, value_of(demo(nora, "Demo.Counter")), {}, [](const DataValue&) {})
          .ok());
}

TEST_F(SecureEndToEnd, OnlyOfferedEndpointsGetSessions) {
  start({{std::string(security::kBasic256Sha256Uri), MessageSecurityMode::SignAndEncrypt}});
  trust_both();
  // The None channel is for GetEndpoints only.
  ClientConfig none = client(kSecurityPolicyNoneUri, MessageSecurityMode::None);
  SyncClient plain(none);
  auto st = plain.connect();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadSecurityPolicyRejected);
  auto endpoints = plain.get_endpoints();
  ASSERT_TRUE(endpoints.ok());
  ASSERT_EQ(endpoints->size(), 1U);
  EXPECT_EQ(endpoints->at(0).security_mode, MessageSecurityMode::SignAndEncrypt);
  EXPECT_EQ(endpoints->at(0).server_certificate, server_credentials().certificate);
  // A mode the server does not offer.
  SyncClient sign(client(security::kBasic256Sha256Uri, MessageSecurityMode::Sign));
  st = sign.connect();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadSecurityPolicyRejected);  // no such endpoint
  // "auto": the most secure endpoint the server has.
  SyncClient best(client("", MessageSecurityMode::None));
  EXPECT_TRUE(best.connect().ok());
}

}  // namespace
}  // namespace sf::opcua
