#include "sf/dashboard/sessions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sf/core/text.hpp"
#include "sf/opcua/server/session.hpp"

namespace sf::dashboard {

namespace {

constexpr std::array<std::pair<std::string_view, Role>, 5> kRoles{{{"consumer", Role::consumer},
                                                                   {"viewer", Role::viewer},
                                                                   {"operator", Role::operator_},
                                                                   {"engineer", Role::engineer},
                                                                   {"admin", Role::admin}}};

std::string random_hex() {
  std::string hex;
  for (auto b : opcua::server::random_bytes(32)) {
    hex += fmt::format("{:02x}", b);
  }
  return hex;
}

// The value of cookie `name` in a Cookie header ("a=1; sf_session=abc", RFC 6265 §5.4).
std::optional<std::string_view> cookie_value(std::string_view header, std::string_view name) {
  for (std::string_view pair : split(header, ';')) {
    pair = trim(pair);
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == name) {
      return pair.substr(eq + 1);
    }
  }
  return std::nullopt;
}

}  // namespace

std::string_view to_string(Role role) {
  for (const auto& [name, r] : kRoles) {
    if (r == role) {
      return name;
    }
  }
  return "?";
}

std::optional<Role> web_role(const opcua::security::User& user) {
  std::optional<Role> best;
  for (const auto& name : user.roles) {
    for (const auto& [role_name, role] : kRoles) {
      if (name == role_name && (!best || role > *best)) {
        best = role;
      }
    }
  }
  return best;
}

Sessions::Sessions(std::shared_ptr<opcua::security::UsersFile> users, const Clock& clock,
                   std::chrono::seconds idle)
    : users_(std::move(users)), clock_(&clock), idle_(idle) {}

Result<Session> Sessions::login(std::string_view user, std::string_view password) {
  const auto database = users_->current();
  auto found = database->authenticate(user, password);
  if (!found) {
    return make_error(Errc::invalid_argument, "wrong user name or password");
  }
  const auto role = web_role(**found);
  if (!role) {
    return make_error(Errc::state,
                      fmt::format("user '{}' has no role of the web (consumer, viewer, operator, "
                                  "engineer, admin)",
                                  user));
  }
  Session s{random_hex(), random_hex(), std::string(user), *role, clock_->now() + idle_};
  std::lock_guard lock(mutex_);
  expire(clock_->now());
  sessions_[s.id] = s;
  return s;
}

std::optional<Session> Sessions::find(std::optional<std::string_view> cookie_header) {
  if (!cookie_header) {
    return std::nullopt;
  }
  const auto id = cookie_value(*cookie_header, kSessionCookie);
  if (!id) {
    return std::nullopt;
  }
  const auto now = clock_->now();
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(*id);
  if (it == sessions_.end()) {
    return std::nullopt;
  }
  if (it->second.expires <= now) {
    sessions_.erase(it);
    return std::nullopt;
  }
  it->second.expires = now + idle_;
  return it->second;
}

void Sessions::logout(const std::string& id) {
  std::lock_guard lock(mutex_);
  sessions_.erase(id);
}

std::size_t Sessions::size() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

void Sessions::expire(Clock::time_point now) {
  std::erase_if(sessions_, [now](const auto& entry) { return entry.second.expires <= now; });
}

std::string Sessions::cookie(const std::string& id, bool secure) {
  return fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict{}{}", kSessionCookie, id,
                     id.empty() ? "; Max-Age=0" : "", secure ? "; Secure" : "");
}

std::optional<std::chrono::seconds> RateLimiter::take(const std::string& key) {
  const auto now = clock_->now();
  std::lock_guard lock(mutex_);
  auto [it, added] = buckets_.try_emplace(key, Bucket{burst_, now});
  Bucket& b = it->second;
  const double refill = std::chrono::duration<double>(now - b.at) / std::chrono::duration<double>(period_);
  b.tokens = std::min(burst_, b.tokens + refill);
  b.at = now;
  if (b.tokens >= 1.0) {
    b.tokens -= 1.0;
    return std::nullopt;
  }
  const double wait = (1.0 - b.tokens) * std::chrono::duration<double>(period_).count();
  return std::chrono::seconds(static_cast<std::int64_t>(std::ceil(wait)));
}

}  // namespace sf::dashboard
