// The PKI folder and certificate validation (OPC 10000-4 §6.1.3): the own certificate, trust
// lists, rejected/, validity, URI, key usage, chains through issuers/ and CRLs; refusals are logged.
#include "sf/opcua/security/pki.hpp"

#include <gtest/gtest.h>

#include "../log_capture.hpp"
#include "sf/opcua/status_codes.hpp"
#include "test_keys.hpp"

namespace sf::opcua::security::test {
namespace {

namespace fs = std::filesystem;
using Folder = PkiStore::Folder;
using std::chrono::hours;

class PkiTest : public ::testing::Test {
 protected:
  PkiTest()
      : store_(dir_.path() / "pki"), clock_(std::chrono::system_clock::now()), validator_(store_, clock_) {
    EXPECT_TRUE(store_.create_folders().ok());
  }

  StatusCode validate(const ByteString& certificate) {
    auto st = validator_.validate(certificate);
    return st.ok() ? StatusCode{} : status_of(st.error());
  }
  std::size_t files_in(const fs::path& folder) {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(folder), fs::directory_iterator()));
  }
  void trust(const ByteString& certificate) { ASSERT_TRUE(store_.add(Folder::Trusted, certificate).ok()); }
  void add_issuer(const ByteString& certificate) {
    ASSERT_TRUE(store_.add(Folder::Issuers, certificate).ok());
  }

  TempDir dir_;
  PkiStore store_;
  ManualClock clock_;
  CertificateValidator validator_;
};

TEST_F(PkiTest, CreatesTheOwnCertificateOnceAndTrustsIt) {
  CertificateRequest request;
  request.application_uri = "urn:host:smartfactory";
  request.common_name = "smartfactory@host";
  request.dns_names = {"host", "localhost"};
  request.ip_addresses = {"127.0.0.1", "::1"};
  request.private_key = test_key("server");
  ASSERT_FALSE(store_.has_own());
  auto own = store_.ensure_own(request);
  ASSERT_TRUE(own.ok()) << own.error().message;
  EXPECT_TRUE(store_.has_own());
  EXPECT_EQ((fs::status(store_.own_private_key()).permissions() & fs::perms::group_read), fs::perms::none);
  auto info = inspect_certificate(own->certificate.span());
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->application_uri, "urn:host:smartfactory");
  EXPECT_EQ(info->common_name, "smartfactory@host");
  EXPECT_EQ(info->dns_names, (std::vector<std::string>{"host", "localhost"}));
  EXPECT_EQ(info->ip_addresses, (std::vector<std::string>{"127.0.0.1", "::1"}));
  EXPECT_TRUE(info->self_signed);
  EXPECT_FALSE(info->is_ca);
  EXPECT_EQ(info->key_bits, 2048U);
  EXPECT_NE(info->key_usage & key_usage::DigitalSignature, 0U);
  EXPECT_NE(info->key_usage & key_usage::KeyEncipherment, 0U);
  EXPECT_NE(info->key_usage & key_usage::KeyCertSign, 0U);  // self-signed
  EXPECT_EQ(files_in(store_.trusted_certs()), 1U);
  EXPECT_EQ(validate(own->certificate), StatusCode{});

  request.application_uri = "urn:another";
  auto again = store_.ensure_own(request);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->certificate, own->certificate);  // kept, not replaced
  EXPECT_EQ(again->private_key, own->private_key);
}

TEST_F(PkiTest, UntrustedGoesToRejectedAndIsAcceptedOnceMovedToTrusted) {
  const auto peer = app_certificate("urn:test:peer", "client");
  EXPECT_EQ(validate(peer.certificate), status::BadCertificateUntrusted);
  ASSERT_EQ(files_in(store_.rejected_certs()), 1U);
  EXPECT_EQ(validate(peer.certificate), status::BadCertificateUntrusted);
  EXPECT_EQ(files_in(store_.rejected_certs()), 1U);  // not twice

  // An operator moves it (what `smartfactory opcua pki trust` does); the same validator sees it.
  const std::string thumbprint = inspect_certificate(peer.certificate.span())->thumbprint;
  auto moved = store_.move(thumbprint.substr(0, 10), Folder::Rejected, Folder::Trusted);
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  EXPECT_EQ(moved->parent_path(), store_.trusted_certs());
  EXPECT_EQ(files_in(store_.rejected_certs()), 0U);
  EXPECT_EQ(validate(peer.certificate), StatusCode{});

  // And back (`pki reject`).
  ASSERT_TRUE(store_.move(thumbprint, Folder::Trusted, Folder::Rejected).ok());
  EXPECT_EQ(validate(peer.certificate), status::BadCertificateUntrusted);
  EXPECT_FALSE(store_.move("00", Folder::Rejected, Folder::Trusted).ok());  // too short a prefix
}

