// Request and Response: an HTTP exchange as plain values (RFC 9110 §6, message abstraction),
// so handlers are pure functions and nothing outside the module sees Boost.Beast.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sf/core/result.hpp"

namespace sf::web {

// Header fields in arrival order; names compare case-insensitively (RFC 9110 §5.1).
class Fields {
 public:
  void add(std::string name, std::string value);
  // Replaces every field of that name by one.
  void set(std::string name, std::string value);
  [[nodiscard]] std::optional<std::string_view> get(std::string_view name) const;
  [[nodiscard]] const std::vector<std::pair<std::string, std::string>>& all() const { return fields_; }

 private:
  std::vector<std::pair<std::string, std::string>> fields_;
};

struct Request {
  std::string method;                               // case-sensitive token (RFC 9110 §9.1)
  std::string target;                               // request-target as received (RFC 9112 §3.2)
  std::string path;                                 // the target's path, percent-decoded
  std::map<std::string, std::string> path_params;   // from the route's {name} segments
  std::map<std::string, std::string> query_params;  // from the target's query, decoded
  Fields headers;
  std::string body;
};

struct Response {
  int status = 200;  // RFC 9110 §15
  std::string content_type = "application/json";
  std::string body;
  Fields headers;  // besides Content-Type, Content-Length and the security headers
};

// The reason phrase of a status code (RFC 9110 §15), "Unknown" for codes we do not name.
std::string_view reason_phrase(int status);

// A JSON body with its status.
Response json_response(const nlohmann::json& body, int status = 200);
// {"error": message, "status": status}: the one shape of every error the module returns.
Response error_response(int status, std::string_view message);
// The request body as JSON, or an error that says where it is malformed.
Result<nlohmann::json> json_body(const Request& request);

}  // namespace sf::web
