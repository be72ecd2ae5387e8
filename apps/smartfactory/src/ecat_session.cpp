#include "ecat_session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/ethercat/master/cia402.hpp"
#include "sf/ethercat/master/cyclic_runner.hpp"

namespace sf::app {
namespace {

namespace ecat = sf::ethercat;
using nlohmann::json;
using namespace std::chrono_literals;

double us(std::chrono::nanoseconds d) {
  return static_cast<double>(d.count()) / 1000.0;
}

json histogram_json(const ecat::master::DurationHistogram& h) {
  return json{{"min", us(h.min())},
              {"median", us(h.median())},
              {"p99", us(h.quantile(0.99))},
              {"max", us(h.max())},
              {"count", h.count()}};
}

// Exercises the outputs every cycle: digital outputs (objects 0x7000–0x7FFF)
// count the cycles, so a capture or the devices show the data moving.
void write_pattern(ecat::master::Master& master, std::uint64_t cycle) {
  for (std::size_t i = 0; i < master.slave_count(); ++i) {
    auto view = master.slave(i);
    const auto* mapping = view.mapping();
    if (mapping == nullptr) {
      continue;
    }
    for (const auto& pdo : mapping->outputs) {
      for (const auto& e : pdo.entries) {
        if (e.index >= 0x7000 && e.index <= 0x7FFF && e.bit_length > 0) {
          const auto mask = e.bit_length >= 64 ? ~0ULL : ((1ULL << e.bit_length) - 1U);
          ecat::master::write_bits(view.outputs(), e.bit_offset, e.bit_length, (cycle + i) & mask);
        }
      }
    }
  }
}

std::size_t total_frame_bytes(const ecat::master::Master& master) {
  std::size_t total = 0;
  for (const auto size : master.cyclic_frame_sizes()) {
    total += size;
  }
  return total;
}

json slaves_json(ecat::master::Master& master) {
  json out = json::array();
  for (std::size_t i = 0; i < master.slave_count(); ++i) {
    const auto& info = master.slave_info(i);
    auto state = master.read_state(i);
    auto view = master.slave(i);
    std::string state_text = state ? state->to_string() : "lost";
    out.push_back({{"position", i},
                   {"name", info.name()},
                   {"state", state_text},
                   {"al_status_code", info.al_status_code},
                   {"outputs", to_hex(view.outputs(), 4096)},
                   {"inputs", to_hex(view.inputs(), 4096)}});
  }
  return out;
}

// An axis of the demo motion, the cycle it reached operation enabled and
// where it stood then.
struct MovingAxis {
  ecat::master::Cia402Axis axis;
  std::optional<std::uint64_t> since;
  std::int32_t origin = 0;
  bool stopping = false;  // hold and disable (end of the run)
  bool fault_at_start = false;
  bool ended_in_fault = false;
};

bool in_fault(const ecat::master::Cia402Axis& axis) {
  const auto s = axis.state();
  return s == ecat::master::cia402::State::Fault || s == ecat::master::cia402::State::FaultReactionActive;
}

// Every CiA 402 axis of every drive in the segment, enabled; a drive that
// comes up in fault (e.g. left by a master that stopped without disabling
// it) is reset first (CiA 402 fault reset, controlword bit 7).
std::vector<MovingAxis> attach_axes(ecat::master::Master& master) {
  std::vector<MovingAxis> axes;
  for (std::size_t i = 0; i < master.slave_count(); ++i) {
    for (unsigned a = 0; a < 64; ++a) {
      auto axis = ecat::master::Cia402Axis::attach(master, i, a);
      if (!axis) {
        break;
      }
      const bool fault = in_fault(*axis);
      axis->fault_reset();
      axis->enable();
      axes.push_back(MovingAxis{std::move(*axis), std::nullopt, 0, false, fault, false});
    }
  }
  return axes;
}

// Axes that no longer hold a torque: switched off or in fault.
bool all_disabled(const std::vector<MovingAxis>& axes) {
  return std::all_of(axes.begin(), axes.end(), [](const MovingAxis& m) {
    const auto s = m.axis.state();
    return in_fault(m.axis) || s == ecat::master::cia402::State::SwitchOnDisabled ||
           s == ecat::master::cia402::State::NotReadyToSwitchOn;
  });
}

// Each axis, once enabled, swings between its start and +20 000 counts
// along (1 - cos) / 2: it starts and turns at zero velocity, as a SCARA
// set-point stream does; the period differs per axis (2 s + 0.25 s each).
void move_axes(std::vector<MovingAxis>& axes, std::uint64_t cycle, std::chrono::nanoseconds period) {
  constexpr double kTwoPi = 6.283185307179586;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    auto& m = axes[k];
    if (!m.axis.enabled() || m.stopping) {
      m.since.reset();
    } else {
      if (!m.since) {
        // Relative to where the axis stands (a drive keeps its position from
        // an earlier run): an absolute target would jump by that much.
        m.since = cycle;
        m.origin = m.axis.actual_position();
      }
      const double t = static_cast<double>(cycle - *m.since) * static_cast<double>(period.count()) * 1e-9;
      const double swing_period = 2.0 + 0.25 * static_cast<double>(k);
      m.axis.set_target_position(
          m.origin + static_cast<std::int32_t>(10000.0 * (1.0 - std::cos(kTwoPi * t / swing_period))));
    }
    m.axis.update();
  }
}

json axes_json(const std::vector<MovingAxis>& axes) {
  json out = json::array();
  for (const auto& m : axes) {
    out.push_back({{"slave", m.axis.slave_position()},
                   {"axis", m.axis.axis()},
                   {"state", std::string{ecat::master::cia402::to_string(m.axis.state())}},
                   {"fault_at_start", m.fault_at_start},
                   {"fault", m.ended_in_fault},
                   {"target", m.axis.target_position()},
                   {"actual", m.axis.actual_position()}});
  }
  return out;
}

void print_text(const ecat::master::Master& master, const json& result) {
  const auto& s = master.statistics();
  std::printf("%s\n", s.summary().c_str());
  for (const auto& slave : result["slaves"]) {
    std::printf("  slave %-3d %-28s %s\n", slave["position"].get<int>(),
                slave["name"].get<std::string>().c_str(), slave["state"].get<std::string>().c_str());
  }
  for (const auto& axis : result["axes"]) {
    std::printf("  axis %d.%d %-20s target %8d actual %8d\n", axis["slave"].get<int>(),
                axis["axis"].get<int>(), axis["state"].get<std::string>().c_str(), axis["target"].get<int>(),
                axis["actual"].get<int>());
  }
}

}  // namespace

