// The messages a client sends on the live endpoint (text frames, RFC 6455 §5.6), as values:
// {"subscribe": ["topic", ...]} or {"unsubscribe": ["topic", ...]}.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"

namespace sf::web {

struct LiveRequest {
  enum class Kind { subscribe, unsubscribe };
  Kind kind = Kind::subscribe;
  std::vector<std::string> topics;  // non-empty strings
};

// The request of a text message, or an error that says what is wrong with it.
Result<LiveRequest> parse_live_request(std::string_view text);

}  // namespace sf::web
