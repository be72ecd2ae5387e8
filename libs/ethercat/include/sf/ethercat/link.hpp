// Link: how EtherCAT frames leave and enter the process. The master and the
// emulated segment never touch a socket directly (compare SOEM's oshw/nicdrv).
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/frame.hpp"

namespace sf::ethercat {

class Link {
 public:
  virtual ~Link() = default;
  // Sends one complete Ethernet frame (header included, no FCS).
  virtual Status send(ByteSpan frame) = 0;
  // Receives one EtherCAT frame into buf, waiting up to timeout. Returns the
  // frame length, or 0 when the timeout passes first. Frames that are not
  // EtherCAT (EtherType 0x88A4) are skipped.
  virtual Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) = 0;
  [[nodiscard]] virtual MacAddress mac() const = 0;
  [[nodiscard]] virtual std::string name() const = 0;
};

}  // namespace sf::ethercat
