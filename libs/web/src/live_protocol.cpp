#include "live_protocol.hpp"

#include <nlohmann/json.hpp>

namespace sf::web {

Result<LiveRequest> parse_live_request(std::string_view text) {
  const auto message = nlohmann::json::parse(text, nullptr, false);
  if (message.is_discarded() || !message.is_object()) {
    return Error(Errc::malformed, "a message must be a JSON object");
  }
  const bool subscribe = message.contains("subscribe");
  if (subscribe == message.contains("unsubscribe") || message.size() != 1) {
    return Error(Errc::malformed, "a message has one member: \"subscribe\" or \"unsubscribe\"");
  }
  const auto& member = message.at(subscribe ? "subscribe" : "unsubscribe");
  if (!member.is_array()) {
    return Error(Errc::malformed, "topics must be an array of strings");
  }
  LiveRequest request{subscribe ? LiveRequest::Kind::subscribe : LiveRequest::Kind::unsubscribe, {}};
  for (const auto& topic : member) {
    if (!topic.is_string() || topic.get_ref<const std::string&>().empty()) {
      return Error(Errc::malformed, "topics must be non-empty strings");
    }
    request.topics.push_back(topic.get<std::string>());
  }
  return request;
}

}  // namespace sf::web
