// The plant's control port: JSON lines over TCP, one request per line, one
// answer per request. For `smartfactory plant faults|snapshot|events` and
// tests; bad requests get {"ok": false, "error": "..."} and the connection
// stays usable.
//
//   {"op": "inject", "fault": "jam:conveyor2", "at": 1.5, "for": 2}
//   {"op": "clear", "fault": "jam:conveyor2"}
//   {"op": "faults"}                  → {"ok": true, "faults": ["jam:conveyor2"]}
//   {"op": "snapshot"}                → {"ok": true, "snapshot": {...}}
//   {"op": "events", "since": 120}    → {"ok": true, "next": 131, "events": [...]}
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/plant/plant.hpp"

namespace sf::plant {

// One request line → one answer line (without the newline). Takes the
// plant's lock itself.
std::string handle_control_request(Plant& plant, std::string_view line);

// Serves the control port on a loop thread of its own (libs/net).
class ControlServer {
 public:
  static constexpr std::size_t kMaxLine = 64 * 1024;  // a longer line closes the connection
  static constexpr std::size_t kMaxClients = 8;       // more are refused
  static Result<std::unique_ptr<ControlServer>> start(Plant& plant, const std::string& host,
                                                      std::uint16_t port);
  ~ControlServer();
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;
  [[nodiscard]] std::uint16_t port() const { return port_; }

 private:
  struct Impl;
  explicit ControlServer(std::unique_ptr<Impl> impl, std::uint16_t port);
  std::unique_ptr<Impl> impl_;
  std::uint16_t port_;
};

// Client side: sends one request, returns the parsed answer's text.
Result<std::string> control_request(const std::string& host, std::uint16_t port, std::string_view request);

}  // namespace sf::plant
