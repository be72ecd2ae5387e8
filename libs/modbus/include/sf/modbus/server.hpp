// Server: a Modbus TCP server (MB TCP) for one Device, many clients at once. One poll() loop
// over the listening socket and every connection, each request answered by libmodbus's
// modbus_reply from the device's register bank after the device's hooks (device.hpp).
//
// It runs either on its own thread (start/stop) or in steps driven by the caller
// (poll_once), never both at once.
//
// Bad input is survived: a frame whose MBAP header is broken (protocol id not 0, length outside
// 2..254) closes that connection; a well-framed request that cannot be served gets the Modbus
// exception the protocol defines (unknown function: illegal_function; quantity or byte count
// wrong, or a PDU whose length does not fit its function: illegal_data_value; addresses outside
// the tables: illegal_data_address); a half-received request never blocks other clients.
// Bounded: at most max_clients connections; a new one evicts the connection idle the longest.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/modbus/device.hpp"

namespace sf::modbus {

struct ServerOptions {
  // A numeric address to listen on: IPv4 ("0.0.0.0" for all) or IPv6.
  std::string host = "127.0.0.1";
  // 0: a free port, chosen by the system (port() reports it).
  std::uint16_t port = 0;
  std::size_t max_clients = 16;
  // Measures how long connections have been idle (eviction); SteadyClock when null.
  Clock* clock = nullptr;
};

// Totals since the server started; `clients` is the number open now.
struct ServerCounters {
  std::uint64_t requests = 0;     // complete frames received
  std::uint64_t exceptions = 0;   // exception responses sent
  std::uint64_t malformed = 0;    // broken frames (connection closed) and ill-formed PDUs
  std::uint64_t connections = 0;  // connections accepted (adopted ones too)
  std::uint64_t refused = 0;      // connections closed at once because the device is unreachable
  std::uint64_t evicted = 0;      // connections closed to make room for a new one
  std::uint64_t unanswered = 0;   // requests dropped because the device is unreachable
  std::size_t clients = 0;
};

class Server {
 public:
  // Binds host:port and listens; the device must outlive the server. Errc::invalid_argument
  // for a host that is not a numeric address, Errc::io when the port cannot be bound.
  static Result<std::unique_ptr<Server>> listen(Device& device, const ServerOptions& options);
  ~Server();  // stops, closes every connection and the listening socket
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  [[nodiscard]] std::uint16_t port() const;
  // "127.0.0.1:1502"
  [[nodiscard]] std::string endpoint() const;

  // Serves on a thread of its own until stop(). Errc::state when already running.
  Status start();
  // Any thread but the server's own; returns when the thread has ended. Connections stay open.
  void stop();
  [[nodiscard]] bool running() const;

  // Serves what is ready, waiting up to `timeout` for something to be (0: do not wait). For
  // callers that drive the server themselves; Errc::state while the thread runs.
  Status poll_once(std::chrono::milliseconds timeout);

  // Serves an already connected stream socket (an accepted TCP socket, one end of a
  // socketpair) as one more connection; takes ownership of fd. Same thread rules as poll_once.
  Status adopt(int fd);

  // Any thread.
  [[nodiscard]] ServerCounters counters() const;

 private:
  struct Impl;
  explicit Server(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf::modbus
