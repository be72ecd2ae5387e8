// Validating a peer's certificate against the PKI folder (OPC 10000-4 §6.1.3 Table 100) with
// OpenSSL's chain builder; the folders are re-read when they change.
#include <openssl/err.h>
#include <openssl/x509_vfy.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "openssl.hpp"
#include "sf/core/log.hpp"
#include "sf/core/text.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace fs = std::filesystem;

struct CertificateValidator::Snapshot {
  std::string signature;  // names, sizes and times of every file it was built from
  ossl::Ptr<X509_STORE> store;
  std::set<std::string> trusted;  // thumbprints of trusted/certs
};

namespace {

// An error OpenSSL reported while building the chain, and at which depth (0 = the leaf).
struct Found {
  int error = X509_V_OK;
  int depth = 0;
};
// Errors that come after the trust list in Table 100's order: recorded, checked later.
struct Deferred {
  bool require_crls = false;
  std::optional<Found> time;
  std::optional<Found> revocation_unknown;
};

// Table 100: validity period and revocation status are checked after the trust list.
int verify_callback(int ok, X509_STORE_CTX* ctx) {
  if (ok == 1) {
    return 1;
  }
  auto* deferred = static_cast<Deferred*>(X509_STORE_CTX_get_app_data(ctx));
  const Found found{X509_STORE_CTX_get_error(ctx), X509_STORE_CTX_get_error_depth(ctx)};
  switch (found.error) {
    case X509_V_ERR_CERT_NOT_YET_VALID:
    case X509_V_ERR_CERT_HAS_EXPIRED:
      if (!deferred->time) {
        deferred->time = found;
      }
      return 1;
    case X509_V_ERR_UNABLE_TO_GET_CRL:
      if (deferred->require_crls && !deferred->revocation_unknown) {
        deferred->revocation_unknown = found;
      }
      return 1;
    case X509_V_ERR_CRL_NOT_YET_VALID:
    case X509_V_ERR_CRL_HAS_EXPIRED:
    case X509_V_ERR_UNABLE_TO_GET_CRL_ISSUER:
      if (!deferred->revocation_unknown) {
        deferred->revocation_unknown = found;
      }
      return 1;
    default:
      return 0;
  }
}

StatusCode code_of(const Found& found) {
  const bool leaf = found.depth == 0;
  switch (found.error) {
    case X509_V_ERR_CERT_NOT_YET_VALID:
    case X509_V_ERR_CERT_HAS_EXPIRED:
      return leaf ? status::BadCertificateTimeInvalid : status::BadCertificateIssuerTimeInvalid;
    case X509_V_ERR_CERT_REVOKED:
      return leaf ? status::BadCertificateRevoked : status::BadCertificateIssuerRevoked;
    case X509_V_ERR_UNABLE_TO_GET_CRL:
    case X509_V_ERR_CRL_NOT_YET_VALID:
    case X509_V_ERR_CRL_HAS_EXPIRED:
    case X509_V_ERR_UNABLE_TO_GET_CRL_ISSUER:
      return leaf ? status::BadCertificateRevocationUnknown : status::BadCertificateIssuerRevocationUnknown;
    case X509_V_ERR_DEPTH_ZERO_SELF_SIGNED_CERT:
    case X509_V_ERR_SELF_SIGNED_CERT_IN_CHAIN:
      return status::BadCertificateUntrusted;
    case X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT:
    case X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY:
    case X509_V_ERR_UNABLE_TO_VERIFY_LEAF_SIGNATURE:
      return status::BadCertificateChainIncomplete;
    case X509_V_ERR_INVALID_CA:
    case X509_V_ERR_KEYUSAGE_NO_CERTSIGN:
    case X509_V_ERR_KEYUSAGE_NO_CRL_SIGN:
    case X509_V_ERR_INVALID_PURPOSE:
      return leaf ? status::BadCertificateUseNotAllowed : status::BadCertificateIssuerUseNotAllowed;
    default:
      return status::BadCertificateInvalid;
  }
}

Error describe(const Found& found, const CertificateInfo& leaf) {
  return status_error(code_of(found),
                      fmt::format("certificate '{}' ({}): {} (at depth {})", leaf.subject, leaf.thumbprint,
                                  X509_verify_cert_error_string(found.error), found.depth));
}

void add_signature(std::string& signature, const fs::path& dir, std::vector<fs::path>& files) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    struct stat st {};
    if (it->path().extension() == ".tmp" || ::stat(it->path().c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
      continue;
    }
    files.push_back(it->path());
    signature +=
        fmt::format("{}|{}|{}.{}\n", it->path().string(), st.st_size, st.st_mtim.tv_sec, st.st_mtim.tv_nsec);
  }
}

