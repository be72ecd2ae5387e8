// Security options of the opcua commands (OPC 10000-2 §4): the PKI folder, endpoints, users and
// the identity of command-line clients, applied by the library (sf/opcua/*/security_setup.hpp).
// The server defaults to SignAndEncrypt and Sign with user authentication; one installation's
// server and clients share a PKI folder whose own certificate is made (and trusted) on first use,
// so a demo on one machine needs no setup.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/client/security_setup.hpp"
#include "sf/opcua/security/provisioning.hpp"
#include "sf/opcua/server/security_setup.hpp"

namespace sf::app {

// The settings with the PKI folder shown in --help.
struct ServerSecurityOptions : opcua::server::ServerSecuritySettings {
  ServerSecurityOptions() { pki = opcua::security::default_pki_dir(); }
};
void add_server_security_options(CLI::App& cmd, ServerSecurityOptions& o);
// server::configure_server_security with these options. `demo`: without --users, anonymous users
// are operators. Returns a line describing the result for stderr.
Result<std::string> apply_server_security(const ServerSecurityOptions& o, bool demo,
                                          opcua::server::ServerConfig& config);

// The settings with the PKI folder shown in --help, and the password in a file (or asked for).
struct ClientSecurityOptions : opcua::ClientSecuritySettings {
  ClientSecurityOptions() { pki = opcua::security::default_pki_dir(); }
  std::string password_file;
};
void add_client_security_options(CLI::App& cmd, ClientSecurityOptions& o);
// configure_client_security with these options, the password read from --password-file or asked
// for.
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
