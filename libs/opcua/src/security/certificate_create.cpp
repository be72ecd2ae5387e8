// Creating application instance certificates, CA certificates and CRLs (OPC 10000-6 §6.2.2,
// RFC 5280).
#include <openssl/bn.h>
#include <openssl/rsa.h>
#include <openssl/x509v3.h>

#include <fmt/format.h>

#include "openssl.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace {

constexpr std::string_view kAppKeyUsage =
    "critical,digitalSignature,nonRepudiation,keyEncipherment,dataEncipherment";

Error openssl_error(std::string_view what) {
  return ossl::failure(status::BadInternalError, what);
}

Result<ossl::Key> key_for(const CertificateRequest& request) {
  if (!request.private_key.empty()) {
    return ossl::load_private_key(request.private_key);
  }
  EVP_PKEY* key = EVP_RSA_gen(request.key_bits);
  if (key == nullptr) {
    return openssl_error("RSA key generation failed");
  }
  return ossl::share(key);
}

// A random positive 128-bit serial number (RFC 5280 §4.1.2.2: at most 20 octets, unique).
bool set_serial(X509* cert) {
  BIGNUM* bn = BN_new();
  const bool ok = bn != nullptr && BN_rand(bn, 127, BN_RAND_TOP_ANY, BN_RAND_BOTTOM_ANY) == 1 &&
                  BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(cert)) != nullptr;
  BN_free(bn);
  return ok;
}

bool set_validity(X509* cert, const CertificateRequest& request) {
  const std::time_t from = std::chrono::system_clock::to_time_t(request.not_before);
  const std::time_t to = std::chrono::system_clock::to_time_t(request.not_before + request.validity);
  return ASN1_TIME_set(X509_getm_notBefore(cert), from) != nullptr &&
         ASN1_TIME_set(X509_getm_notAfter(cert), to) != nullptr;
}

bool add_name_entry(X509_NAME* name, const char* field, const std::string& value) {
  return value.empty() || X509_NAME_add_entry_by_txt(name, field, MBSTRING_UTF8,
                                                     reinterpret_cast<const unsigned char*>(value.data()),
                                                     static_cast<int>(value.size()), -1, 0) == 1;
}

bool push_name(GENERAL_NAMES* names, int type, ASN1_STRING* value) {
  GENERAL_NAME* name = GENERAL_NAME_new();
  if (name == nullptr || value == nullptr) {
    GENERAL_NAME_free(name);
    ASN1_STRING_free(value);
    return false;
  }
  GENERAL_NAME_set0_value(name, type, value);
  return sk_GENERAL_NAME_push(names, name) > 0;
}

ASN1_STRING* ia5(const std::string& text) {
  ASN1_STRING* s = ASN1_IA5STRING_new();
  if (s != nullptr && ASN1_STRING_set(s, text.data(), static_cast<int>(text.size())) != 1) {
    ASN1_STRING_free(s);
    return nullptr;
  }
  return s;
}

// subjectAltName built name by name (a URI may contain characters the config syntax splits on).
Status add_alt_names(X509* cert, const CertificateRequest& request) {
  GENERAL_NAMES* names = sk_GENERAL_NAME_new_null();
  bool ok = names != nullptr;
  if (ok && !request.application_uri.empty()) {
    ok = push_name(names, GEN_URI, ia5(request.application_uri));
  }
  for (const auto& dns : request.dns_names) {
    ok = ok && push_name(names, GEN_DNS, ia5(dns));
  }
  for (const auto& ip : request.ip_addresses) {
    ASN1_OCTET_STRING* address = a2i_IPADDRESS(ip.c_str());
    if (address == nullptr) {
      GENERAL_NAMES_free(names);
      return status_error(status::BadInvalidArgument, fmt::format("'{}' is not an IP address", ip));
    }
    ok = ok && push_name(names, GEN_IPADD, address);
  }
  ok = ok &&
       (sk_GENERAL_NAME_num(names) == 0 || X509_add1_ext_i2d(cert, NID_subject_alt_name, names, 0, 0) == 1);
  GENERAL_NAMES_free(names);
  if (!ok) {
    return openssl_error("cannot add subjectAltName");
  }
  return {};
}

Status add_extension(X509* cert, X509V3_CTX* ctx, int nid, std::string_view value) {
  const std::string text(value);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, ctx, nid, text.c_str());
  const bool ok = ext != nullptr && X509_add_ext(cert, ext, -1) == 1;
  X509_EXTENSION_free(ext);
  if (!ok) {
    return openssl_error(fmt::format("cannot add extension {}", OBJ_nid2sn(nid)));
  }
  return {};
}

