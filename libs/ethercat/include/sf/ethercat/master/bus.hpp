// Bus: the master's only way onto the wire. It packs datagrams into a frame,
// sends it through a Link, waits for the same frame to come back (matched by
// the index of its first datagram, ETG.1000.4 §5.4.1.2) and resends frames that
// were lost. Compare SOEM's ec_base / ec_main "port": every acyclic read or
// write of the master goes through here; the cyclic frame uses the raw calls.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <span>
#include <type_traits>

#include "sf/core/bytes.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/link.hpp"

namespace sf::ethercat::master {

struct BusOptions {
  // How long to wait for a frame to come back before calling it lost.
  std::chrono::nanoseconds frame_timeout{std::chrono::milliseconds{2}};
  // How often an acyclic frame is sent again after it was lost.
  int retries = 3;
};

struct BusCounters {
  std::uint64_t frames_sent = 0;
  std::uint64_t frames_lost = 0;       // no matching answer within the timeout
  std::uint64_t frames_discarded = 0;  // late or foreign frames skipped while waiting
};

class Bus {
 public:
  Bus(Link& link, Clock& clock, BusOptions options = {});

  // Sends the datagrams in one frame and waits for it to return; on success
  // each datagram's data and wkc hold what came back. Lost frames are resent
  // (options.retries times); a frame that never returns is an Errc::timeout.
  Status transceive(std::span<Datagram> datagrams) { return transceive(datagrams, options_.retries); }
  // The same with an explicit number of resends: 0 for writes that must not
  // reach a slave twice (a mailbox message).
  Status transceive(std::span<Datagram> datagrams, int retries);

  // One datagram; returns its working counter. `out` receives the data read.
  Result<std::uint16_t> read(Command command, std::uint32_t address, MutableByteSpan out);
  Result<std::uint16_t> write(Command command, std::uint32_t address, ByteSpan data);

  // Configured-address access that expects exactly one slave to answer
  // (WKC 1); anything else is an error naming the station and register.
  template <typename T>
  requires std::is_arithmetic_v<T> Result<T> fprd(std::uint16_t station, std::uint16_t ado) {
    std::array<std::uint8_t, sizeof(T)> buf{};
    SF_TRY(read_one(Command::FPRD, station, ado, buf));
    return load_le<T>(buf.data());
  }
  template <typename T>
  requires std::is_arithmetic_v<T> Status fpwr(std::uint16_t station, std::uint16_t ado, T value) {
    std::array<std::uint8_t, sizeof(T)> buf{};
    store_le<T>(buf.data(), value);
    return write_one(Command::FPWR, station, ado, buf);
  }
  Status read_one(Command command, std::uint16_t adp, std::uint16_t ado, MutableByteSpan out);
  Status write_one(Command command, std::uint16_t adp, std::uint16_t ado, ByteSpan data);

  // Raw path for the cyclic frame, which is built once and reused: sends an
  // encoded frame, then waits for the frame whose first datagram has `index`.
  // Returns the received length, 0 if it did not come back. No allocation.
  Status send_raw(ByteSpan frame);
  Result<std::size_t> receive_raw(MutableByteSpan buf, std::uint8_t index);
  // Receives whatever frame comes next (0 on timeout), for callers that wait
  // for several frames at once. Does not count losses.
  Result<std::size_t> receive_frame(MutableByteSpan buf) {
    return link_.receive(buf, options_.frame_timeout);
  }
  // Offset of the first datagram's index byte in a frame (ETG.1000.4 Table 11).
  static constexpr std::size_t kFirstIndexOffset = kEthernetHeaderSize + kEcatHeaderSize + 1;

  // Auto-increment addressing (ETG.1000.4 §5.3.1): every slave increments
  // ADP on the way and the one that sees 0 is addressed, so ring position p
  // is reached with ADP = −p.
  static std::uint16_t auto_increment_address(std::size_t position) {
    return static_cast<std::uint16_t>(0x10000U - (position & 0xffffU));
  }

  // A fresh datagram index for a frame (wraps at 256).
  std::uint8_t next_index() { return index_++; }

  // Serialises access when a cyclic thread and acyclic callers share the bus.
  std::recursive_mutex& mutex() const { return mutex_; }

  [[nodiscard]] const BusCounters& counters() const { return counters_; }
  [[nodiscard]] Clock& clock() const { return clock_; }
  [[nodiscard]] Link& link() const { return link_; }
  [[nodiscard]] const BusOptions& options() const { return options_; }

 private:
  Status transceive_once(std::span<Datagram> datagrams, bool& lost);

  Link& link_;
  Clock& clock_;
  BusOptions options_;
  BusCounters counters_;
  std::uint8_t index_ = 0;
  Bytes rx_;
  mutable std::recursive_mutex mutex_;
};

}  // namespace sf::ethercat::master
