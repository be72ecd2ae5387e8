// Reading certificates and the files of a PKI folder.
#include "sf/opcua/security/certificate.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <openssl/bn.h>
#include <openssl/x509v3.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>

#include <fmt/format.h>

#include "openssl.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace {

std::string name_text(const X509_NAME* name) {
  ossl::Ptr<BIO> bio(BIO_new(BIO_s_mem()));
  X509_NAME_print_ex(bio.get(), name, 0, XN_FLAG_RFC2253 & ~ASN1_STRFLGS_ESC_MSB);
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio.get(), &data);
  return size > 0 ? std::string(data, static_cast<std::size_t>(size)) : std::string();
}

std::string common_name(const X509_NAME* name) {
  const int index = X509_NAME_get_index_by_NID(name, NID_commonName, -1);
  if (index < 0) {
    return {};
  }
  unsigned char* utf8 = nullptr;
  const int size = ASN1_STRING_to_UTF8(&utf8, X509_NAME_ENTRY_get_data(X509_NAME_get_entry(name, index)));
  if (size < 0) {
    return {};
  }
  std::string out(reinterpret_cast<const char*>(utf8), static_cast<std::size_t>(size));
  OPENSSL_free(utf8);
  return out;
}

std::string ia5_text(const ASN1_STRING* s) {
  return std::string(reinterpret_cast<const char*>(ASN1_STRING_get0_data(s)),
                     static_cast<std::size_t>(ASN1_STRING_length(s)));
}

std::string ip_text(const ASN1_OCTET_STRING* s) {
  const int length = ASN1_STRING_length(s);
  char buffer[INET6_ADDRSTRLEN] = {};
  const int family = length == 4 ? AF_INET : length == 16 ? AF_INET6 : 0;
  if (family == 0 || inet_ntop(family, ASN1_STRING_get0_data(s), buffer, sizeof buffer) == nullptr) {
    return {};
  }
  return buffer;
}

void read_alt_names(X509* cert, CertificateInfo& info) {
  auto* names = static_cast<GENERAL_NAMES*>(X509_get_ext_d2i(cert, NID_subject_alt_name, nullptr, nullptr));
  if (names == nullptr) {
    return;
  }
  for (int i = 0; i < sk_GENERAL_NAME_num(names); ++i) {
    const GENERAL_NAME* name = sk_GENERAL_NAME_value(names, i);
    if (name->type == GEN_URI && info.application_uri.empty()) {
      info.application_uri = ia5_text(name->d.uniformResourceIdentifier);
    } else if (name->type == GEN_DNS) {
      info.dns_names.push_back(ia5_text(name->d.dNSName));
    } else if (name->type == GEN_IPADD) {
      info.ip_addresses.push_back(ip_text(name->d.iPAddress));
    }
  }
  GENERAL_NAMES_free(names);
}

std::chrono::system_clock::time_point time_of(const ASN1_TIME* t) {
  std::tm tm{};
  if (t == nullptr || ASN1_TIME_to_tm(t, &tm) != 1) {
    return {};
  }
  return std::chrono::system_clock::from_time_t(timegm(&tm));
}

std::string serial_hex(X509* cert) {
  BIGNUM* bn = ASN1_INTEGER_to_BN(X509_get0_serialNumber(cert), nullptr);
  char* text = bn != nullptr ? BN_bn2hex(bn) : nullptr;
  std::string out = text != nullptr ? text : "";
  OPENSSL_free(text);
  BN_free(bn);
  return out;
}

Result<Bytes> read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return make_error(Errc::io, fmt::format("cannot read {}: {}", path.string(), std::strerror(errno)));
  }
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

Result<CertificateInfo> inspect_certificate(ByteSpan der) {
  std::size_t used = 0;
  auto cert = ossl::load_certificate(der, &used);
  if (!cert) {
    return cert.error();
  }
  X509* x = cert->get();
  CertificateInfo info;
  info.subject = name_text(X509_get_subject_name(x));
  info.common_name = common_name(X509_get_subject_name(x));
  info.issuer = name_text(X509_get_issuer_name(x));
  read_alt_names(x, info);
  info.not_before = time_of(X509_get0_notBefore(x));
  info.not_after = time_of(X509_get0_notAfter(x));
  info.thumbprint = ossl::hex(ossl::sha1(der.first(used)));
  info.serial = serial_hex(x);
  info.key_bits = ossl::rsa_bytes(X509_get0_pubkey(x)) * 8;
  info.is_ca = X509_check_ca(x) != 0;
  info.self_signed = X509_self_signed(x, 0) == 1;
  info.has_key_usage = (X509_get_extension_flags(x) & EXFLAG_KUSAGE) != 0;
  info.key_usage = info.has_key_usage ? X509_get_key_usage(x) : 0;
  return info;
}

Result<ByteString> leaf_certificate(ByteSpan der) {
  std::size_t used = 0;
  auto cert = ossl::load_certificate(der, &used);
  if (!cert) {
    return cert.error();
  }
  return ByteString(der.first(used));
}

Result<ByteString> read_certificate_file(const std::filesystem::path& path) {
  auto bytes = read_all(path);
  if (!bytes) {
    return bytes.error();
  }
  auto cert = ossl::load_certificate_file_bytes(*bytes);
  if (!cert) {
    return cert.error().with_context(path.string());
  }
  return ByteString(ossl::der_of(cert->get()));
}

Result<Bytes> read_crl_file(const std::filesystem::path& path) {
  auto bytes = read_all(path);
  if (!bytes) {
    return bytes.error();
  }
  auto crl = ossl::load_crl_bytes(*bytes);
  if (!crl) {
    return crl.error().with_context(path.string());
  }
  return ossl::der_of(crl->get());
}

Result<Bytes> read_private_key_file(const std::filesystem::path& path) {
  auto bytes = read_all(path);
  if (!bytes) {
    return bytes.error();
  }
  auto key = ossl::load_private_key(*bytes);
  if (!key) {
    return key.error().with_context(path.string());
  }
  return ossl::private_key_der(key->get());
}

Status write_file(const std::filesystem::path& path, ByteSpan bytes, bool secret) {
  // Write a temporary file and rename it, so a reader never sees half a certificate.
  const std::filesystem::path temporary = path.string() + ".tmp";
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, secret ? 0600 : 0644);
  if (fd < 0) {
    return make_error(Errc::io, fmt::format("cannot write {}: {}", temporary.string(), std::strerror(errno)));
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n <= 0) {
      const int error = errno;
      ::close(fd);
      return make_error(Errc::io,
                        fmt::format("cannot write {}: {}", temporary.string(), std::strerror(error)));
    }
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    return make_error(Errc::io, fmt::format("cannot rename {}: {}", temporary.string(), ec.message()));
  }
  return {};
}

Status write_private_key_file(const std::filesystem::path& path, ByteSpan pkcs8_der) {
  auto key = ossl::load_private_key(pkcs8_der);
  if (!key) {
    return key.error();
  }
  auto pem = ossl::private_key_pem(key->get());
  if (!pem) {
    return pem.error();
  }
  return write_file(path, ByteSpan(reinterpret_cast<const std::uint8_t*>(pem->data()), pem->size()), true);
}

std::string certificate_pem(ByteSpan der) {
  auto cert = ossl::load_certificate(der);
  return cert ? ossl::pem_of(cert->get()) : std::string();
}

}  // namespace sf::opcua::security
