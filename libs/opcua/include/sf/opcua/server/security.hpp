// What a server offers and whom it lets in (OPC 10000-2 §4): the endpoints (security policy × mode),
// its application instance certificate, how client certificates are validated, the users with
// their roles, and anonymous access. The default is an open server: SecurityPolicy None only,
// anonymous users who may do everything.
//
// A SecureChannel with SecurityPolicy None is always accepted for discovery (GetEndpoints,
// FindServers; OPC 10000-4 §5.4); sessions only on the endpoints listed here.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/users.hpp"
#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/server/services.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua::server {

// One security configuration of the server's endpoints (OPC 10000-4 §7.14).
struct EndpointSecurity {
  std::string policy_uri = std::string(kSecurityPolicyNoneUri);
  MessageSecurityMode mode = MessageSecurityMode::None;
  friend bool operator==(const EndpointSecurity&, const EndpointSecurity&) = default;
};

struct ServerSecurity {
  std::vector<EndpointSecurity> endpoints{EndpointSecurity{}};
  // Application instance certificate (its subjectAltName URI must be the server's
  // ApplicationUri) and key; required for policies other than None.
  SecurityCredentials credentials;
  // Client certificates; nullptr accepts any well-formed one (tests).
  std::shared_ptr<security::CertificateValidator> validator;
  // UserName and X509 users with their roles; nullptr: none (anonymous only).
  std::shared_ptr<const security::UserDatabase> users;
  // Or the users of a file, re-read when it changes; replaces `users` when set.
  std::shared_ptr<security::UsersFile> users_file;
  bool allow_anonymous = true;
  // The role of anonymous sessions; "" = no restriction beyond the nodes' own access levels.
  std::string anonymous_role;

  // Endpoints with policy `policy_uri` and `mode`, e.g. every policy × {Sign, SignAndEncrypt}.
  static std::vector<EndpointSecurity> endpoints_for(const std::vector<std::string>& policy_uris,
                                                     const std::vector<MessageSecurityMode>& modes);
  [[nodiscard]] bool offers(std::string_view policy_uri, MessageSecurityMode mode) const;
  // The users in force now (users_file's current users, else `users`; may be nullptr).
  [[nodiscard]] std::shared_ptr<const security::UserDatabase> current_users() const;
};

// OPC 10000-4 §7.41: the user token policies of one endpoint (anonymous if allowed, UserName and
// X509 when users have passwords or certificates). Secrets and signatures of UserName/X509 tokens
// use the endpoint's policy, or Basic256Sha256 on a None endpoint: passwords never travel in clear.
std::vector<UserTokenPolicy> user_token_policies(const ServerSecurity& security,
                                                 const EndpointSecurity& endpoint);
// OPC 10000-4 §7.14 securityLevel: SignAndEncrypt above Sign above None, stronger policies higher.
std::uint8_t security_level(const EndpointSecurity& endpoint);

// The permissions of a set of roles over an address space (node patterns of users.hpp):
// browse always, read/write/call as the roles grant (any role granting is enough).
class RoleAccess final : public UserContext {
 public:
  RoleAccess(const AddressSpace& space, std::vector<security::Role> roles);
  [[nodiscard]] bool can_read(const Node& node) const override;
  [[nodiscard]] bool can_write(const Node& node, AttributeId attribute) const override;
  [[nodiscard]] bool can_browse(const Node& node) const override;
  [[nodiscard]] bool can_call(const Node& method) const override;
  // "nsu=<namespace URI>;<identifier>", the form patterns are written in.
  [[nodiscard]] std::string node_text(const NodeId& node) const;

 private:
  [[nodiscard]] bool allows(security::Permission permission, const Node& node) const;

  const AddressSpace& space_;
  std::vector<security::Role> roles_;
  // Per permission: a role whose first pattern is "*" grants it for every node, so the node's
  // text (formatted per call) is not needed.
  std::array<bool, 3> grants_all_{};
};

}  // namespace sf::opcua::server
