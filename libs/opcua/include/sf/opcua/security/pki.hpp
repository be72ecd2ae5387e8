// The PKI folder of an application and the validation of peer certificates against it
// (OPC 10000-4 §6.1.3, OPC 10000-12 §F.1 directory store):
//
//   <root>/own/certs/cert.der        our application instance certificate
//   <root>/own/private/key.pem       its private key (PKCS#8, mode 0600)
//   <root>/trusted/certs/            trusted certificates (peers, or CAs whose issues we trust)
//   <root>/trusted/crl/              CRLs of trusted CAs
//   <root>/issuers/certs/            CA certificates that only complete chains
//   <root>/issuers/crl/              their CRLs
//   <root>/rejected/certs/           certificates we refused, for an operator to move to trusted/
//
// Files may be DER or PEM. The validator re-reads the folders whenever they change, so a
// certificate moved from rejected/ into trusted/ is accepted without a restart.
#pragma once

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/security/certificate.hpp"

namespace sf::opcua::security {

class PkiStore {
 public:
  explicit PkiStore(std::filesystem::path root) : root_(std::move(root)) {}

  [[nodiscard]] const std::filesystem::path& root() const { return root_; }
  [[nodiscard]] std::filesystem::path own_certificate() const { return root_ / "own" / "certs" / "cert.der"; }
  [[nodiscard]] std::filesystem::path own_private_key() const {
    return root_ / "own" / "private" / "key.pem";
  }
  [[nodiscard]] std::filesystem::path trusted_certs() const { return root_ / "trusted" / "certs"; }
  [[nodiscard]] std::filesystem::path trusted_crls() const { return root_ / "trusted" / "crl"; }
  [[nodiscard]] std::filesystem::path issuer_certs() const { return root_ / "issuers" / "certs"; }
  [[nodiscard]] std::filesystem::path issuer_crls() const { return root_ / "issuers" / "crl"; }
  [[nodiscard]] std::filesystem::path rejected_certs() const { return root_ / "rejected" / "certs"; }

  // Creates the folders (own/private 0700).
  Status create_folders() const;
  [[nodiscard]] bool has_own() const;
  Result<SecurityCredentials> load_own() const;
  // Creates (replaces) the own certificate and key and trusts the certificate, so that the
  // server and the command-line client of one installation accept each other.
  Result<SecurityCredentials> create_own(const CertificateRequest& request) const;
  // load_own(), or create_own(request) when there is no own certificate yet.
  Result<SecurityCredentials> ensure_own(const CertificateRequest& request) const;

  enum class Folder { Own, Trusted, Issuers, Rejected };
  struct Entry {
    Folder folder = Folder::Trusted;
    std::filesystem::path file;
    CertificateInfo info;
  };
  // Every certificate in own/, trusted/, issuers/ and rejected/ (unreadable files are skipped
  // with a warning in the log), and the CRL files.
  [[nodiscard]] std::vector<Entry> certificates() const;
  [[nodiscard]] std::vector<std::filesystem::path> crls() const;

  // Copies a certificate into a folder as "<CN>_<thumbprint>.der"; returns the file.
  Result<std::filesystem::path> add(Folder folder, const ByteString& certificate) const;
  // Moves the certificate whose thumbprint starts with `thumbprint` (hex, at least 8 digits) from
  // one folder to another: trust = rejected → trusted, reject = trusted → rejected.
  Result<std::filesystem::path> move(std::string_view thumbprint, Folder from, Folder to) const;

  // "<CN>_<thumbprint>.der" with the CN reduced to letters, digits, '-' and '_'.
  static std::string file_name(const CertificateInfo& info);
  static std::string_view folder_name(Folder folder);

 private:
  [[nodiscard]] std::filesystem::path folder_path(Folder folder) const;
  std::filesystem::path root_;
};

struct ValidationOptions {
  // Refuse certificates whose issuer has no CRL (BadCertificateRevocationUnknown); by default a
  // missing CRL means "not revoked", a CRL that is present is always checked.
  bool require_crls = false;
  // Copy untrusted certificates into rejected/certs.
  bool copy_rejected = true;
};

// Validates peer certificates against a PkiStore (OPC 10000-4 §6.1.3 Table 100): structure,
// chain through issuers/ and trusted/ (and the chain the peer sent), signatures, trust list,
// validity period (of the clock's UTC time), key usage and revocation. Thread-safe.
class CertificateValidator {
 public:
  explicit CertificateValidator(PkiStore store, const Clock& clock = SteadyClock::instance(),
                                ValidationOptions options = {});
  ~CertificateValidator();
  CertificateValidator(const CertificateValidator&) = delete;
  CertificateValidator& operator=(const CertificateValidator&) = delete;

  // Good, or BadCertificateInvalid, BadCertificateUntrusted (then copied to rejected/),
  // BadCertificateChainIncomplete, BadCertificateTimeInvalid, BadCertificateIssuerTimeInvalid,
  // BadCertificateUseNotAllowed, BadCertificateIssuerUseNotAllowed, BadCertificateRevoked,
  // BadCertificateIssuerRevoked, BadCertificateRevocationUnknown, ... with the reason.
  Status validate(const ByteString& certificate_chain);

  [[nodiscard]] const PkiStore& store() const { return store_; }

  struct Snapshot;

 private:
  std::shared_ptr<const Snapshot> snapshot();

  PkiStore store_;
  const Clock& clock_;
  ValidationOptions options_;
  std::mutex mutex_;
  std::shared_ptr<const Snapshot> snapshot_;
};

// OPC 10000-4 §6.1.3: the certificate's subjectAltName URI must be the ApplicationUri of the
// application description that comes with it (BadCertificateUriInvalid).
Status check_application_uri(const ByteString& certificate, std::string_view application_uri);
// The host of an endpoint URL must be one of the certificate's DNS or IP names
// (BadCertificateHostNameInvalid).
Status check_host_name(const ByteString& certificate, std::string_view host);

}  // namespace sf::opcua::security