void add_certificates(X509_STORE* store, const std::vector<fs::path>& files, std::set<std::string>* trusted) {
  for (const auto& file : files) {
    auto der = read_certificate_file(file);
    auto cert = der ? ossl::load_certificate(der->span()) : Result<ossl::Cert>(der.error());
    if (!cert) {
      log::get("opcua")->warn("PKI: skipping {}: {}", file.string(), cert.error().message);
      continue;
    }
    X509_STORE_add_cert(store, cert->get());  // duplicates are fine
    if (trusted != nullptr) {
      trusted->insert(ossl::hex(ossl::sha1(der->span())));
    }
  }
}

void add_crls(X509_STORE* store, const std::vector<fs::path>& files) {
  for (const auto& file : files) {
    auto der = read_crl_file(file);
    auto crl = der ? ossl::load_crl_bytes(*der) : Result<ossl::Crl>(der.error());
    if (!crl) {
      log::get("opcua")->warn("PKI: skipping CRL {}: {}", file.string(), crl.error().message);
      continue;
    }
    X509_STORE_add_crl(store, crl->get());
  }
  ERR_clear_error();
}

}  // namespace

CertificateValidator::CertificateValidator(PkiStore store, const Clock& clock, ValidationOptions options)
    : store_(std::move(store)), clock_(clock), options_(options) {}

CertificateValidator::~CertificateValidator() = default;

std::shared_ptr<const CertificateValidator::Snapshot> CertificateValidator::snapshot() {
  std::string signature;
  std::vector<fs::path> trusted;
  std::vector<fs::path> issuers;
  std::vector<fs::path> crls;
  add_signature(signature, store_.trusted_certs(), trusted);
  add_signature(signature, store_.issuer_certs(), issuers);
  add_signature(signature, store_.trusted_crls(), crls);
  add_signature(signature, store_.issuer_crls(), crls);
  std::lock_guard lock(mutex_);
  if (snapshot_ && snapshot_->signature == signature) {
    return snapshot_;
  }
  auto next = std::make_shared<Snapshot>();
  next->signature = std::move(signature);
  next->store.reset(X509_STORE_new());
  add_certificates(next->store.get(), trusted, &next->trusted);
  add_certificates(next->store.get(), issuers, nullptr);
  add_crls(next->store.get(), crls);
  log::get("opcua")->debug("PKI {}: {} trusted, {} issuer certificates, {} CRLs", store_.root().string(),
                           trusted.size(), issuers.size(), crls.size());
  snapshot_ = std::move(next);
  return snapshot_;
}

