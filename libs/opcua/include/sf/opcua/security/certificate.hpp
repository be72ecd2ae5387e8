// X.509 application instance certificates (OPC 10000-6 §6.2.2): reading what a certificate
// says, creating self-signed and CA-issued ones with the X509v3 extensions OPC UA needs
// (ApplicationUri as the subjectAltName URI, DNS and IP names, key usage), CRLs, and files.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/transport/security_policy.hpp"

namespace sf::opcua::security {

// X.509 keyUsage bits (RFC 5280 §4.2.1.3) as OpenSSL reports them.
namespace key_usage {
inline constexpr std::uint32_t DigitalSignature = 0x80;
inline constexpr std::uint32_t NonRepudiation = 0x40;
inline constexpr std::uint32_t KeyEncipherment = 0x20;
inline constexpr std::uint32_t DataEncipherment = 0x10;
inline constexpr std::uint32_t KeyCertSign = 0x04;
inline constexpr std::uint32_t CrlSign = 0x02;
}  // namespace key_usage

struct CertificateInfo {
  std::string subject;      // "CN=..., O=..." (RFC 2253 order)
  std::string common_name;  // CN
  std::string issuer;
  std::string application_uri;  // the (first) URI of subjectAltName
  std::vector<std::string> dns_names;
  std::vector<std::string> ip_addresses;
  std::chrono::system_clock::time_point not_before{};
  std::chrono::system_clock::time_point not_after{};
  std::string thumbprint;  // SHA-1 of the DER, lower-case hex (what ReceiverCertificateThumbprint carries)
  std::string serial;      // hex
  std::size_t key_bits = 0;
  bool is_ca = false;
  bool self_signed = false;
  bool has_key_usage = false;
  std::uint32_t key_usage = 0;  // key_usage:: bits when has_key_usage
};

// The leaf of a DER certificate (or chain); BadCertificateInvalid when it does not parse.
Result<CertificateInfo> inspect_certificate(ByteSpan der);
// The leaf certificate's DER out of a chain (DER certificates back to back, OPC 10000-6 §6.7.2.3).
Result<ByteString> leaf_certificate(ByteSpan der);

struct CertificateRequest {
  std::string application_uri;  // subjectAltName URI (required unless ca)
  std::string common_name;      // CN
  std::string organization = "smartfactory";
  std::vector<std::string> dns_names;     // subjectAltName DNS
  std::vector<std::string> ip_addresses;  // subjectAltName IP (IPv4 or IPv6 text)
  std::chrono::system_clock::time_point not_before = std::chrono::system_clock::now() - std::chrono::hours(1);
  std::chrono::hours validity = std::chrono::hours(24 * 365 * 5);
  unsigned key_bits = 2048;
  // A CA (basicConstraints CA:TRUE, keyCertSign and cRLSign) instead of an application instance
  // certificate.
  bool ca = false;
  // Leave keyUsage out (tests of certificates that may not be used).
  bool omit_key_usage = false;
  // Reuse this PKCS#8 key instead of generating one (RSA key generation is slow).
  Bytes private_key;
};

// A new certificate and its key. Self-signed unless `issuer` (a CA's certificate and key) is
// given. Application instance certificates get digitalSignature, nonRepudiation,
// keyEncipherment, dataEncipherment (plus keyCertSign when self-signed), extendedKeyUsage
// serverAuth and clientAuth, basicConstraints CA:FALSE (OPC 10000-6 §6.2.2).
Result<SecurityCredentials> create_certificate(const CertificateRequest& request,
                                               const SecurityCredentials* issuer = nullptr);

// A CRL of `issuer` revoking `revoked` (certificates it issued), valid from `this_update` for
// `validity`. DER.
Result<Bytes> create_crl(const SecurityCredentials& issuer, const std::vector<ByteString>& revoked,
                         std::chrono::system_clock::time_point this_update = std::chrono::system_clock::now(),
                         std::chrono::hours validity = std::chrono::hours(24 * 30));

// Files: certificates and CRLs as DER or PEM, private keys as PKCS#8 PEM (written 0600).
Result<ByteString> read_certificate_file(const std::filesystem::path& path);
Result<Bytes> read_crl_file(const std::filesystem::path& path);
Result<Bytes> read_private_key_file(const std::filesystem::path& path);  // → PKCS#8 DER
Status write_file(const std::filesystem::path& path, ByteSpan bytes, bool secret = false);
Status write_private_key_file(const std::filesystem::path& path, ByteSpan pkcs8_der);
std::string certificate_pem(ByteSpan der);

}  // namespace sf::opcua::security
