// Certificates and keys for the TLS tests of web servers (libs/web, libs/dashboard), made at test
// time by the OPC UA security library (sf::web_testing_tls links it) as PEM files in a temporary
// directory: a CA and the server's certificate it issued for 127.0.0.1 and localhost, and the
// files a server must refuse.
#pragma once

#include <filesystem>

#include "sf/testing/temp_dir.hpp"

namespace sf::web::testing {

struct TlsFiles {
  sf::testing::TempDir dir{"sf-web-tls"};
  std::filesystem::path ca = dir.path() / "ca.pem";               // what clients trust
  std::filesystem::path chain = dir.path() / "server-chain.pem";  // the server's certificate, then the CA's
  std::filesystem::path key = dir.path() / "server-key.pem";
  std::filesystem::path expired_chain = dir.path() / "expired-chain.pem";  // the same key, valid yesterday
  std::filesystem::path other_key = dir.path() / "other-key.pem";          // matches no certificate here
  std::filesystem::path not_pem = dir.path() / "not.pem";

  // Made once per test binary (RSA keys are slow to make).
  static const TlsFiles& get();

 private:
  TlsFiles();
};

}  // namespace sf::web::testing