TEST_F(PkiTest, ValidityPeriodIsChecked) {
  CertificateRequest expired;
  expired.not_before = std::chrono::system_clock::now() - hours(48);
  expired.validity = hours(24);
  const auto old = app_certificate("urn:test:expired", "client", 2048, nullptr, expired);
  trust(old.certificate);
  const opcua::test::LogCapture log;
  EXPECT_EQ(validate(old.certificate), status::BadCertificateTimeInvalid);
  EXPECT_TRUE(log.warned("certificate has expired"));

  CertificateRequest future;
  future.not_before = std::chrono::system_clock::now() + hours(24);
  const auto young = app_certificate("urn:test:future", "client", 2048, nullptr, future);
  trust(young.certificate);
  EXPECT_EQ(validate(young.certificate), status::BadCertificateTimeInvalid);
  // The validator uses the clock: a day later it is valid.
  clock_.advance(hours(25));
  EXPECT_EQ(validate(young.certificate), StatusCode{});
}

TEST_F(PkiTest, UntrustedWinsOverExpired) {
  // Table 100 checks the trust list before the validity period.
  CertificateRequest expired;
  expired.not_before = std::chrono::system_clock::now() - hours(48);
  expired.validity = hours(24);
  const auto old = app_certificate("urn:test:expired", "client", 2048, nullptr, expired);
  EXPECT_EQ(validate(old.certificate), status::BadCertificateUntrusted);
}

TEST_F(PkiTest, ApplicationUriAndHostNameAreChecked) {
  const auto peer = app_certificate("urn:test:peer", "client");
  EXPECT_TRUE(check_application_uri(peer.certificate, "urn:test:peer").ok());
  EXPECT_EQ(status_of(check_application_uri(peer.certificate, "urn:test:other").error()),
            status::BadCertificateUriInvalid);
  EXPECT_TRUE(check_host_name(peer.certificate, "LOCALHOST").ok());
  EXPECT_TRUE(check_host_name(peer.certificate, "127.0.0.1").ok());
  EXPECT_EQ(status_of(check_host_name(peer.certificate, "10.1.1.1").error()),
            status::BadCertificateHostNameInvalid);
}

TEST_F(PkiTest, MissingKeyUsageIsRefused) {
  CertificateRequest bare;
  bare.omit_key_usage = true;
  const auto peer = app_certificate("urn:test:bare", "client", 2048, nullptr, bare);
  EXPECT_FALSE(inspect_certificate(peer.certificate.span())->has_key_usage);
  trust(peer.certificate);
  EXPECT_EQ(validate(peer.certificate), status::BadCertificateUseNotAllowed);
}

TEST_F(PkiTest, ChainsThroughIssuers) {
  const auto ca = ca_certificate("Plant CA");
  const auto leaf = app_certificate("urn:test:cell", "client", 2048, &ca);
  EXPECT_FALSE(inspect_certificate(leaf.certificate.span())->self_signed);
  // No CA anywhere: the chain cannot be built.
  EXPECT_EQ(validate(leaf.certificate), status::BadCertificateChainIncomplete);
  // The CA only completes chains: the leaf is still not trusted.
  add_issuer(ca.certificate);
  EXPECT_EQ(validate(leaf.certificate), status::BadCertificateUntrusted);
  // The leaf itself trusted, its CA in issuers/.
  trust(leaf.certificate);
  EXPECT_EQ(validate(leaf.certificate), StatusCode{});
}

