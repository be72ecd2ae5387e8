// Certificates made at test time for the security tests (RSA key generation is slow, so each
// key is made once per test binary), and a temporary PKI folder.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "sf/opcua/security/certificate.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::opcua::security::test {

// A PKCS#8 RSA key of `bits`, the same one for every call with the same name.
inline const Bytes& test_key(const std::string& name, unsigned bits = 2048) {
  static std::map<std::string, Bytes> keys;
  auto it = keys.find(name);
  if (it == keys.end()) {
    CertificateRequest request;
    request.application_uri = "urn:test:keygen";
    request.key_bits = bits;
    auto made = create_certificate(request);
    EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().message);
    it = keys.emplace(name, made.ok() ? made->private_key : Bytes{}).first;
  }
  return it->second;
}

// An application instance certificate for `uri` with the named key.
inline SecurityCredentials app_certificate(const std::string& uri, const std::string& key = "server",
                                           unsigned bits = 2048, const SecurityCredentials* issuer = nullptr,
                                           CertificateRequest request = {}) {
  request.application_uri = uri;
  if (request.common_name.empty()) {
    request.common_name = uri.substr(uri.rfind(':') + 1);
  }
  request.dns_names = {"localhost"};
  request.ip_addresses = {"127.0.0.1"};
  request.private_key = test_key(key, bits);
  auto made = create_certificate(request, issuer);
  EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().message);
  return made.ok() ? *made : SecurityCredentials{};
}

inline SecurityCredentials ca_certificate(const std::string& name,
                                          const SecurityCredentials* issuer = nullptr) {
  CertificateRequest request;
  request.common_name = name;
  request.ca = true;
  request.private_key = test_key("ca-" + name);
  auto made = create_certificate(request, issuer);
  EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().message);
  return made.ok() ? *made : SecurityCredentials{};
}

using TempDir = sf::testing::TempDir;

}  // namespace sf::opcua::security::test
