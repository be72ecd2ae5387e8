#include <sys/random.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

#include "sf/core/log.hpp"
#include "sf/opcua/server/session.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace {

// Sessions live in the server's own namespace (index 1, the ApplicationUri; OPC 10000-3 §8.2.2).
constexpr std::uint16_t kSessionNamespace = 1;
constexpr std::size_t kTokenBytes = 32;
constexpr std::size_t kNonceBytes = 32;

Clock::duration to_duration(double ms) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(ms));
}

}  // namespace

Bytes random_bytes(std::size_t size) {
  Bytes out(size);
  std::size_t filled = 0;
  while (filled < size) {
    const ssize_t n = getrandom(out.data() + filled, size - filled, 0);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      // getrandom only fails for bad arguments or before the pool is initialised at boot; a
      // session token must never be predictable, so there is no fallback.
      log::get("opcua")->critical("getrandom failed: {}", std::strerror(errno));
      std::abort();
    }
    filled += static_cast<std::size_t>(n);
  }
  return out;
}

SessionManager::SessionManager(const Clock& clock, SessionLimits limits) : clock_(clock), limits_(limits) {}

Result<Session*> SessionManager::create(const CreateSessionRequest& request, std::uint32_t channel_id) {
  if (sessions_.size() >= limits_.max_sessions) {
    log::get("opcua")->warn("CreateSession refused: {} sessions already open", sessions_.size());
    return status_error(status::BadTooManySessions, "the server holds its maximum of " +
                                                        std::to_string(limits_.max_sessions) + " sessions");
  }
  auto session = std::make_unique<Session>(limits_.max_browse_continuation_points);
  session->session_id = NodeId(kSessionNamespace, next_session_number_++);
  session->authentication_token = NodeId(kSessionNamespace, ByteString(random_bytes(kTokenBytes)));
  session->name = request.session_name.is_null()
                      ? std::string("session ") + std::to_string(next_session_number_ - 1)
                      : std::string(request.session_name.view());
  session->client_description = request.client_description;
  // Part 4 §5.6.2: a requested timeout of 0 (or outside the server's range) is revised.
  session->timeout_ms = std::clamp(request.requested_session_timeout > 0 ? request.requested_session_timeout
                                                                         : limits_.max_session_timeout_ms,
                                   limits_.min_session_timeout_ms, limits_.max_session_timeout_ms);
  session->channel_id = channel_id;
  session->last_activity = clock_.now();
  session->server_nonce = ByteString(random_bytes(kNonceBytes));
  Session* raw = session.get();
  sessions_.emplace(raw->authentication_token, std::move(session));
  log::get("opcua")->info("session {} \"{}\" created on channel {} (timeout {} ms)",
                          to_string(raw->session_id), raw->name, channel_id, raw->timeout_ms);
  return raw;
}

Result<Session*> SessionManager::find_for_activation(const ActivateSessionRequest& request,
                                                     std::uint32_t channel_id) {
  auto it = sessions_.find(request.request_header.authentication_token);
  if (it == sessions_.end()) {
    return status_error(status::BadSessionIdInvalid, "ActivateSession for an unknown session");
  }
  Session& session = *it->second;
  if (!session.activated && session.channel_id != channel_id) {
    return status_error(status::BadSecureChannelIdInvalid,
                        "the first ActivateSession must use the channel that created the session");
  }
  return &session;
}

Result<Session*> SessionManager::complete_activation(Session& session, SessionIdentity identity,
                                                     const ActivateSessionRequest& request,
                                                     std::uint32_t channel_id) {
  // Part 4 §5.6.3 allows a new user on an activated session; we do not (a reconnecting client
  // re-activates as the same user).
  if (session.activated && (identity.token_type != session.identity.token_type ||
                            identity.user_name != session.identity.user_name)) {
    return status_error(status::BadIdentityChangeNotSupported, "the session's user cannot change");
  }
  if (session.activated && session.channel_id != channel_id) {
    log::get("opcua")->info("session {} moves from channel {} to channel {}", to_string(session.session_id),
                            session.channel_id, channel_id);
  }
  session.identity = std::move(identity);
  session.channel_id = channel_id;
  session.activated = true;
  session.last_activity = clock_.now();
  session.server_nonce = ByteString(random_bytes(kNonceBytes));
  session.locale_ids.clear();
  for (const String& locale : request.locale_ids) {
    session.locale_ids.emplace_back(locale.view());
  }
  return &session;
}

Result<Session*> SessionManager::lookup(const RequestHeader& header, std::uint32_t channel_id,
                                        bool require_activated) {
  auto it = sessions_.find(header.authentication_token);
  if (it == sessions_.end()) {
    return status_error(status::BadSessionIdInvalid, "no session with this authentication token");
  }
  Session& session = *it->second;
  if (session.channel_id != channel_id) {
    return status_error(status::BadSecureChannelIdInvalid, "the session belongs to another secure channel");
  }
  if (require_activated && !session.activated) {
    return status_error(status::BadSessionNotActivated, "ActivateSession has not been called");
  }
  session.last_activity = clock_.now();
  return &session;
}

Result<Session*> SessionManager::find(const RequestHeader& header, std::uint32_t channel_id) {
  return lookup(header, channel_id, true);
}

Result<Session*> SessionManager::find_for_close(const RequestHeader& header, std::uint32_t channel_id) {
  return lookup(header, channel_id, false);
}

void SessionManager::remove(const NodeId& authentication_token) {
  sessions_.erase(authentication_token);
}

std::vector<NodeId> SessionManager::expire() {
  std::vector<NodeId> expired;
  const auto now = clock_.now();
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    const Session& session = *it->second;
    if (now - session.last_activity >= to_duration(session.timeout_ms)) {
      log::get("opcua")->info("session {} \"{}\" timed out after {} ms without a request",
                              to_string(session.session_id), session.name, session.timeout_ms);
      expired.push_back(it->first);
      it = sessions_.erase(it);
    } else {
      ++it;
    }
  }
  return expired;
}

Clock::time_point SessionManager::next_expiry() const {
  auto next = Clock::time_point::max();
  for (const auto& [token, session] : sessions_) {
    next = std::min(next, session->last_activity + to_duration(session->timeout_ms));
  }
  return next;
}

bool SessionManager::has_activated_session(std::uint32_t channel_id) const {
  return std::any_of(sessions_.begin(), sessions_.end(), [channel_id](const auto& entry) {
    return entry.second->activated && entry.second->channel_id == channel_id;
  });
}

}  // namespace sf::opcua::server
