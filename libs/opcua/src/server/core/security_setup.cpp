#include "sf/opcua/server/security_setup.hpp"

#include <algorithm>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/provisioning.hpp"
#include "sf/opcua/security/users.hpp"

namespace sf::opcua::server {
namespace {

std::string mode_names(const std::vector<MessageSecurityMode>& modes) {
  std::string out;
  for (const auto mode : modes) {
    out += (out.empty() ? "" : ", ") + std::string(to_string(mode));
  }
  return out;
}

}  // namespace

Result<std::string> configure_server_security(const ServerSecuritySettings& settings, bool demo,
                                              ServerConfig& config) {
  ServerSecuritySettings o = settings;
  if (o.pki.empty()) {
    o.pki = security::default_pki_dir();
  }
  auto modes = security::parse_security_modes(o.modes);
  auto policies =
      modes ? security::parse_security_policies(o.policies) : Result<std::vector<std::string>>(modes.error());
  if (!policies) {
    return policies.error();
  }
  ServerSecurity& out = config.security;
  out.endpoints = ServerSecurity::endpoints_for(*policies, *modes);
  const bool secure = std::any_of(modes->begin(), modes->end(),
                                  [](MessageSecurityMode m) { return m != MessageSecurityMode::None; });
  std::shared_ptr<const security::UserDatabase> users;
  if (!o.users.empty()) {
    auto file = security::UsersFile::open(o.users);  // re-read when `opcua users` changes it
    if (!file) {
      return file.error();
    }
    out.users_file = *file;
    users = out.current_users();
  }
  std::string pki_text = "no PKI";
  if (secure || users) {
    auto own = security::own_credentials(o.pki, config.advertised_host);
    if (!own) {
      return own.error();
    }
    auto info = security::inspect_certificate(own->certificate.span());
    if (!info) {
      return info.error();
    }
    // The server is the application its certificate names (OPC 10000-4 §6.1.3).
    config.identity.application_uri = info->application_uri;
    out.credentials = std::move(*own);
    out.validator = std::make_shared<security::CertificateValidator>(security::PkiStore(o.pki));
    pki_text = fmt::format("PKI {} (certificate {})", o.pki, info->thumbprint.substr(0, 12));
  }
  std::string anonymous = o.anonymous.empty() ? (users ? "off" : demo ? "operator" : "viewer") : o.anonymous;
  out.allow_anonymous = anonymous != "off";
  out.anonymous_role = out.allow_anonymous ? anonymous : "";
  const security::UserDatabase builtin;
  if (out.allow_anonymous && (users ? users->role(anonymous) : builtin.role(anonymous)) == nullptr) {
    return make_error(Errc::invalid_argument, fmt::format("anonymous users: unknown role '{}'", anonymous));
  }
  // Policies only matter to the endpoints that sign.
  const std::string endpoints =
      secure ? fmt::format("{} with {}", mode_names(*modes), o.policies) : mode_names(*modes);
  return fmt::format(
      "security: {}; {}; {}; anonymous users: {}", endpoints, pki_text,
      users ? fmt::format("{} users from {} (re-read when it changes)", users->users().size(), o.users)
            : "no users",
      anonymous);
}

}  // namespace sf::opcua::server
