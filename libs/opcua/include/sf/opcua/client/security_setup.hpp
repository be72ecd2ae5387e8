// A client's security from settings as a user or a configuration file gives them (the `opcua`
// client commands, the cloud gateway's connections): endpoint, own certificate, trusted servers
// and login.
#pragma once

#include <string>

#include "sf/core/result.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::opcua {

struct ClientSecuritySettings {
  std::string pki;                // our certificate and the servers we trust
  std::string security = "auto";  // POLICY:MODE, none, or auto (the most secure endpoint offered)
  std::string user;               // log in as this user with `password`,
  std::string password;
  std::string user_certificate;  // or with this X.509 certificate (DER or PEM)
  std::string user_key;          // and its private key
};

// Fills config.security, its ApplicationUri and user from `settings` (OPC 10000-4 §5.4.4, §7.41);
// the PKI folder and own certificate are made when needed.
Status configure_client_security(const ClientSecuritySettings& settings, ClientConfig& config);

}  // namespace sf::opcua
