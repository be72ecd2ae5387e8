#include "sf/web/router.hpp"

#include <exception>
#include <set>

#include "sf/core/log.hpp"

namespace sf::web {

std::vector<std::string> split_path(std::string_view path) {
  std::vector<std::string> segments;
  if (!path.empty() && path.front() == '/') {
    path.remove_prefix(1);
  }
  while (true) {
    const auto slash = path.find('/');
    segments.emplace_back(path.substr(0, slash));
    if (slash == std::string_view::npos) {
      return segments;
    }
    path.remove_prefix(slash + 1);
  }
}

Status Router::add(std::string method, std::string_view pattern, Handler handler) {
  if (pattern.empty() || pattern.front() != '/' || method.empty() || !handler) {
    return Error(Errc::invalid_argument, "route needs a method, a pattern starting with '/' and a handler");
  }
  Route route{std::move(method), {}, std::move(handler)};
  for (auto& text : split_path(pattern)) {
    const bool parameter = text.size() >= 2 && text.front() == '{' && text.back() == '}';
    if (!parameter && text.find_first_of("{}") != std::string::npos) {
      return Error(Errc::invalid_argument,
                   "route pattern " + std::string(pattern) + ": '{' '}' must enclose a segment");
    }
    route.segments.push_back({parameter ? text.substr(1, text.size() - 2) : std::move(text), parameter});
  }
  routes_.push_back(std::move(route));
  return {};
}

bool Router::match(const Route& route, const std::vector<std::string>& path,
                   std::map<std::string, std::string>* params) {
  if (route.segments.size() != path.size()) {
    return false;
  }
  for (std::size_t i = 0; i < path.size(); ++i) {
    const auto& segment = route.segments[i];
    if (segment.parameter ? path[i].empty() : segment.text != path[i]) {
      return false;
    }
  }
  for (std::size_t i = 0; params != nullptr && i < path.size(); ++i) {
    if (route.segments[i].parameter) {
      (*params)[route.segments[i].text] = path[i];
    }
  }
  return true;
}

bool Router::matches_path(std::string_view path) const {
  const auto segments = split_path(path);
  for (const auto& route : routes_) {
    if (match(route, segments, nullptr)) {
      return true;
    }
  }
  return false;
}

std::optional<Response> Router::dispatch(Request& request) const {
  const auto segments = split_path(request.path);
  std::set<std::string> allowed;
  for (const auto& route : routes_) {
    if (!match(route, segments, nullptr)) {
      continue;
    }
    if (route.method != request.method) {
      allowed.insert(route.method);
      continue;
    }
    match(route, segments, &request.path_params);
    try {
      return route.handler(request);
    } catch (const std::exception& e) {
      sf::log::get("web")->error("{} {}: handler failed: {}", request.method, request.path, e.what());
    } catch (...) {
      sf::log::get("web")->error("{} {}: handler failed", request.method, request.path);
    }
    // The exception's text stays in the log: it may name internals.
    return error_response(500, "the handler of " + request.method + " " + request.path + " failed");
  }
  if (allowed.empty()) {
    return std::nullopt;
  }
  std::string allow;
  for (const auto& method : allowed) {
    allow += (allow.empty() ? "" : ", ") + method;
  }
  auto response = error_response(405, "method " + request.method + " not allowed on " + request.path);
  response.headers.set("Allow", allow);
  return response;
}

std::vector<std::pair<std::string, std::string>> Router::routes() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& r : routes_) {
    std::string pattern;
    for (const auto& s : r.segments) {
      pattern += '/';
      pattern += s.parameter ? '{' + s.text + '}' : s.text;
    }
    out.emplace_back(r.method, pattern.empty() ? "/" : pattern);
  }
  return out;
}

}  // namespace sf::web
