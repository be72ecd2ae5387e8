#include "opcua_security.hpp"

#include <termios.h>
#include <unistd.h>

#include <fstream>
#include <iostream>

#include <fmt/format.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::app {

namespace ua = sf::opcua;

void add_server_security_options(CLI::App& cmd, ServerSecurityOptions& o) {
  cmd.add_option("--security", o.modes,
                 "Security modes of the endpoints, a comma list of none, sign, encrypt (None only when asked "
                 "for; a None channel always serves GetEndpoints)")
      ->capture_default_str();
  cmd.add_option("--policies", o.policies, "Security policies of the sign and encrypt endpoints")
      ->capture_default_str();
  cmd.add_option(
         "--pki", o.pki,
         "PKI folder (own/, trusted/, issuers/, rejected/; made with a self-signed certificate on first "
         "use; see `opcua pki`)")
      ->capture_default_str();
  cmd.add_option("--users", o.users,
                 "Users file: names with salted password hashes or certificate thumbprints, and roles "
                 "(`opcua users add`)");
  cmd.add_option("--anonymous", o.anonymous,
                 "Role of anonymous users (viewer, operator, engineer, or a role of the users file), or off. "
                 "Default: off with --users, operator with --demo-model, else viewer");
}

Result<std::string> apply_server_security(const ServerSecurityOptions& o, bool demo,
                                          opcua::server::ServerConfig& config) {
  return ua::server::configure_server_security(o, demo, config);
}

void add_client_security_options(CLI::App& cmd, ClientSecurityOptions& o) {
  cmd.add_option("--security", o.security,
                 "POLICY:MODE (e.g. Basic256Sha256:SignAndEncrypt, Aes256_Sha256_RsaPss:Sign), none, or auto "
                 "(the most secure endpoint the server offers)")
      ->capture_default_str();
  cmd.add_option("--pki", o.pki, "PKI folder with our certificate and the servers we trust (see `opcua pki`)")
      ->capture_default_str();
  cmd.add_option("--user", o.user, "Log in as this user (password from --password-file or asked for)");
  cmd.add_option("--password-file", o.password_file, "File whose first line is the password of --user");
  cmd.add_option("--user-cert", o.user_certificate, "Log in with this X.509 user certificate (DER or PEM)");
  cmd.add_option("--user-key", o.user_key, "The private key of --user-cert (PEM or DER)")
      ->needs("--user-cert");
}

Status apply_client_security(const ClientSecurityOptions& o, opcua::ClientConfig& config) {
  ua::ClientSecuritySettings settings = o;  // NOLINT(cppcoreguidelines-slicing): the settings part
  if (!o.user.empty() && o.user_certificate.empty()) {
    auto password = read_password(o.password_file, fmt::format("Password for {}: ", o.user));
    if (!password) {
      return password.error();
    }
    settings.password = std::move(*password);
  }
  return ua::configure_client_security(settings, config);
}

std::string security_hint(const ClientSecurityOptions& o, const Error& error) {
  const ua::StatusCode code = ua::status_of(error);
  if (code == ua::status::BadCertificateUntrusted || code == ua::status::BadCertificateChainIncomplete) {
    return fmt::format(
        "the server's certificate is not trusted; it was copied to {}/rejected/certs. If it is the right "
        "server: smartfactory opcua pki trust --pki {} <thumbprint>  (smartfactory opcua pki list --pki {})",
        o.pki, o.pki, o.pki);
  }
  if (code == ua::status::BadSecurityChecksFailed) {
    return fmt::format(
        "the server refused our certificate ({}/own/certs/cert.der); it is in the server's rejected/ folder, "
        "where its operator can trust it (smartfactory opcua pki trust)",
        o.pki);
  }
  if (code == ua::status::BadUserAccessDenied || code == ua::status::BadIdentityTokenRejected) {
    return "wrong user name or password, or the server does not accept this kind of login here";
  }
  return {};
}

Result<std::string> read_password(const std::string& file, const std::string& prompt) {
  std::string password;
  if (!file.empty()) {
    std::ifstream in(file);
    if (!in || !std::getline(in, password)) {
      return make_error(Errc::io, fmt::format("cannot read a password from {}", file));
    }
    return password;
  }
  if (::isatty(STDIN_FILENO) == 1) {
    std::cerr << prompt << std::flush;
    termios old{};
    ::tcgetattr(STDIN_FILENO, &old);
    termios quiet = old;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    ::tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
    std::getline(std::cin, password);
    ::tcsetattr(STDIN_FILENO, TCSANOW, &old);
    std::cerr << "\n";
    return password;
  }
  if (!std::getline(std::cin, password)) {
    return make_error(Errc::io, "no password on stdin (use --password-file)");
  }
  return password;
}

}  // namespace sf::app