void add_link_options(CLI::App& command, LinkChoice& link) {
  // A master waits for its frames by spinning first, as SOEM and KickCAT do:
  // a sleeping receive adds a thread wake-up to every round trip.
  link.busy_poll_us = kMasterBusyPollUs;
  auto* iface = command.add_option("--iface", link.iface,
                                   "Network interface of the EtherCAT segment (needs root), or udp:HOST:PORT "
                                   "for EtherCAT in UDP (a plant)");
  auto* sim = command.add_option("--sim", link.sim,
                                 "No interface: emulate this segment in-process, e.g. "
                                 "smart-controller:1,digital-io:2,servo:1");
  iface->excludes(sim);
  sim->excludes(iface);
  command.add_option("--pcap", link.pcap,
                     "Record every frame the master sends and receives to this pcap file");
  add_busy_poll_option(command, link);
}

void add_busy_poll_option(CLI::App& command, LinkChoice& link) {
  command
      .add_option("--busy-poll-us", link.busy_poll_us,
                  "With --iface: wait for a frame by spinning on the socket for up to this many microseconds "
                  "before sleeping: a shorter round trip at the price of a busy core (0 = always sleep)")
      ->check(CLI::Range(0U, 1'000'000U))
      ->capture_default_str();
}

void set_input_pattern(ecat::slave::Segment& segment) {
  for (std::size_t i = 0; i < segment.size(); ++i) {
    if (auto* io = segment.device<ecat::slave::DigitalIo>(i)) {
      io->set_inputs(static_cast<std::uint8_t>(0xA0U + i));
    } else if (auto* drive = segment.device<ecat::slave::DriveDevice>(i); drive && drive->has_digital_io()) {
      drive->set_digital_inputs(0x5A5A0000U + static_cast<std::uint32_t>(i));
    }
  }
}

