// A server's security from settings as a user or a configuration file gives them (the `opcua
// server` command, the cloud's aggregating server): endpoints, PKI, users and anonymous access.
#pragma once

#include <string>

#include "sf/core/result.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::opcua::server {

struct ServerSecuritySettings {
  std::string pki;                     // PKI folder (security::default_pki_dir())
  std::string modes = "sign,encrypt";  // comma list of none, sign, encrypt
  std::string policies = "Basic256Sha256,Aes128_Sha256_RsaOaep,Aes256_Sha256_RsaPss";
  std::string users;      // users file, or none
  std::string anonymous;  // a role, "off", or "" for the default (off with users, else viewer)
};

// Fills config.security (and the ApplicationUri from the certificate, OPC 10000-4 §6.1.3),
// making the PKI folder and its own certificate when needed. `demo`: without users, anonymous
// users are operators. Returns a line that describes the result.
Result<std::string> configure_server_security(const ServerSecuritySettings& settings, bool demo,
                                              ServerConfig& config);

}  // namespace sf::opcua::server
