// The client's side of OPC UA security (OPC 10000-2 §4): which endpoint to use (OPC 10000-4 §5.4.4), its own
// application instance certificate, how it checks the server's certificate, and who it logs in
// as (§5.6.3, §7.40).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua {

struct ClientSecurity {
  // The endpoint: a policy URI and mode. With an empty policy_uri the client asks the server
  // (GetEndpoints) and takes its most secure endpoint it supports (highest securityLevel).
  // None/None connects without discovery (GetEndpoints is skipped).
  std::string policy_uri = std::string(kSecurityPolicyNoneUri);
  MessageSecurityMode mode = MessageSecurityMode::None;
  // Own certificate (subjectAltName URI = ClientConfig::application_uri) and key; required for
  // policies other than None.
  SecurityCredentials credentials;
  // Checks the server's certificate from GetEndpoints (e.g. CertificateValidator::validate of
  // the client's PKI); nullptr accepts any. The client also checks that its ApplicationUri is
  // the endpoint's.
  std::function<Status(const ByteString& certificate)> validate_server_certificate;
};

// Who the session belongs to.
struct UserIdentity {
  UserTokenType type = UserTokenType::Anonymous;
  std::string user_name;            // UserName
  std::string password;             // UserName: encrypted for the server as the token policy says
  SecurityCredentials certificate;  // Certificate: the user's certificate and key

  static UserIdentity anonymous() { return {}; }
  static UserIdentity user(std::string name, std::string password) {
    return {UserTokenType::UserName, std::move(name), std::move(password), {}};
  }
  static UserIdentity x509(SecurityCredentials credentials) {
    return {UserTokenType::Certificate, {}, {}, std::move(credentials)};
  }
};

// OPC 10000-4 §5.4.4: the endpoint matching `policy_uri` and `mode` (empty policy: the highest
// securityLevel among the policies this stack implements, of `mode` unless that is None; among
// equal levels SignAndEncrypt before Sign, then the stronger policy) with the UA-TCP transport
// profile and a user token policy for `user`; BadSecurityPolicyRejected when the server offers
// none that fits.
Result<EndpointDescription> select_endpoint(const std::vector<EndpointDescription>& endpoints,
                                            std::string_view policy_uri, MessageSecurityMode mode,
                                            UserTokenType user = UserTokenType::Anonymous);

}  // namespace sf::opcua
