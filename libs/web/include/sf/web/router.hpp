// Router: one table of routes (method + path pattern) to handlers, the only place a request
// meets application code. Patterns are literal segments and {name} parameters:
// "/api/orders/{id}" matches "/api/orders/42" with path_params["id"] == "42".
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/web/message.hpp"

namespace sf::web {

using Handler = std::function<Response(const Request&)>;

class Router {
 public:
  // Adds a route; a pattern must start with '/', and '{' '}' enclose a whole segment.
  Status add(std::string method, std::string_view pattern, Handler handler);

  // Every route as (method, pattern), in the order added (e.g. to check an API description).
  [[nodiscard]] std::vector<std::pair<std::string, std::string>> routes() const;

  // Whether some route's pattern matches the path, whatever the method.
  [[nodiscard]] bool matches_path(std::string_view path) const;

  // The response for a request: the handler's, or 405 with Allow when the path matches under
  // other methods only (RFC 9110 §15.5.6), or 500 when the handler throws. nullopt when no
  // pattern matches the path, so the caller may look elsewhere (static files) or answer 404.
  [[nodiscard]] std::optional<Response> dispatch(Request& request) const;

 private:
  struct Segment {
    std::string text;
    bool parameter = false;
  };
  struct Route {
    std::string method;
    std::vector<Segment> segments;
    Handler handler;
  };
  static bool match(const Route& route, const std::vector<std::string>& path,
                    std::map<std::string, std::string>* params);

  std::vector<Route> routes_;
};

// The segments of a decoded path: "/a/b/" → {"a", "b", ""}.
std::vector<std::string> split_path(std::string_view path);

}  // namespace sf::web
