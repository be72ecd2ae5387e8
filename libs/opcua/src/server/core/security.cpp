// Endpoint security, user token policies and role-based access (OPC 10000-4 §7.14, §7.41;
// OPC 10000-3 §4.8).
#include "sf/opcua/server/security.hpp"

#include <algorithm>

#include "sf/opcua/security/policies.hpp"

namespace sf::opcua::server {

namespace sec = ::sf::opcua::security;
namespace {

constexpr std::string_view kAnonymousPolicyId = "anonymous";
constexpr std::string_view kUserNamePolicyId = "username";
constexpr std::string_view kCertificatePolicyId = "certificate";

bool is_none(std::string_view policy_uri) {
  return policy_uri.empty() || policy_uri == kSecurityPolicyNoneUri;
}

}  // namespace

std::vector<EndpointSecurity> ServerSecurity::endpoints_for(const std::vector<std::string>& policy_uris,
                                                            const std::vector<MessageSecurityMode>& modes) {
  std::vector<EndpointSecurity> out;
  for (const auto mode : modes) {
    if (mode == MessageSecurityMode::None) {
      out.push_back(EndpointSecurity{});
      continue;
    }
    for (const auto& uri : policy_uris) {
      out.push_back(EndpointSecurity{uri, mode});
    }
  }
  return out;
}

bool ServerSecurity::offers(std::string_view policy_uri, MessageSecurityMode mode) const {
  const std::string uri = is_none(policy_uri) ? std::string(kSecurityPolicyNoneUri) : std::string(policy_uri);
  return std::any_of(endpoints.begin(), endpoints.end(),
                     [&](const EndpointSecurity& e) { return e.policy_uri == uri && e.mode == mode; });
}

std::shared_ptr<const sec::UserDatabase> ServerSecurity::current_users() const {
  return users_file ? users_file->current() : users;
}

std::vector<UserTokenPolicy> user_token_policies(const ServerSecurity& security,
                                                 const EndpointSecurity& endpoint) {
  std::vector<UserTokenPolicy> out;
  if (security.allow_anonymous) {
    UserTokenPolicy anonymous;
    anonymous.policy_id = std::string(kAnonymousPolicyId);
    anonymous.token_type = UserTokenType::Anonymous;
    out.push_back(anonymous);
  }
  // Secrets are encrypted (and X509 tokens signed) with the endpoint's policy; on a None
  // endpoint with Basic256Sha256 and the server certificate, never in clear.
  const bool none = is_none(endpoint.policy_uri);
  const auto users = security.current_users();
  if (!users || (none && security.credentials.certificate.empty())) {
    return out;
  }
  const std::string token_policy = none ? std::string(sec::kBasic256Sha256Uri) : endpoint.policy_uri;
  if (users->has_password_users()) {
    UserTokenPolicy user;
    user.policy_id = std::string(kUserNamePolicyId);
    user.token_type = UserTokenType::UserName;
    user.security_policy_uri = token_policy;
    out.push_back(user);
  }
  if (users->has_certificate_users()) {
    UserTokenPolicy certificate;
    certificate.policy_id = std::string(kCertificatePolicyId);
    certificate.token_type = UserTokenType::Certificate;
    certificate.security_policy_uri = token_policy;
    out.push_back(certificate);
  }
  return out;
}

std::uint8_t security_level(const EndpointSecurity& endpoint) {
  const int mode = endpoint.mode == MessageSecurityMode::SignAndEncrypt ? 100
                   : endpoint.mode == MessageSecurityMode::Sign         ? 50
                                                                        : 0;
  return static_cast<std::uint8_t>(mode + sec::policy_strength(endpoint.policy_uri));
}

RoleAccess::RoleAccess(const AddressSpace& space, std::vector<sec::Role> roles)
    : space_(space), roles_(std::move(roles)) {
  for (const auto permission : {sec::Permission::Read, sec::Permission::Write, sec::Permission::Call}) {
    grants_all_.at(static_cast<std::size_t>(permission)) =
        std::any_of(roles_.begin(), roles_.end(), [permission](const sec::Role& role) {
          const auto& patterns = role.patterns(permission);
          return !patterns.empty() && patterns.front() == "*";
        });
  }
}

std::string RoleAccess::node_text(const NodeId& node) const {
  std::string text = to_string(node);
  if (node.namespace_index != 0) {
    text.erase(0, text.find(';') + 1);  // "ns=2;s=X" → "s=X"
  }
  const auto& namespaces = space_.namespaces();
  const std::string uri = node.namespace_index < namespaces.size() ? namespaces[node.namespace_index] : "";
  return "nsu=" + uri + ";" + text;
}

bool RoleAccess::allows(sec::Permission permission, const Node& node) const {
  if (grants_all_.at(static_cast<std::size_t>(permission))) {
    return true;
  }
  const std::string text = node_text(node.node_id);
  return std::any_of(roles_.begin(), roles_.end(),
                     [&](const sec::Role& role) { return sec::allowed(role.patterns(permission), text); });
}

bool RoleAccess::can_read(const Node& node) const {
  return allows(sec::Permission::Read, node);
}

bool RoleAccess::can_write(const Node& node, AttributeId /*attribute*/) const {
  return allows(sec::Permission::Write, node);
}

bool RoleAccess::can_browse(const Node& /*node*/) const {
  return true;
}

bool RoleAccess::can_call(const Node& method) const {
  return allows(sec::Permission::Call, method);
}

}  // namespace sf::opcua::server
