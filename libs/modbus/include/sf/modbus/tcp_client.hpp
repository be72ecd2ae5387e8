// TcpClient: a Modbus TCP client over libmodbus (MB TCP). It connects on first use, and again
// on the next call after its connection was lost, timed out or closed by the server (a closed
// connection is noticed before a request is sent on it, so a server restart costs no failed
// call). Not thread-safe: one caller at a time.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "sf/core/result.hpp"
#include "sf/modbus/client.hpp"

struct _modbus;  // NOLINT(bugprone-reserved-identifier): libmodbus's modbus_t

namespace sf::modbus {

struct TcpClientOptions {
  // A numeric IPv4 address, or a host name / IPv6 address (resolved by getaddrinfo).
  std::string host = "127.0.0.1";
  std::uint16_t port = 502;
  // The unit identifier of every request (MB TCP §4.4.2: 0xFF addresses the server itself).
  std::uint8_t unit_id = kTcpUnitId;
  // How long to wait for each response; also the connect timeout (libmodbus uses one for both).
  std::chrono::milliseconds response_timeout{500};
};

class TcpClient final : public Client {
 public:
  // Checks the options (Errc::invalid_argument); does not connect yet.
  static Result<std::unique_ptr<TcpClient>> create(const TcpClientOptions& options);
  ~TcpClient() override;

  // Connects now (requests also connect on demand). Errc::io when the server cannot be reached.
  Status connect();
  void close();
  [[nodiscard]] bool connected() const;
  // "127.0.0.1:1502"
  [[nodiscard]] std::string endpoint() const;

 protected:
  ClientResult<Reply> transact(const Transaction& transaction) override;

 private:
  struct ContextFree {
    void operator()(_modbus* ctx) const;
  };
  TcpClient(const TcpClientOptions& options, _modbus* ctx);
  bool connection_closed_by_peer() const;
  ClientError failure(const Transaction& transaction, int err);

  TcpClientOptions options_;
  std::unique_ptr<_modbus, ContextFree> ctx_;
};

}  // namespace sf::modbus
