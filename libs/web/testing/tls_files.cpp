#include "sf/web/testing/tls_files.hpp"

#include <chrono>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sf/opcua/security/certificate.hpp"

namespace sf::web::testing {
namespace {

namespace sec = opcua::security;
using namespace std::chrono_literals;

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

opcua::SecurityCredentials make(const sec::CertificateRequest& request,
                                const opcua::SecurityCredentials* issuer) {
  auto made = sec::create_certificate(request, issuer);
  if (!made) {
    throw std::runtime_error("test certificate: " + made.error().describe());
  }
  return *made;
}

// The server's certificate for 127.0.0.1 issued by `ca`, valid from `not_before` for a day.
opcua::SecurityCredentials server_certificate(const opcua::SecurityCredentials& ca, Bytes key,
                                              std::chrono::system_clock::time_point not_before) {
  sec::CertificateRequest request;
  request.application_uri = "urn:test:web";
  request.common_name = "localhost";
  request.dns_names = {"localhost"};
  request.ip_addresses = {"127.0.0.1"};
  request.not_before = not_before;
  request.validity = 24h;
  request.private_key = std::move(key);
  return make(request, &ca);
}

void write_key(const std::filesystem::path& path, const Bytes& key) {
  if (auto written = sec::write_private_key_file(path, key); !written) {
    throw std::runtime_error("test key: " + written.error().describe());
  }
}

}  // namespace

TlsFiles::TlsFiles() {
  sec::CertificateRequest ca_request;
  ca_request.common_name = "smartfactory test CA";
  ca_request.ca = true;
  const auto authority = make(ca_request, nullptr);
  const auto now = std::chrono::system_clock::now();
  const auto server = server_certificate(authority, {}, now - 1h);
  const auto expired = server_certificate(authority, server.private_key, now - 48h);
  sec::CertificateRequest other_request;
  other_request.application_uri = "urn:test:other";
  const auto other = make(other_request, nullptr);
  const auto ca_pem = sec::certificate_pem(authority.certificate.span());
  write_text(ca, ca_pem);
  write_text(chain, sec::certificate_pem(server.certificate.span()) + ca_pem);
  write_text(expired_chain, sec::certificate_pem(expired.certificate.span()) + ca_pem);
  write_key(key, server.private_key);
  write_key(other_key, other.private_key);
  write_text(not_pem, "not a certificate\n");
}

const TlsFiles& TlsFiles::get() {
  static const TlsFiles files;
  return files;
}

}  // namespace sf::web::testing
