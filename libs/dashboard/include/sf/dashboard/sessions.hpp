// Users, roles and sessions of the web API: the same users file and roles as the OPC UA servers
// (`smartfactory opcua users`, sf/opcua/security/users.hpp), sessions as random ids in an
// HttpOnly, SameSite=Strict cookie (RFC 6265 §4.1.2.5-6; draft-ietf-httpbis-rfc6265bis §5.6.7),
// a CSRF token per session that every write carries in a header (the synchronizer token
// pattern: a cross-site form cannot read it), and rate limits as token buckets.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/security/users.hpp"

namespace sf::dashboard {

// Ordered by what they may do: each may what the ones before it may.
//   consumer: place orders, see and cancel their own;  viewer: read everything;
//   operator: also command machines, acknowledge alarms, cancel any order;  engineer, admin: as operator.
enum class Role { consumer, viewer, operator_, engineer, admin };
std::string_view to_string(Role role);
// The highest web role among a user's roles; nullopt when none is one (e.g. a custom OPC UA role).
std::optional<Role> web_role(const opcua::security::User& user);

struct Session {
  std::string id;    // the cookie's value: 32 random bytes, hex
  std::string csrf;  // 32 random bytes, hex
  std::string user;
  Role role = Role::viewer;
  Clock::time_point expires{};
};

inline constexpr std::string_view kSessionCookie = "sf_session";

class Sessions {
 public:
  // A session ends `idle` after its last request.
  Sessions(std::shared_ptr<opcua::security::UsersFile> users, const Clock& clock,
           std::chrono::seconds idle = std::chrono::hours(8));

  // Errc::invalid_argument for a wrong name or password (one message for both), Errc::state for
  // a user without a web role.
  Result<Session> login(std::string_view user, std::string_view password);
  // The session of a request's Cookie header, its expiry moved on; nullopt when none is valid.
  std::optional<Session> find(std::optional<std::string_view> cookie_header);
  void logout(const std::string& id);
  [[nodiscard]] std::size_t size() const;

  // The Set-Cookie value for a session (empty id: one that deletes the cookie).
  static std::string cookie(const std::string& id, bool secure);

 private:
  void expire(Clock::time_point now);  // with mutex_ held

  std::shared_ptr<opcua::security::UsersFile> users_;
  const Clock* clock_;
  std::chrono::seconds idle_;
  mutable std::mutex mutex_;
  std::map<std::string, Session, std::less<>> sessions_;
};

// Token buckets by key (a user, an address): `burst` at once, then one every `period`.
class RateLimiter {
 public:
  RateLimiter(const Clock& clock, double burst, std::chrono::milliseconds period)
      : clock_(&clock), burst_(burst), period_(period) {}
  // Takes a token: nullopt when there was one, else how long until the next.
  std::optional<std::chrono::seconds> take(const std::string& key);

 private:
  struct Bucket {
    double tokens = 0;
    Clock::time_point at{};
  };
  const Clock* clock_;
  double burst_;
  std::chrono::milliseconds period_;
  std::mutex mutex_;
  std::map<std::string, Bucket> buckets_;
};

}  // namespace sf::dashboard
