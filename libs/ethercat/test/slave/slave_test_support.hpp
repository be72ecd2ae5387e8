// Helpers for the slave tests: frames built and decoded with the common
// codec (frame.hpp), passed through a Segment in place.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/slave/segment.hpp"

namespace sf::ethercat::slave::testing {

class Harness {
 public:
  explicit Harness(std::string_view spec, SegmentOptions options = {}) {
    auto made = Segment::create(spec, clock, options);
    EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().describe());
    segment = std::move(*made);
  }

  // Sends the datagrams in one frame; returns them as they came back (empty
  // if the frame did not return).
  std::vector<Datagram> run(std::vector<Datagram> datagrams) {
    Frame f;
    f.source = {0x00, 0x11, 0x22, 0x33, 0x44, 0x55};
    f.datagrams = std::move(datagrams);
    auto bytes = encode(f);
    EXPECT_TRUE(bytes.ok());
    last_frame = *bytes;
    if (!segment->process(last_frame)) {
      return {};
    }
    auto back = decode(last_frame);
    EXPECT_TRUE(back.ok()) << (back.ok() ? "" : back.error().describe());
    return back.ok() ? back->datagrams : std::vector<Datagram>{};
  }

  Datagram run(Datagram d) {
    auto out = run(std::vector<Datagram>{std::move(d)});
    return out.empty() ? Datagram{} : out.front();
  }

  static Datagram make(Command c, std::uint32_t address, Bytes data) {
    Datagram d;
    d.command = c;
    d.address = address;
    d.data = std::move(data);
    return d;
  }
  static Datagram physical(Command c, std::uint16_t adp, std::uint16_t ado, Bytes data) {
    return make(c, Datagram::physical(adp, ado), std::move(data));
  }
  template <typename T>
  static Bytes le(T v) {
    Bytes b(sizeof(T));
    store_le<T>(b.data(), v);
    return b;
  }

  // Configured-address access to one slave.
  Datagram fprd(std::uint16_t station, std::uint16_t ado, std::size_t n) {
    return run(physical(Command::FPRD, station, ado, Bytes(n, 0)));
  }
  std::uint16_t fprd16(std::uint16_t station, std::uint16_t ado) {
    auto d = fprd(station, ado, 2);
    return d.data.size() == 2 ? load_le<std::uint16_t>(d.data.data()) : 0xDEAD;
  }
  std::uint16_t fpwr(std::uint16_t station, std::uint16_t ado, Bytes data) {
    return run(physical(Command::FPWR, station, ado, std::move(data))).wkc;
  }
  template <typename T>
  std::uint16_t fpwr_value(std::uint16_t station, std::uint16_t ado, T v) {
    return fpwr(station, ado, le(v));
  }

  // Station addresses 0x1001, 0x1002, ... by position (APWR 0x0010).
  void assign_stations() {
    for (std::size_t i = 0; i < segment->size(); ++i) {
      auto d = run(physical(Command::APWR, static_cast<std::uint16_t>(-static_cast<int>(i)),
                            reg::kStationAddress, le<std::uint16_t>(station(i))));
      EXPECT_EQ(d.wkc, 1);
    }
  }
  static std::uint16_t station(std::size_t position) { return static_cast<std::uint16_t>(0x1001 + position); }

  // Writes AL control and returns AL status as the master then reads it.
  AlStatus request(std::size_t position, AlState s, bool acknowledge = false) {
    EXPECT_EQ(
        fpwr_value<std::uint16_t>(station(position), reg::kAlControl, AlControl::of(s, acknowledge).encode()),
        1);
    return AlStatus::decode(fprd16(station(position), reg::kAlStatus));
  }

  // Writes a SyncManager as a master does (8 bytes, activate = enable).
  std::uint16_t write_sm(std::size_t position, unsigned n, std::uint16_t start, std::uint16_t length,
                         std::uint8_t control, bool enable = true) {
    Bytes b(8, 0);
    store_le<std::uint16_t>(&b[0], start);
    store_le<std::uint16_t>(&b[2], length);
    b[4] = control;
    b[6] = enable ? 1 : 0;
    return fpwr(station(position), reg::sync_manager(n), b);
  }
  // SM0/SM1 as the SII of the CoE devices says.
  void configure_mailbox(std::size_t position) {
    const auto& sms = segment->slave(position).device().sii().sync_managers;
    for (unsigned n = 0; n < 2; ++n) {
      EXPECT_EQ(write_sm(position, n, sms[n].start, sms[n].length, sms[n].control), 1);
    }
  }
  // Process-data SMs with the lengths of the device's PDO mapping (from the
  // SII) and byte-wise FMMUs: outputs at `logical`, inputs right after.
  // Returns the total logical size.
  std::size_t configure_process_data(std::size_t position, std::uint32_t logical) {
    const auto& sii = segment->slave(position).device().sii();
    std::size_t out_bytes = 0;
    std::size_t in_bytes = 0;
    for (const auto& p : sii.rx_pdos)
      out_bytes += p.bit_length() / 8;
    for (const auto& p : sii.tx_pdos)
      in_bytes += p.bit_length() / 8;
    unsigned fmmu = 0;
    for (unsigned n = 0; n < sii.sync_managers.size(); ++n) {
      const auto& sm = sii.sync_managers[n];
      const bool out = sm.type == SiiSyncManagerType::outputs;
      const bool in = sm.type == SiiSyncManagerType::inputs;
      if (!out && !in)
        continue;
      const auto len = static_cast<std::uint16_t>(out ? out_bytes : in_bytes);
      EXPECT_EQ(write_sm(position, n, sm.start, len, sm.control), 1);
      const auto at = static_cast<std::uint32_t>(out ? logical : logical + out_bytes);
      const auto cfg = FmmuConfig::bytes(at, sm.start, len, out ? kFmmuWrite : kFmmuRead).encode();
      EXPECT_EQ(fpwr(station(position), reg::fmmu(fmmu++), Bytes(cfg.begin(), cfg.end())), 1);
    }
    return out_bytes + in_bytes;
  }

  ManualClock clock;
  std::unique_ptr<Segment> segment;
  Bytes last_frame;
};

}  // namespace sf::ethercat::slave::testing
