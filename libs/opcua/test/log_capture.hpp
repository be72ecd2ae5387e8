// What a module logs while a LogCapture lives (a ring buffer sink next to the module's stderr
// sink), for tests that check a refusal is logged. Single-threaded use: the sink is added and
// removed without the logger's lock, so no other thread may log to the module meanwhile.
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <string_view>

#include <spdlog/sinks/ringbuffer_sink.h>

#include "sf/core/log.hpp"

namespace sf::opcua::test {

class LogCapture {
 public:
  explicit LogCapture(std::string_view module = "opcua")
      : logger_(sf::log::get(module)), sink_(std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(64)) {
    sink_->set_pattern("%l %v");
    logger_->sinks().push_back(sink_);
  }
  ~LogCapture() {
    auto& sinks = logger_->sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
  }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  // Whether a warning (or worse) that contains `text` was logged.
  [[nodiscard]] bool warned(std::string_view text) const {
    const auto lines = sink_->last_formatted();
    return std::any_of(lines.begin(), lines.end(), [text](const std::string& line) {
      const bool severe =
          line.rfind("warning ", 0) == 0 || line.rfind("error ", 0) == 0 || line.rfind("critical ", 0) == 0;
      return severe && line.find(text) != std::string::npos;
    });
  }

 private:
  sf::log::Logger logger_;
  std::shared_ptr<spdlog::sinks::ringbuffer_sink_mt> sink_;
};

}  // namespace sf::opcua::test