Status CertificateValidator::validate(const ByteString& certificate_chain) {
  auto chain = ossl::load_chain(certificate_chain.span());
  if (!chain) {
    return chain.error();
  }
  const Bytes leaf_der = ossl::der_of((*chain)[0].get());
  auto leaf = inspect_certificate(leaf_der);
  if (!leaf) {
    return leaf.error();
  }
  const auto snap = snapshot();
  ossl::Ptr<stack_st_X509> untrusted(sk_X509_new_null());
  for (std::size_t i = 1; i < chain->size(); ++i) {
    sk_X509_push(untrusted.get(), (*chain)[i].get());
  }
  ossl::Ptr<X509_STORE_CTX> ctx(X509_STORE_CTX_new());
  if (!ctx || X509_STORE_CTX_init(ctx.get(), snap->store.get(), (*chain)[0].get(), untrusted.get()) != 1) {
    return ossl::failure(status::BadInternalError, "cannot set up certificate validation");
  }
  Deferred deferred;
  deferred.require_crls = options_.require_crls;
  X509_STORE_CTX_set_app_data(ctx.get(), &deferred);
  X509_STORE_CTX_set_verify_cb(ctx.get(), verify_callback);
  X509_VERIFY_PARAM* param = X509_STORE_CTX_get0_param(ctx.get());
  X509_VERIFY_PARAM_set_time(param, std::chrono::system_clock::to_time_t(clock_.utc_now()));
  // Chains end at a self-signed root; only a leaf that is itself in trusted/ may stand alone
  // (a trusted peer whose CA we do not have). CRLs are checked for every certificate of the
  // chain that has one.
  unsigned long flags = X509_V_FLAG_CRL_CHECK | X509_V_FLAG_CRL_CHECK_ALL;
  if (snap->trusted.count(leaf->thumbprint) != 0) {
    flags |= X509_V_FLAG_PARTIAL_CHAIN;
  }
  X509_VERIFY_PARAM_set_flags(param, flags);
  const int verified = X509_verify_cert(ctx.get());
  ERR_clear_error();

  std::optional<Error> failure;
  if (verified != 1) {
    failure = describe(Found{X509_STORE_CTX_get_error(ctx.get()), X509_STORE_CTX_get_error_depth(ctx.get())},
                       *leaf);
  } else {
    STACK_OF(X509)* built = X509_STORE_CTX_get0_chain(ctx.get());
    bool trusted = false;
    for (int i = 0; i < sk_X509_num(built) && !trusted; ++i) {
      trusted = snap->trusted.count(ossl::hex(ossl::sha1(ossl::der_of(sk_X509_value(built, i))))) != 0;
    }
    if (!trusted) {
      failure =
          status_error(status::BadCertificateUntrusted,
                       fmt::format("certificate '{}' ({}) is not trusted", leaf->subject, leaf->thumbprint));
    } else if (deferred.time) {
      failure = describe(*deferred.time, *leaf);
    } else if (deferred.revocation_unknown) {
      failure = describe(*deferred.revocation_unknown, *leaf);
    } else if (!leaf->has_key_usage || (leaf->key_usage & key_usage::DigitalSignature) == 0 ||
               (leaf->key_usage & key_usage::KeyEncipherment) == 0) {
      // OPC 10000-6 §6.2.2: digitalSignature and keyEncipherment at least.
      failure = status_error(status::BadCertificateUseNotAllowed,
                             fmt::format("certificate '{}' ({}) lacks the key usage digitalSignature and "
                                         "keyEncipherment",
                                         leaf->subject, leaf->thumbprint));
    }
  }
  if (!failure) {
    return {};
  }
  const StatusCode code = status_of(*failure);
  if (options_.copy_rejected &&
      (code == status::BadCertificateUntrusted || code == status::BadCertificateChainIncomplete)) {
    auto file = store_.add(PkiStore::Folder::Rejected, ByteString(leaf_der));
    log::get("opcua")->warn("{}; copied to {} (trust it with `smartfactory opcua pki trust {}`)",
                            failure->message, file ? file->string() : std::string("rejected/ (failed)"),
                            leaf->thumbprint.substr(0, 12));
  } else {
    log::get("opcua")->warn("{}", failure->message);
  }
  return *failure;
}

Status check_application_uri(const ByteString& certificate, std::string_view application_uri) {
  auto info = inspect_certificate(certificate.span());
  if (!info) {
    return info.error();
  }
  if (info->application_uri != application_uri) {
    return status_error(status::BadCertificateUriInvalid,
                        fmt::format("certificate '{}' names the application '{}', not '{}'", info->subject,
                                    info->application_uri, application_uri));
  }
  return {};
}

Status check_host_name(const ByteString& certificate, std::string_view host) {
  auto info = inspect_certificate(certificate.span());
  if (!info) {
    return info.error();
  }
  const std::string wanted = lower(host);
  const auto same = [&wanted](const std::string& name) { return lower(name) == wanted; };
  if (std::any_of(info->dns_names.begin(), info->dns_names.end(), same) ||
      std::any_of(info->ip_addresses.begin(), info->ip_addresses.end(), same)) {
    return {};
  }
  return status_error(status::BadCertificateHostNameInvalid,
                      fmt::format("certificate '{}' is not for the host '{}'", info->subject, host));
}

}  // namespace sf::opcua::security
