#include "sf/core/log.hpp"

#include <cstdlib>
#include <mutex>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>

namespace sf::log {
namespace {

std::mutex& registry_mutex() {
  static std::mutex m;
  return m;
}

spdlog::level::level_enum& default_level() {
  static spdlog::level::level_enum level = spdlog::level::info;
  return level;
}

std::optional<spdlog::level::level_enum> parse_level(std::string_view name) {
  const auto level = spdlog::level::from_str(std::string{name});
  // from_str maps unknown names to "off"; accept "off" only when asked for.
  if (level == spdlog::level::off && name != "off") {
    return std::nullopt;
  }
  return level;
}

}  // namespace

Logger get(std::string_view module) {
  const std::lock_guard lock{registry_mutex()};
  std::string name{module};
  if (auto existing = spdlog::get(name)) {
    return existing;
  }
  // All module loggers share one stderr sink so lines do not interleave.
  static auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  auto logger = std::make_shared<spdlog::logger>(name, sink);
  logger->set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%-5l%$ [%n] %v");
  logger->set_level(default_level());
  spdlog::register_logger(logger);
  return logger;
}

Status set_level(std::string_view spec) {
  // "info" or "info,ethercat=trace,opcua=debug"
  std::size_t start = 0;
  while (start <= spec.size()) {
    const auto end = std::min(spec.find(',', start), spec.size());
    const auto item = spec.substr(start, end - start);
    const auto eq = item.find('=');
    if (eq == std::string_view::npos) {
      const auto level = parse_level(item);
      if (!level) {
        return Error{Errc::invalid_argument, fmt::format("unknown log level '{}'", item)};
      }
      const std::lock_guard lock{registry_mutex()};
      default_level() = *level;
      spdlog::apply_all([&](const Logger& l) { l->set_level(*level); });
    } else {
      const auto level = parse_level(item.substr(eq + 1));
      if (!level) {
        return Error{Errc::invalid_argument, fmt::format("unknown log level in '{}'", item)};
      }
      get(item.substr(0, eq))->set_level(*level);
    }
    start = end + 1;
  }
  return {};
}

void init_from_env() {
  if (const char* env = std::getenv("SF_LOG"); env != nullptr && *env != '\0') {
    if (auto st = set_level(env); !st) {
      get("core")->warn("SF_LOG ignored: {}", st.error().describe());
    }
  }
}

}  // namespace sf::log
