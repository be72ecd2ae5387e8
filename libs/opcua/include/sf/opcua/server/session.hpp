// Sessions of the server (OPC 10000-4 §5.6): CreateSession, ActivateSession, CloseSession, the
// per-request checks every other service goes through, and timeouts. Pure logic over a Clock;
// the Server calls it on its loop thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/server/services.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua::server {

struct SessionLimits {
  std::size_t max_sessions = 100;
  double min_session_timeout_ms = 10'000;
  double max_session_timeout_ms = 3'600'000;
  std::size_t max_browse_continuation_points = 10;
  // Part 4 §5.6.2: "maxRequestMessageSize"; 0 = no limit.
  std::uint32_t max_request_message_size = 0;
};

// The identity an ActivateSession established (OPC 10000-4 §5.6.3, §7.40).
struct SessionIdentity {
  UserTokenType token_type = UserTokenType::Anonymous;
  std::string policy_id;
  std::string user_name;               // UserName, and the user an X509 certificate maps to
  std::string certificate_thumbprint;  // X509
  std::vector<std::string> roles;      // from the users file (anonymous: the anonymous role)
};

struct Session {
  NodeId session_id;            // public (e.g. in diagnostics)
  NodeId authentication_token;  // secret: 32 random bytes, proves the session in each request
  std::string name;
  ApplicationDescription client_description;
  double timeout_ms = 0;
  Clock::time_point last_activity{};
  std::uint32_t channel_id = 0;  // the channel the session is bound to
  bool activated = false;
  ByteString server_nonce;
  // The security of the channel that created it (OPC 10000-4 §5.6.2): a later ActivateSession
  // must come over a channel with the same policy, mode and client certificate.
  std::string security_policy_uri;
  MessageSecurityMode security_mode = MessageSecurityMode::None;
  ByteString client_certificate;  // leaf DER; null for SecurityPolicy None
  SessionIdentity identity;
  // What the user may do (nullptr: everything the nodes allow).
  std::shared_ptr<const UserContext> user;
  std::vector<std::string> locale_ids;
  BrowseContinuations continuations;

  explicit Session(std::size_t max_continuations) : continuations(max_continuations) {}
};

class SessionManager {
 public:
  SessionManager(const Clock& clock, SessionLimits limits);

  // Creates a session bound to channel_id with the revised timeout; BadTooManySessions at the
  // limit. The response's session fields are filled by the caller from the returned Session.
  Result<Session*> create(const CreateSessionRequest& request, std::uint32_t channel_id);

  // Part 4 §5.6.3: the session an ActivateSession names (BadSessionIdInvalid); the first
  // activation must come over the channel that created it (BadSecureChannelIdInvalid). Changes
  // nothing: the caller checks signatures and the identity token first.
  Result<Session*> find_for_activation(const ActivateSessionRequest& request, std::uint32_t channel_id);
  // Activates the session for a checked identity over channel_id (a later activation may move
  // the session to a new channel, e.g. after a reconnect, but the user must not change:
  // BadIdentityChangeNotSupported) and issues a new server nonce.
  Result<Session*> complete_activation(Session& session, SessionIdentity identity,
                                       const ActivateSessionRequest& request, std::uint32_t channel_id);

  // The session a service request belongs to (authenticationToken of the request header):
  // BadSessionIdInvalid when unknown, BadSecureChannelIdInvalid when it is bound to another
  // channel, BadSessionNotActivated before ActivateSession. Refreshes its timeout.
  Result<Session*> find(const RequestHeader& header, std::uint32_t channel_id);

  // CloseSession: like find, but a not yet activated session may be closed too.
  Result<Session*> find_for_close(const RequestHeader& header, std::uint32_t channel_id);

  void remove(const NodeId& authentication_token);

  // Sessions whose timeout passed without a request; they are removed and returned (their
  // tokens), so the caller can delete their subscriptions.
  std::vector<NodeId> expire();

  [[nodiscard]] std::size_t size() const { return sessions_.size(); }
  // Whether an activated session is bound to the channel.
  [[nodiscard]] bool has_activated_session(std::uint32_t channel_id) const;
  [[nodiscard]] const SessionLimits& limits() const { return limits_; }
  // The nearest time a session may expire (for the caller's timer).
  [[nodiscard]] Clock::time_point next_expiry() const;

 private:
  Result<Session*> lookup(const RequestHeader& header, std::uint32_t channel_id, bool require_activated);

  const Clock& clock_;
  SessionLimits limits_;
  std::unordered_map<NodeId, std::unique_ptr<Session>> sessions_;
  std::uint32_t next_session_number_ = 1;
};

// `size` bytes from the kernel's CSPRNG (getrandom(2)).
Bytes random_bytes(std::size_t size);

}  // namespace sf::opcua::server