Result<std::unique_ptr<ecat::Link>> open_link(const LinkChoice& choice, const Clock& clock) {
  // An interface name, or udp:HOST:PORT for a segment that speaks EtherCAT in UDP (a plant).
  auto opened =
      ecat::open_link(choice.iface, ecat::RawSocketOptions{std::chrono::microseconds{choice.busy_poll_us}});
  if (!opened) {
    return opened.error();
  }
  std::unique_ptr<ecat::Link> link = std::move(*opened);
  if (!choice.pcap.empty()) {
    auto tap = ecat::PcapTap::open(std::move(link), choice.pcap, clock);
    if (!tap) {
      return tap.error();
    }
    link = std::move(*tap);
  }
  return link;
}

Result<std::unique_ptr<EcatSession>> EcatSession::open(const LinkChoice& choice,
                                                       ecat::master::MasterOptions options) {
  auto& clock = SteadyClock::instance();
  std::unique_ptr<EcatSession> s{new EcatSession};
  if (choice.iface.empty() && choice.sim.empty()) {
    return Error{Errc::invalid_argument, "one of --iface IF or --sim SPEC is required"};
  }
  if (!choice.sim.empty()) {
    auto segment = ecat::slave::Segment::create(choice.sim, clock);
    if (!segment) {
      return segment.error().with_context("--sim");
    }
    s->segment_ = std::move(*segment);
    set_input_pattern(*s->segment_);
    auto pair = ecat::make_memory_link_pair();
    s->segment_link_ = std::move(pair.b);
    s->runner_ = std::make_unique<ecat::slave::SegmentRunner>(*s->segment_, *s->segment_link_);
    (void)try_realtime(70);  // the segment's thread inherits it where permitted
    SF_TRY(s->runner_->start());
    s->link_ = std::move(pair.a);
    if (!choice.pcap.empty()) {
      auto tap = ecat::PcapTap::open(std::move(s->link_), choice.pcap, clock);
      if (!tap) {
        return tap.error();
      }
      s->link_ = std::move(*tap);
    }
  } else {
    auto link = open_link(choice, clock);
    if (!link) {
      return link.error();
    }
    s->link_ = std::move(*link);
  }
  s->master_ = std::make_unique<ecat::master::Master>(*s->link_, clock, options);
  return s;
}

EcatSession::~EcatSession() {
  master_.reset();
  if (runner_) {
    runner_->stop();
  }
}

namespace {

// The end of a run: the axes are disabled while the cycle still runs (a
// drive that loses OP while enabled faults), then the cycle stops and the
// segment goes to `final_state` (as other masters' tools do), so no
// process-data watchdog trips. Faults seen before the axes were disabled
// are kept for the report.
void stop_motion(ecat::master::Master& master, ecat::master::CyclicRunner& runner,
                 std::vector<MovingAxis>& axes) {
  {
    std::lock_guard lock(master.bus().mutex());
    for (auto& m : axes) {
      m.ended_in_fault = in_fault(m.axis);
      m.stopping = true;
      m.axis.disable();
    }
  }
  auto& clock = master.clock();
  const auto deadline = clock.now() + std::chrono::milliseconds{500};
  while (clock.now() < deadline) {
    {
      std::lock_guard lock(master.bus().mutex());
      if (all_disabled(axes)) {
        break;
      }
    }
    std::this_thread::sleep_for(1ms);
  }
  runner.stop();
  // The cycle callback prepared outputs for a cycle that never ran: send them,
  // so the image reports exactly what the devices last received.
  for (int attempt = 0; attempt < 3 && !master.exchange().received; ++attempt) {
  }
}

// Why the run failed, one line per problem (empty: it did not).
std::vector<std::string> run_problems(ecat::master::Master& master, const std::vector<MovingAxis>& axes) {
  std::vector<std::string> out;
  for (const auto& m : axes) {
    if (m.ended_in_fault) {
      out.push_back(fmt::format("axis {}.{} ended in fault", m.axis.slave_position(), m.axis.axis()));
    }
  }
  for (const auto p : master.lost_slaves()) {
    out.push_back(fmt::format("slave {} ({}) was lost", p, master.slave_info(p).name()));
  }
  return out;
}

}  // namespace

