// The request-target of a request (RFC 9112 §3.2): its path and query, percent-decoded
// (RFC 3986 §2.1). Only origin-form ("/path?query") is accepted: the server is no proxy.
#pragma once

#include <map>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::web {

struct Target {
  std::string path;  // decoded; never contains NUL, '\' or a decoded '/'
  std::map<std::string, std::string> query;
};

// "%41" → "A"; a '%' not followed by two hex digits is malformed. In a query, '+' is a space
// (application/x-www-form-urlencoded).
Result<std::string> percent_decode(std::string_view text, bool plus_is_space);

Result<Target> parse_target(std::string_view target);

}  // namespace sf::web
