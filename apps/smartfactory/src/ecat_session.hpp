// What the ecat commands share: choosing a link (a real interface or an
// emulated segment in this process), a master session on it, and the cyclic
// run loop behind `ecat run` (and the main job in scripts/demo).
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/slave/segment.hpp"

namespace sf::app {

struct CommandResult;

struct LinkChoice {
  std::string iface;          // raw socket on this interface
  std::string sim;            // or an emulated segment in-process, e.g. "servo:2"
  std::string pcap;           // optional capture of every frame
  unsigned busy_poll_us = 0;  // raw socket: spin this long for a frame before sleeping
};

// --iface / --sim (one of them), --pcap and --busy-poll-us (default
// kMasterBusyPollUs: the master tools spin; `ecat sim` sleeps by default).
inline constexpr unsigned kMasterBusyPollUs = 200;
void add_link_options(CLI::App& command, LinkChoice& link);
void add_busy_poll_option(CLI::App& command, LinkChoice& link);

// Digital inputs of an emulated segment show a fixed pattern so a master
// sees data arrive: 0xA0 + position (8-bit), 0x5A5A0000 + position (32-bit).
void set_input_pattern(ethercat::slave::Segment& segment);

// A raw socket on choice.iface, wrapped in a pcap tap when choice.pcap is set.
Result<std::unique_ptr<ethercat::Link>> open_link(const LinkChoice& choice, const Clock& clock);

// A master on a link; with --sim also the emulated segment serving it from
// its own thread over an in-memory link pair.
class EcatSession {
 public:
  static Result<std::unique_ptr<EcatSession>> open(const LinkChoice& choice,
                                                   ethercat::master::MasterOptions options = {});
  ~EcatSession();
  EcatSession(const EcatSession&) = delete;
  EcatSession& operator=(const EcatSession&) = delete;

  ethercat::master::Master& master() { return *master_; }

 private:
  EcatSession() = default;

  std::unique_ptr<ethercat::slave::Segment> segment_;
  std::unique_ptr<ethercat::Link> segment_link_;
  std::unique_ptr<ethercat::slave::SegmentRunner> runner_;
  std::unique_ptr<ethercat::Link> link_;
  std::unique_ptr<ethercat::master::Master> master_;
};

struct RunOptions {
  LinkChoice link;
  bool json = false;
  unsigned cycle_us = 1000;
  double duration_s = 10.0;
  bool dc = true;
  ethercat::AlState final_state = ethercat::AlState::Init;
};

// `ecat sdo list|read|write` (ecat_sdo.cpp).
void register_ecat_sdo(CLI::App& ecat_cmd, CommandResult& result);

// Brings the segment to OP (resetting drive faults), runs the cycle for the
// duration (or until SIGINT/SIGTERM), disables the axes, takes the segment
// to options.final_state, prints statistics. Exit code 1 when an axis ended
// in fault or a slave was lost, or bring-up failed.
int run_cyclic(const RunOptions& options);

}  // namespace sf::app