int run_cyclic(const RunOptions& o) {
  ecat::master::MasterOptions options;
  options.distributed_clocks = o.dc;
  auto session = EcatSession::open(o.link, options);
  if (!session) {
    std::cerr << "ecat run: " << session.error().describe() << "\n";
    return kExitFailure;
  }
  auto& master = (*session)->master();
  auto& clock = master.clock();
  // From here on Ctrl-C ends the run the orderly way, even during bring-up.
  install_stop_signals();
  std::fprintf(stderr, "ecat run: scanning, configuring and bringing the segment to OP...\n");
  if (auto st = master.bring_up(ecat::AlState::Op); !st) {
    std::cerr << "ecat run: " << st.error().describe() << "\n";
    if (master.slave_count() > 0) {
      (void)master.request_state(o.final_state);
    }
    return kExitFailure;
  }
  const auto period = std::chrono::microseconds{o.cycle_us};
  std::vector<MovingAxis> axes = attach_axes(master);
  master.statistics().reset();
  ecat::master::CyclicRunner runner{master, ecat::master::CyclicOptions{period, true, 80, true}};
  std::uint64_t cycle = 0;
  auto st = runner.start([&](ecat::master::Master& m, const ecat::master::ExchangeResult&) {
    write_pattern(m, cycle);
    move_axes(axes, cycle, period);
    ++cycle;
  });
  if (!st) {
    std::cerr << "ecat run: " << st.error().describe() << "\n";
    return kExitFailure;
  }
  std::fprintf(stderr, "ecat run: %zu slaves in OP, %zu CiA 402 axes; %u us cycle for %.1f s%s\n",
               master.slave_count(), axes.size(), o.cycle_us, o.duration_s,
               runner.realtime_active() ? " (SCHED_FIFO)" : "");
  const auto end = clock.now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     std::chrono::duration<double>{o.duration_s});
  while (clock.now() < end && !stop_requested()) {
    std::this_thread::sleep_for(std::min<std::chrono::nanoseconds>(end - clock.now(), 1s));
    if (!o.json) {
      std::fprintf(stderr, "ecat run: %s\n", runner.statistics().summary().c_str());
    }
  }
  stop_motion(master, runner, axes);
  const auto& stats = master.statistics();
  json result{{"cycles", stats.cycles},
              {"lost_frames", stats.lost_frames},
              {"wkc_errors", stats.wkc_errors},
              {"cycle_us", o.cycle_us},
              {"round_trip_us", histogram_json(stats.round_trip)},
              {"jitter_us", histogram_json(stats.jitter)},
              {"realtime", runner.realtime_active()},
              {"frame_bytes", total_frame_bytes(master)},
              {"frames_per_cycle", master.cyclic_frame_sizes().size()},
              {"lost_slaves", master.lost_slaves()}};
  result["slaves"] = slaves_json(master);
  result["axes"] = axes_json(axes);
  auto problems = run_problems(master, axes);
  if (auto down = master.request_state(o.final_state); !down) {
    problems.push_back(
        fmt::format("taking the segment to {}: {}", to_string(o.final_state), down.error().describe()));
  }
  result["final_state"] = std::string{to_string(o.final_state)};
  result["problems"] = problems;
  if (o.json) {
    std::cout << result.dump(2) << "\n";
  } else {
    print_text(master, result);
  }
  for (const auto& p : problems) {
    std::fprintf(stderr, "ecat run: %s\n", p.c_str());
  }
  return problems.empty() ? kExitOk : kExitFailure;
}

}  // namespace sf::app
