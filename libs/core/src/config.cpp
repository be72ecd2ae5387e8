#include "sf/core/config.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace sf::config {
namespace {

std::string join_path(const std::string& parent, std::string_view key) {
  if (parent.empty()) {
    return std::string{key};
  }
  return fmt::format("{}.{}", parent, key);
}

std::string describe_type(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing";
    case YAML::NodeType::Scalar:
      return fmt::format("'{}'", n.Scalar());
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Undefined:
      return "nothing";
  }
  return "?";
}

}  // namespace

int Node::line() const {
  if (!node_.IsDefined()) {
    return 0;
  }
  const auto mark = node_.Mark();
  return mark.line < 0 ? 0 : mark.line + 1;
}

std::string Node::where() const {
  if (!node_.IsDefined() || node_.Mark().line < 0) {
    return *file_;
  }
  const auto mark = node_.Mark();
  return fmt::format("{}:{}:{}", *file_, mark.line + 1, mark.column + 1);
}

Error Node::error(std::string_view message) const {
  if (path_.empty()) {
    return Error{Errc::invalid_argument, fmt::format("{}: {}", where(), message)};
  }
  return Error{Errc::invalid_argument, fmt::format("{}: {}: {}", where(), path_, message)};
}

bool Node::has(std::string_view key) const {
  if (!node_.IsMap()) {
    return false;
  }
  const auto c = node_[std::string{key}];
  return c.IsDefined() && !c.IsNull();
}

Result<Node> Node::child(std::string_view key) const {
  if (!node_.IsMap()) {
    return error(fmt::format("expected a mapping with key '{}', found {}", key, describe_type(node_)));
  }
  const auto c = node_[std::string{key}];
  if (!c.IsDefined() || c.IsNull()) {
    return error(fmt::format("missing required key '{}'", key));
  }
  return Node{c, file_, join_path(path_, key)};
}

Result<std::vector<Node>> Node::items() const {
  std::vector<Node> out;
  if (!node_.IsDefined() || node_.IsNull()) {
    return out;
  }
  if (!node_.IsSequence()) {
    return error(fmt::format("expected a list, found {}", describe_type(node_)));
  }
  for (std::size_t i = 0; i < node_.size(); ++i) {
    out.emplace_back(node_[i], file_, fmt::format("{}[{}]", path_, i));
  }
  return out;
}

Result<std::vector<std::string>> Node::keys() const {
  if (!node_.IsMap()) {
    return error(fmt::format("expected a mapping, found {}", describe_type(node_)));
  }
  std::vector<std::string> out;
  for (const auto& kv : node_) {
    out.push_back(kv.first.as<std::string>());
  }
  return out;
}

Status Node::only_keys(std::initializer_list<std::string_view> allowed) const {
  auto list = keys();
  if (!list) {
    return list.error();
  }
  for (const std::string& key : *list) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) {
      continue;
    }
    std::string known;
    for (std::string_view a : allowed) {
      known += (known.empty() ? "" : ", ") + std::string(a);
    }
    auto c = child(key);
    return (c ? *c : *this).error(fmt::format("unknown setting '{}' (known: {})", key, known));
  }
  return {};
}

Result<std::string> Node::scalar() const {
  if (!node_.IsScalar()) {
    return error(fmt::format("expected a value, found {}", describe_type(node_)));
  }
  return node_.Scalar();
}

Result<std::int64_t> Node::integer() const {
  auto s = scalar();
  if (!s)
    return s.error();
  std::int64_t v = 0;
  const auto* first = s->data();
  const auto* last = s->data() + s->size();
  int base = 10;
  if (s->size() > 2 && (*s)[0] == '0' && ((*s)[1] == 'x' || (*s)[1] == 'X')) {
    first += 2;
    base = 16;
  }
  const auto [ptr, ec] = std::from_chars(first, last, v, base);
  if (ec != std::errc{} || ptr != last || first == last) {
    return error(fmt::format("expected an integer, found '{}'", *s));
  }
  return v;
}

Result<std::uint64_t> Node::unsigned_integer() const {
  auto s = scalar();
  if (!s)
    return s.error();
  if (!s->empty() && (*s)[0] == '-') {
    return error(fmt::format("expected a non-negative integer, found '{}'", *s));
  }
  std::uint64_t v = 0;
  const auto* first = s->data();
  const auto* last = s->data() + s->size();
  int base = 10;
  if (s->size() > 2 && (*s)[0] == '0' && ((*s)[1] == 'x' || (*s)[1] == 'X')) {
    first += 2;
    base = 16;
  }
  const auto [ptr, ec] = std::from_chars(first, last, v, base);
  if (ec != std::errc{} || ptr != last || first == last) {
    return error(fmt::format("expected a non-negative integer, found '{}'", *s));
  }
  return v;
}

Result<double> Node::real() const {
  auto s = scalar();
  if (!s)
    return s.error();
  double v = 0;
  const auto [ptr, ec] = std::from_chars(s->data(), s->data() + s->size(), v);
  if (ec != std::errc{} || ptr != s->data() + s->size() || s->empty()) {
    return error(fmt::format("expected a number, found '{}'", *s));
  }
  return v;
}

Result<bool> Node::boolean() const {
  auto s = scalar();
  if (!s)
    return s.error();
  if (*s == "true" || *s == "yes" || *s == "on")
    return true;
  if (*s == "false" || *s == "no" || *s == "off")
    return false;
  return error(fmt::format("expected true or false, found '{}'", *s));
}

Result<Node> load_string(std::string_view text, std::string name) {
  auto file = std::make_shared<const std::string>(std::move(name));
  try {
    return Node{YAML::Load(std::string{text}), file, ""};
  } catch (const YAML::Exception& e) {
    return Error{Errc::malformed,
                 fmt::format("{}:{}:{}: {}", *file, e.mark.line + 1, e.mark.column + 1, e.msg)};
  }
}

Result<std::string> read_text(const std::filesystem::path& path) {
  std::ifstream in{path, std::ios::binary};
  if (!in) {
    return Error{Errc::not_found, fmt::format("{}: cannot open: {}", path.string(), std::strerror(errno))};
  }
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Result<Node> load_file(const std::filesystem::path& path) {
  auto text = read_text(path);
  if (!text) {
    return text.error();
  }
  return load_string(*text, path.string());
}

}  // namespace sf::config
