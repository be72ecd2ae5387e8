// YAML configuration with errors that say where: file, line, column and the
// full key path, e.g. "cloud.yaml:12:7: servers[1].url: expected a string".
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "sf/core/result.hpp"

namespace sf::config {

class Node {
 public:
  Node(YAML::Node node, std::shared_ptr<const std::string> file, std::string path)
      : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

  // True if this mapping has the key (with a non-null value).
  [[nodiscard]] bool has(std::string_view key) const;
  // A required child: missing → error naming the key and the parent's line.
  [[nodiscard]] Result<Node> child(std::string_view key) const;
  // Elements of a sequence (empty for a missing or null node).
  [[nodiscard]] Result<std::vector<Node>> items() const;
  // Keys of a mapping, in file order.
  [[nodiscard]] Result<std::vector<std::string>> keys() const;

  // This node's scalar value converted to T.
  template <typename T>
  [[nodiscard]] Result<T> as() const;

  // A required key converted to T.
  template <typename T>
  [[nodiscard]] Result<T> get(std::string_view key) const {
    auto c = child(key);
    if (!c) {
      return c.error();
    }
    return c->as<T>();
  }

  // An optional key: missing → fallback; present but malformed → error.
  template <typename T>
  [[nodiscard]] Result<T> get_or(std::string_view key, T fallback) const {
    if (!has(key)) {
      return fallback;
    }
    return get<T>(key);
  }

  // Every key of this mapping is one of `allowed`: a misspelt key is an error
  // at that key naming the known ones, not a silently ignored setting.
  [[nodiscard]] Status only_keys(std::initializer_list<std::string_view> allowed) const;
  // Sets `out` from this[key] when the key is there (a malformed value is an
  // error; a missing key leaves `out` as it is).
  template <typename T>
  [[nodiscard]] Status read(std::string_view key, T& out) const {
    auto value = get_or<T>(key, out);
    if (!value) {
      return value.error();
    }
    out = std::move(*value);
    return {};
  }

  // Errors and warnings about this node: "file:line:col: path: message".
  [[nodiscard]] Error error(std::string_view message) const;
  [[nodiscard]] std::string where() const;
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const std::string& file() const { return *file_; }
  [[nodiscard]] int line() const;  // 1-based, 0 if unknown
  [[nodiscard]] const YAML::Node& yaml() const { return node_; }

 private:
  [[nodiscard]] Result<std::string> scalar() const;
  [[nodiscard]] Result<std::int64_t> integer() const;
  [[nodiscard]] Result<std::uint64_t> unsigned_integer() const;
  [[nodiscard]] Result<double> real() const;
  [[nodiscard]] Result<bool> boolean() const;

  YAML::Node node_;
  std::shared_ptr<const std::string> file_;
  std::string path_;
};

// Loads a YAML file; a syntax error names file, line and column.
Result<Node> load_file(const std::filesystem::path& file);
// A whole file as text; the error names the file and why it cannot be read.
Result<std::string> read_text(const std::filesystem::path& file);
// Loads YAML text; `name` stands in for the file name in errors.
Result<Node> load_string(std::string_view text, std::string name = "<config>");

template <typename T>
Result<T> Node::as() const {
  if constexpr (std::is_same_v<T, std::string>) {
    return scalar();
  } else if constexpr (std::is_same_v<T, bool>) {
    return boolean();
  } else if constexpr (std::is_floating_point_v<T>) {
    auto v = real();
    if (!v)
      return v.error();
    return static_cast<T>(*v);
  } else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) {
    auto v = integer();
    if (!v)
      return v.error();
    if (*v < std::numeric_limits<T>::min() || *v > std::numeric_limits<T>::max()) {
      return error("integer out of range for this setting");
    }
    return static_cast<T>(*v);
  } else if constexpr (std::is_integral_v<T> && std::is_unsigned_v<T>) {
    auto v = unsigned_integer();
    if (!v)
      return v.error();
    if (*v > std::numeric_limits<T>::max()) {
      return error("integer out of range for this setting");
    }
    return static_cast<T>(*v);
  } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
    auto list = items();
    if (!list)
      return list.error();
    std::vector<std::string> out;
    for (const auto& item : *list) {
      auto s = item.scalar();
      if (!s)
        return s.error();
      out.push_back(std::move(*s));
    }
    return out;
  } else {
    static_assert(sizeof(T) == 0, "unsupported config value type");
  }
}

}  // namespace sf::config