Status add_extensions(X509* cert, X509* issuer, const CertificateRequest& request, bool self_signed) {
  X509V3_CTX ctx;
  X509V3_set_ctx(&ctx, issuer, cert, nullptr, nullptr, 0);
  if (request.ca) {
    SF_TRY(add_extension(cert, &ctx, NID_basic_constraints, "critical,CA:TRUE"));
    SF_TRY(add_extension(cert, &ctx, NID_key_usage, "critical,keyCertSign,cRLSign"));
  } else {
    SF_TRY(add_extension(cert, &ctx, NID_basic_constraints, "critical,CA:FALSE"));
    if (!request.omit_key_usage) {
      // OPC 10000-6 §6.2.2: keyCertSign too when the certificate is self-signed.
      const std::string usage = std::string(kAppKeyUsage) + (self_signed ? ",keyCertSign" : "");
      SF_TRY(add_extension(cert, &ctx, NID_key_usage, usage));
    }
    SF_TRY(add_extension(cert, &ctx, NID_ext_key_usage, "serverAuth,clientAuth"));
  }
  SF_TRY(add_extension(cert, &ctx, NID_subject_key_identifier, "hash"));
  SF_TRY(add_extension(cert, &ctx, NID_authority_key_identifier, "keyid:always"));
  return add_alt_names(cert, request);
}

}  // namespace

Result<SecurityCredentials> create_certificate(const CertificateRequest& request,
                                               const SecurityCredentials* issuer) {
  if (request.application_uri.empty() && !request.ca) {
    return status_error(status::BadInvalidArgument,
                        "an application instance certificate needs an ApplicationUri");
  }
  auto key = key_for(request);
  if (!key) {
    return key.error();
  }
  ossl::Key issuer_key = *key;
  ossl::Cert issuer_cert;
  if (issuer != nullptr) {
    auto loaded_key = ossl::load_private_key(issuer->private_key);
    auto loaded_cert = ossl::load_certificate(issuer->certificate.span());
    if (!loaded_key || !loaded_cert) {
      return status_error(status::BadInvalidArgument, "the issuer's certificate or key does not load");
    }
    issuer_key = *loaded_key;
    issuer_cert = std::move(*loaded_cert);
  }
  ossl::Cert cert(X509_new());
  X509* x = cert.get();
  X509_NAME* subject = X509_get_subject_name(x);
  const bool names_ok = add_name_entry(subject, "CN", request.common_name) &&
                        add_name_entry(subject, "O", request.organization);
  if (!names_ok || X509_set_version(x, 2) != 1 || !set_serial(x) || !set_validity(x, request) ||
      X509_set_issuer_name(x, issuer_cert ? X509_get_subject_name(issuer_cert.get()) : subject) != 1 ||
      X509_set_pubkey(x, key->get()) != 1) {
    return openssl_error("cannot fill in the certificate");
  }
  SF_TRY(add_extensions(x, issuer_cert ? issuer_cert.get() : x, request, !issuer_cert));
  if (X509_sign(x, issuer_key.get(), EVP_sha256()) <= 0) {
    return openssl_error("cannot sign the certificate");
  }
  auto private_key = ossl::private_key_der(key->get());
  if (!private_key) {
    return private_key.error();
  }
  return SecurityCredentials{ByteString(ossl::der_of(x)), std::move(*private_key)};
}

Result<Bytes> create_crl(const SecurityCredentials& issuer, const std::vector<ByteString>& revoked,
                         std::chrono::system_clock::time_point this_update, std::chrono::hours validity) {
  auto key = ossl::load_private_key(issuer.private_key);
  auto ca = ossl::load_certificate(issuer.certificate.span());
  if (!key || !ca) {
    return status_error(status::BadInvalidArgument, "the CA's certificate or key does not load");
  }
  ossl::Crl crl(X509_CRL_new());
  ossl::Ptr<ASN1_TIME> last(ASN1_TIME_set(nullptr, std::chrono::system_clock::to_time_t(this_update)));
  ossl::Ptr<ASN1_TIME> next(
      ASN1_TIME_set(nullptr, std::chrono::system_clock::to_time_t(this_update + validity)));
  if (!crl || !last || !next || X509_CRL_set_version(crl.get(), 1) != 1 ||
      X509_CRL_set_issuer_name(crl.get(), X509_get_subject_name(ca->get())) != 1 ||
      X509_CRL_set1_lastUpdate(crl.get(), last.get()) != 1 ||
      X509_CRL_set1_nextUpdate(crl.get(), next.get()) != 1) {
    return openssl_error("cannot fill in the CRL");
  }
  for (const auto& der : revoked) {
    auto cert = ossl::load_certificate(der.span());
    if (!cert) {
      return cert.error();
    }
    X509_REVOKED* entry = X509_REVOKED_new();
    if (entry == nullptr || X509_REVOKED_set_serialNumber(entry, X509_get_serialNumber(cert->get())) != 1 ||
        X509_REVOKED_set_revocationDate(entry, last.get()) != 1 ||
        X509_CRL_add0_revoked(crl.get(), entry) != 1) {
      X509_REVOKED_free(entry);
      return openssl_error("cannot add a revoked certificate");
    }
  }
  if (X509_CRL_sort(crl.get()) != 1 || X509_CRL_sign(crl.get(), key->get(), EVP_sha256()) <= 0) {
    return openssl_error("cannot sign the CRL");
  }
  return ossl::der_of(crl.get());
}

}  // namespace sf::opcua::security
