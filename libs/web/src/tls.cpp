#include "tls.hpp"

#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <array>
#include <ctime>
#include <filesystem>
#include <string>
#include <system_error>

namespace sf::web {
namespace {

namespace fs = std::filesystem;

// RFC 9325 §4.2: TLS 1.2 with ephemeral key exchange and AEAD ciphers only (the ECDHE GCM and
// ChaCha20-Poly1305 suites); TLS 1.3's suites are all AEAD (RFC 8446 §9.1).
constexpr const char* kTls12Ciphers =
    "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-RSA-AES128-GCM-SHA256:"
    "ECDHE-ECDSA-AES256-GCM-SHA384:ECDHE-RSA-AES256-GCM-SHA384:"
    "ECDHE-ECDSA-CHACHA20-POLY1305:ECDHE-RSA-CHACHA20-POLY1305";
constexpr const char* kTls13Suites =
    "TLS_AES_128_GCM_SHA256:TLS_AES_256_GCM_SHA384:TLS_CHACHA20_POLY1305_SHA256";
constexpr const char* kGroups = "X25519:P-256:P-384";

// What OpenSSL said about the last failure (its error queue, emptied).
std::string openssl_reason() {
  std::string reason = "unknown OpenSSL error";
  while (const unsigned long code = ERR_get_error()) {
    std::array<char, 256> text{};
    ERR_error_string_n(code, text.data(), text.size());
    reason = text.data();
  }
  return reason;
}

Error file_error(std::string_view what, const fs::path& path, std::string_view problem) {
  return Error(Errc::invalid_argument, std::string(what) + " " + path.string() + ": " + std::string(problem));
}

Status readable(std::string_view what, const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    return file_error(what, path, ec ? ec.message() : "not a regular file");
  }
  return {};
}

std::string utc_text(const ASN1_TIME* time) {
  std::tm tm{};
  if (ASN1_TIME_to_tm(time, &tm) != 1) {
    return "an unreadable time";
  }
  std::array<char, 32> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%d %H:%M:%S UTC", &tm);
  return text.data();
}

// A certificate outside its validity period would be refused by every client (RFC 5280 §6.1.3).
Status check_validity(const X509* leaf, const fs::path& path) {
  if (X509_cmp_current_time(X509_get0_notAfter(leaf)) < 0) {
    return file_error("TLS certificate", path, "expired on " + utc_text(X509_get0_notAfter(leaf)));
  }
  if (X509_cmp_current_time(X509_get0_notBefore(leaf)) > 0) {
    return file_error("TLS certificate", path, "not valid before " + utc_text(X509_get0_notBefore(leaf)));
  }
  return {};
}

struct KeyDeleter {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};
struct BioDeleter {
  void operator()(BIO* bio) const { BIO_free(bio); }
};

// The private key of a PEM file; an encrypted key is refused rather than asked for on a terminal.
Result<std::unique_ptr<EVP_PKEY, KeyDeleter>> read_private_key(const fs::path& path) {
  SF_TRY(readable("TLS private key", path));
  const std::unique_ptr<BIO, BioDeleter> bio(BIO_new_file(path.c_str(), "r"));
  if (!bio) {
    return file_error("TLS private key", path, openssl_reason());
  }
  auto no_password = [](char*, int, int, void*) { return 0; };
  std::unique_ptr<EVP_PKEY, KeyDeleter> key(
      PEM_read_bio_PrivateKey(bio.get(), nullptr, no_password, nullptr));
  if (!key) {
    return file_error("TLS private key", path,
                      "not an unencrypted PEM private key (" + openssl_reason() + ")");
  }
  return key;
}

Status load_credentials(SSL_CTX* context, const TlsConfig& config) {
  SF_TRY(readable("TLS certificate chain", config.certificate_chain));
  if (SSL_CTX_use_certificate_chain_file(context, config.certificate_chain.c_str()) != 1) {
    return file_error("TLS certificate chain", config.certificate_chain,
                      "not a PEM certificate chain (" + openssl_reason() + ")");
  }
  const X509* leaf = SSL_CTX_get0_certificate(context);
  SF_TRY(check_validity(leaf, config.certificate_chain));
  auto key = read_private_key(config.private_key);
  if (!key) {
    return key.error();
  }
  if (X509_check_private_key(leaf, key->get()) != 1) {
    ERR_clear_error();
    return file_error("TLS private key", config.private_key,
                      "does not match the certificate " + config.certificate_chain.string());
  }
  if (SSL_CTX_use_PrivateKey(context, key->get()) != 1) {
    return file_error("TLS private key", config.private_key, openssl_reason());
  }
  return {};
}

Status restrict_protocol(SSL_CTX* context) {
  SSL_CTX_set_options(context,
                      SSL_OP_NO_COMPRESSION | SSL_OP_NO_RENEGOTIATION | SSL_OP_CIPHER_SERVER_PREFERENCE);
  if (SSL_CTX_set_min_proto_version(context, TLS1_2_VERSION) != 1 ||
      SSL_CTX_set_cipher_list(context, kTls12Ciphers) != 1 ||
      SSL_CTX_set_ciphersuites(context, kTls13Suites) != 1 ||
      SSL_CTX_set1_groups_list(context, kGroups) != 1) {
    return Error(Errc::unsupported, "TLS: this OpenSSL refuses the protocol settings: " + openssl_reason());
  }
  return {};
}

}  // namespace

Result<std::shared_ptr<boost::asio::ssl::context>> make_tls_context(const TlsConfig& config) {
  if (config.handshake_timeout_seconds <= 0) {
    return Error(Errc::invalid_argument, "TLS handshake timeout must be at least 1 s");
  }
  ERR_clear_error();
  auto context = std::make_shared<boost::asio::ssl::context>(boost::asio::ssl::context::tls_server);
  SF_TRY(restrict_protocol(context->native_handle()));
  SF_TRY(load_credentials(context->native_handle(), config));
  return context;
}

}  // namespace sf::web
