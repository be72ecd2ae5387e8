// MemoryClient: a Client that calls a Device in the same process, synchronously, for the
// deterministic simulation mode (one thread, one ManualClock). Each request is encoded as the
// PDU a TcpClient would send and takes the Server's own path through the device (fault, the
// checks libmodbus's modbus_reply makes, before_request, the bank, after_write; device.hpp),
// so a gateway sees the same answers and exception codes over either client.
#pragma once

#include <chrono>
#include <cstdint>

#include "sf/core/clock.hpp"
#include "sf/modbus/client.hpp"
#include "sf/modbus/device.hpp"

namespace sf::modbus {

struct MemoryClientOptions {
  std::uint8_t unit_id = kTcpUnitId;
  // An unreachable device (Fault::unreachable) costs a request this long on `clock` before it
  // fails with Errc::timeout, as over TCP; no clock: it fails at once.
  Clock* clock = nullptr;
  std::chrono::milliseconds response_timeout{500};
};

class MemoryClient final : public Client {
 public:
  // The device must outlive the client.
  explicit MemoryClient(Device& device, MemoryClientOptions options = {})
      : device_(device), options_(options) {}

 protected:
  ClientResult<Reply> transact(const Transaction& transaction) override;

 private:
  Device& device_;
  MemoryClientOptions options_;
};

}  // namespace sf::modbus
