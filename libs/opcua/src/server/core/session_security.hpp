// The security steps of CreateSession and ActivateSession (OPC 10000-4 §5.6.2, §5.6.3): the
// client certificate and nonce, the server's and the client's signatures, and the user identity
// token. Internal to sf_opcua_server (used by the Dispatcher).
#pragma once

#include <memory>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/server/security.hpp"
#include "sf/opcua/server/session.hpp"
#include "sf/opcua/transport/server_transport.hpp"

namespace sf::opcua::server::detail {

// The channel's policy and mode are one of the server's endpoints (BadSecurityPolicyRejected
// otherwise: a None channel is for discovery only unless None is offered).
Status check_endpoint(const ServerSecurity& security, const ChannelInfo& channel);

// CreateSession on a secured channel: the client certificate is the channel's, its URI the
// client description's, the nonce long enough; then the server signs clientCertificate +
// clientNonce. Records the channel's security in the session.
Status secure_create_session(const ServerSecurity& security, const ChannelInfo& channel,
                             const CreateSessionRequest& request, Session& session,
                             CreateSessionResponse& response);

// ActivateSession: the channel matches the session's security, the client signature over
// serverCertificate + serverNonce verifies (BadApplicationSignatureInvalid), and the identity
// token authenticates a user (BadIdentityTokenInvalid, BadIdentityTokenRejected,
// BadUserAccessDenied, BadUserSignatureInvalid).
Result<SessionIdentity> authenticate_activation(const ServerSecurity& security, const ChannelInfo& channel,
                                                const Session& session, const ActivateSessionRequest& request,
                                                const Clock& clock);

// What the identity may do: nullptr for unrestricted anonymous access, else its roles' rights.
std::shared_ptr<const UserContext> access_for(const ServerSecurity& security, const AddressSpace& space,
                                              const SessionIdentity& identity);

}  // namespace sf::opcua::server::detail
