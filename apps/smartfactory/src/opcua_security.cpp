#include "opcua_security.hpp"

#include <arpa/inet.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "sf/core/text.hpp"
#include "sf/net/tcp.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/security/users.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::app {
namespace {

namespace ua = sf::opcua;
namespace sec = sf::opcua::security;
namespace fs = std::filesystem;

bool is_ip(const std::string& text) {
  std::array<unsigned char, 16> buffer{};
  return inet_pton(AF_INET, text.c_str(), buffer.data()) == 1 ||
         inet_pton(AF_INET6, text.c_str(), buffer.data()) == 1;
}

// The non-empty items of a comma-separated list, in lower case.
std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  for (const auto item : split(text, ',')) {
    if (!item.empty()) {
      out.push_back(lower(item));
    }
  }
  return out;
}

Result<ua::MessageSecurityMode> parse_mode(const std::string& text) {
  if (text == "none") {
    return ua::MessageSecurityMode::None;
  }
  if (text == "sign") {
    return ua::MessageSecurityMode::Sign;
  }
  if (text == "encrypt" || text == "signandencrypt") {
    return ua::MessageSecurityMode::SignAndEncrypt;
  }
  return make_error(Errc::invalid_argument,
                    fmt::format("unknown security mode '{}' (none, sign, encrypt / SignAndEncrypt)", text));
}

Result<std::vector<ua::MessageSecurityMode>> parse_modes(const std::string& text) {
  std::vector<ua::MessageSecurityMode> modes;
  for (const auto& item : split_list(text)) {
    auto mode = parse_mode(item);
    if (!mode) {
      return mode.error();
    }
    if (std::find(modes.begin(), modes.end(), *mode) == modes.end()) {
      modes.push_back(*mode);
    }
  }
  if (modes.empty()) {
    return make_error(Errc::invalid_argument, "--security needs at least one of none, sign, encrypt");
  }
  return modes;
}

Result<std::vector<std::string>> parse_policies(const std::string& text) {
  std::vector<std::string> uris;
  for (const auto& item : split_list(text)) {
    auto uri = sec::policy_uri_from_name(item);
    if (!uri || *uri == ua::kSecurityPolicyNoneUri) {
      return make_error(Errc::invalid_argument, fmt::format("unknown security policy '{}'", item));
    }
    uris.push_back(*uri);
  }
  return uris;
}

// The own certificate of the PKI folder, made on first use.
Result<ua::SecurityCredentials> own_credentials(const std::string& pki, const std::string& extra_host) {
  sec::PkiStore store(pki);
  auto own = store.ensure_own(own_certificate_request(extra_host));
  if (!own) {
    return own.error().with_context("PKI " + pki);
  }
  return own;
}

std::string mode_names(const std::vector<ua::MessageSecurityMode>& modes) {
  std::string out;
  for (const auto mode : modes) {
    out += (out.empty() ? "" : ", ") + std::string(ua::to_string(mode));
  }
  return out;
}

}  // namespace

std::string default_pki_dir() {
  const char* state = std::getenv("XDG_STATE_HOME");
  if (state != nullptr && *state != '\0') {
    return (fs::path(state) / "smartfactory" / "opcua" / "pki").string();
  }
  const char* home = std::getenv("HOME");
  if (home != nullptr && *home != '\0') {
    return (fs::path(home) / ".local" / "state" / "smartfactory" / "opcua" / "pki").string();
  }
  return fmt::format("/tmp/smartfactory-{}/opcua/pki", ::getuid());
}