TEST_F(PkiTest, TrustedCaTrustsWhatItIssuesAndChainsMaySendTheirCa) {
  const auto root = ca_certificate("Root CA");
  const auto sub = ca_certificate("Line CA", &root);
  const auto leaf = app_certificate("urn:test:cell", "client", 2048, &sub);
  trust(root.certificate);
  EXPECT_EQ(validate(leaf.certificate), status::BadCertificateChainIncomplete);
  // The peer sends its chain (leaf then issuer, OPC 10000-6 §6.7.2.3).
  Bytes chain = leaf.certificate.bytes();
  chain.insert(chain.end(), sub.certificate.bytes().begin(), sub.certificate.bytes().end());
  EXPECT_EQ(validate(ByteString(chain)), StatusCode{});
  add_issuer(sub.certificate);
  EXPECT_EQ(validate(leaf.certificate), StatusCode{});
}

TEST_F(PkiTest, RevokedCertificatesAreRefused) {
  const auto ca = ca_certificate("Plant CA");
  const auto good = app_certificate("urn:test:good", "client", 2048, &ca);
  const auto bad = app_certificate("urn:test:bad", "other", 2048, &ca);
  trust(ca.certificate);
  EXPECT_EQ(validate(bad.certificate), StatusCode{});  // no CRL yet: not known to be revoked
  // Issued at the validator's time: a CRL dated after it is not yet valid.
  auto crl = create_crl(ca, {bad.certificate}, clock_.utc_now());
  ASSERT_TRUE(crl.ok()) << crl.error().message;
  ASSERT_TRUE(write_file(store_.trusted_crls() / "plant.crl", *crl).ok());
  const opcua::test::LogCapture log;
  EXPECT_EQ(validate(bad.certificate), status::BadCertificateRevoked);
  EXPECT_TRUE(log.warned("certificate revoked"));
  EXPECT_EQ(validate(good.certificate), StatusCode{});
}

TEST_F(PkiTest, RevokedIssuersAreRefused) {
  const auto root = ca_certificate("Root CA");
  const auto sub = ca_certificate("Line CA", &root);
  const auto leaf = app_certificate("urn:test:cell", "client", 2048, &sub);
  trust(root.certificate);
  add_issuer(sub.certificate);
  EXPECT_EQ(validate(leaf.certificate), StatusCode{});
  ASSERT_TRUE(
      write_file(store_.trusted_crls() / "root.crl", *create_crl(root, {sub.certificate}, clock_.utc_now()))
          .ok());
  EXPECT_EQ(validate(leaf.certificate), status::BadCertificateIssuerRevoked);
}

TEST_F(PkiTest, RequiredCrlsMakeAMissingOneAnError) {
  const auto ca = ca_certificate("Plant CA");
  const auto leaf = app_certificate("urn:test:cell", "client", 2048, &ca);
  trust(ca.certificate);
  ValidationOptions strict;
  strict.require_crls = true;
  CertificateValidator validator(store_, clock_, strict);
  auto st = validator.validate(leaf.certificate);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(status_of(st.error()), status::BadCertificateRevocationUnknown);
}

TEST_F(PkiTest, GarbageIsAnInvalidCertificate) {
  EXPECT_EQ(validate(ByteString::from_text("not a certificate")), status::BadCertificateInvalid);
  EXPECT_EQ(validate(ByteString(Bytes{})), status::BadCertificateInvalid);
  EXPECT_EQ(files_in(store_.rejected_certs()), 0U);
}

TEST_F(PkiTest, ListsEveryFolder) {
  CertificateRequest request;
  request.application_uri = "urn:host:smartfactory";
  request.private_key = test_key("server");
  ASSERT_TRUE(store_.ensure_own(request).ok());
  const auto peer = app_certificate("urn:test:peer", "client");
  (void)validate(peer.certificate);
  add_issuer(ca_certificate("Plant CA").certificate);
  std::map<Folder, int> seen;
  for (const auto& entry : store_.certificates()) {
    seen[entry.folder] += 1;
  }
  EXPECT_EQ(seen[Folder::Own], 1);
  EXPECT_EQ(seen[Folder::Trusted], 1);
  EXPECT_EQ(seen[Folder::Issuers], 1);
  EXPECT_EQ(seen[Folder::Rejected], 1);
}

}  // namespace
}  // namespace sf::opcua::security::test
