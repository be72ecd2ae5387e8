// Security options of the opcua commands (issue 6): the PKI folder, endpoints, users and the
// identity of command-line clients. The server defaults to SignAndEncrypt and Sign with user
// authentication; one installation's server and clients share a PKI folder whose own
// certificate is made (and trusted) on first use, so a demo on one machine needs no setup.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::app {

// $XDG_STATE_HOME/smartfactory/opcua/pki (~/.local/state/... without it).
std::string default_pki_dir();
// urn:<host name>:smartfactory and a self-signed certificate for it: CN smartfactory@<host>,
// DNS <host> and localhost, IP 127.0.0.1 and ::1, plus `extra_host` (a name or an address).
opcua::security::CertificateRequest own_certificate_request(const std::string& extra_host = "");

struct ServerSecurityOptions {
  std::string pki = default_pki_dir();
  std::string modes = "sign,encrypt";
  std::string policies = "Basic256Sha256,Aes128_Sha256_RsaOaep,Aes256_Sha256_RsaPss";
  std::string users;
  std::string anonymous;  // a role, "off", or "" for the default
};
void add_server_security_options(CLI::App& cmd, ServerSecurityOptions& o);
// Fills config.security (and the ApplicationUri from the certificate), creating the PKI folder
// and own certificate when needed. `demo`: without --users, anonymous users are operators.
// Returns a line describing the result for stderr.
Result<std::string> apply_server_security(const ServerSecurityOptions& o, bool demo,
                                          opcua::server::ServerConfig& config);

struct ClientSecurityOptions {
  std::string pki = default_pki_dir();
  std::string security = "auto";
  std::string user;
  std::string password_file;
  std::string user_certificate;
  std::string user_key;
};
void add_client_security_options(CLI::App& cmd, ClientSecurityOptions& o);
Status apply_client_security(const ClientSecurityOptions& o, opcua::ClientConfig& config);
// What to tell the user when connecting failed for a security reason (e.g. how to trust the
// server's certificate); empty when there is nothing to add.
std::string security_hint(const ClientSecurityOptions& o, const Error& error);

// `opcua pki init|list|trust|reject` (opcua_pki.cpp) and `opcua users add|remove|list`
// (opcua_users.cpp).
void register_opcua_pki(CLI::App& group, CommandResult& result);
void register_opcua_users(CLI::App& group, CommandResult& result);

// A password from FILE (its first line), else prompted on the terminal without echo, else the
// first line of stdin.
Result<std::string> read_password(const std::string& file, const std::string& prompt);

}  // namespace sf::app