opcua::security::CertificateRequest own_certificate_request(const std::string& extra_host) {
  const std::string host = sf::net::host_name();
  sec::CertificateRequest request;
  request.application_uri = fmt::format("urn:{}:smartfactory", host);
  request.common_name = fmt::format("smartfactory@{}", host);
  request.dns_names = {host};
  if (host != "localhost") {
    request.dns_names.emplace_back("localhost");
  }
  request.ip_addresses = {"127.0.0.1", "::1"};
  if (!extra_host.empty() && extra_host != host && extra_host != "localhost") {
    auto& list = is_ip(extra_host) ? request.ip_addresses : request.dns_names;
    if (std::find(list.begin(), list.end(), extra_host) == list.end()) {
      list.push_back(extra_host);
    }
  }
  return request;
}

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
  auto modes = parse_modes(o.modes);
  auto policies = modes ? parse_policies(o.policies) : Result<std::vector<std::string>>(modes.error());
  if (!policies) {
    return policies.error();
  }
  ua::server::ServerSecurity& security = config.security;
  security.endpoints = ua::server::ServerSecurity::endpoints_for(*policies, *modes);
  const bool secure = std::any_of(modes->begin(), modes->end(), [](ua::MessageSecurityMode m) {
    return m != ua::MessageSecurityMode::None;
  });
  std::shared_ptr<sec::UserDatabase> users;
  if (!o.users.empty()) {
    auto loaded = sec::UserDatabase::load(o.users);
    if (!loaded) {
      return loaded.error();
    }
    users = std::make_shared<sec::UserDatabase>(std::move(*loaded));
    security.users = users;
  }
  std::string pki_text = "no PKI";
  if (secure || users) {
    auto own = own_credentials(o.pki, config.advertised_host);
    if (!own) {
      return own.error();
    }
    auto info = sec::inspect_certificate(own->certificate.span());
    if (!info) {
      return info.error();
    }
    // The server is the application its certificate names (OPC 10000-4 §6.1.3).
    config.identity.application_uri = info->application_uri;
    security.credentials = std::move(*own);
    security.validator = std::make_shared<sec::CertificateValidator>(sec::PkiStore(o.pki));
    pki_text = fmt::format("PKI {} (certificate {})", o.pki, info->thumbprint.substr(0, 12));
  }
  std::string anonymous = o.anonymous.empty() ? (users ? "off" : demo ? "operator" : "viewer") : o.anonymous;
  security.allow_anonymous = anonymous != "off";
  security.anonymous_role = security.allow_anonymous ? anonymous : "";
  const sec::UserDatabase builtin;
  if (security.allow_anonymous && (users ? users->role(anonymous) : builtin.role(anonymous)) == nullptr) {
    return make_error(Errc::invalid_argument, fmt::format("--anonymous: unknown role '{}'", anonymous));
  }
  return fmt::format(
      "security: {} with {}; {}; {}; anonymous users: {}", mode_names(*modes), o.policies, pki_text,
      users ? fmt::format("{} users from {}", users->users().size(), o.users) : "no users", anonymous);
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
  const std::string wanted = lower(o.security);
  ua::ClientSecurity& security = config.security;
  if (wanted == "none") {
    security.policy_uri = std::string(ua::kSecurityPolicyNoneUri);
    security.mode = ua::MessageSecurityMode::None;
  } else if (wanted == "auto") {
    security.policy_uri.clear();
    security.mode = ua::MessageSecurityMode::None;
  } else {
    const auto colon = wanted.find(':');
    auto policy = sec::policy_uri_from_name(wanted.substr(0, colon));
    auto mode = colon == std::string::npos
                    ? Result<ua::MessageSecurityMode>(ua::MessageSecurityMode::SignAndEncrypt)
                    : parse_mode(wanted.substr(colon + 1));
    if (!policy || !mode) {
      return !policy ? policy.error() : mode.error();
    }
    security.policy_uri = *policy;
    security.mode = *mode;
  }
  if (wanted != "none") {
    auto own = own_credentials(o.pki, "");
    if (!own) {
      return own.error();
    }
    config.application_uri = sec::inspect_certificate(own->certificate.span())->application_uri;
    security.credentials = std::move(*own);
    auto validator = std::make_shared<sec::CertificateValidator>(sec::PkiStore(o.pki));
    security.validate_server_certificate = [validator](const ua::ByteString& c) {
      return validator->validate(c);
    };
  }
  if (!o.user_certificate.empty()) {
    auto certificate = sec::read_certificate_file(o.user_certificate);
    auto key = certificate ? sec::read_private_key_file(o.user_key) : Result<Bytes>(certificate.error());
    if (!key) {
      return key.error();
    }
    config.user = ua::UserIdentity::x509(ua::SecurityCredentials{std::move(*certificate), std::move(*key)});
  } else if (!o.user.empty()) {
    auto password = read_password(o.password_file, fmt::format("Password for {}: ", o.user));
    if (!password) {
      return password.error();
    }
    config.user = ua::UserIdentity::user(o.user, std::move(*password));
  }
  return {};
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
