#include "target.hpp"

#include "sf/core/text.hpp"

namespace sf::web {
namespace {

Status parse_query(std::string_view query, std::map<std::string, std::string>& out) {
  while (!query.empty()) {
    const auto amp = query.find('&');
    const auto pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    if (pair.empty()) {
      continue;
    }
    const auto eq = pair.find('=');
    auto name = percent_decode(pair.substr(0, eq), true);
    auto value =
        percent_decode(eq == std::string_view::npos ? std::string_view{} : pair.substr(eq + 1), true);
    if (!name || !value) {
      return Error(Errc::malformed, "query: " + (name ? value.error() : name.error()).message);
    }
    out[std::move(*name)] = std::move(*value);
  }
  return {};
}

}  // namespace

Result<std::string> percent_decode(std::string_view text, bool plus_is_space) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+' && plus_is_space) {
      out += ' ';
    } else if (text[i] != '%') {
      out += text[i];
    } else {
      const int high = i + 2 < text.size() ? hex_value(text[i + 1]) : -1;
      const int low = i + 2 < text.size() ? hex_value(text[i + 2]) : -1;
      if (high < 0 || low < 0) {
        return Error(Errc::malformed, "'%' not followed by two hex digits");
      }
      out += static_cast<char>(high * 16 + low);
      i += 2;
    }
  }
  return out;
}

Result<Target> parse_target(std::string_view target) {
  if (target.empty() || target.front() != '/') {
    return Error(Errc::malformed, "request-target is not origin-form (RFC 9112 §3.2.1)");
  }
  const auto question = target.find('?');
  const auto raw_path = target.substr(0, question);
  if (raw_path.find("%2f") != std::string_view::npos || raw_path.find("%2F") != std::string_view::npos) {
    return Error(Errc::malformed, "path contains an encoded '/'");
  }
  auto path = percent_decode(raw_path, false);
  if (!path) {
    return Error(Errc::malformed, "path: " + path.error().message);
  }
  if (path->find('\0') != std::string::npos || path->find('\\') != std::string::npos) {
    return Error(Errc::malformed, "path contains NUL or '\\'");
  }
  Target out{std::move(*path), {}};
  if (question != std::string_view::npos) {
    if (auto status = parse_query(target.substr(question + 1), out.query); !status) {
      return status.error();
    }
  }
  return out;
}

}  // namespace sf::web
