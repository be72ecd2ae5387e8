// Distributed clocks (ETG.1000.4 §9.1.3; ET1100 datasheet I §9 and II
// §13.1–13.3): one frame latches every slave's receive times (BWR 0x0900);
// from the port times the master derives the topology's propagation delays,
// picks the first DC slave as reference clock and writes each slave's delay
// (0x0928) and offset (0x0920) so that all system times read the same; then
// many FRMWs of the reference's 0x0910 let every slave's time control loop
// learn its drift (static compensation). In operation one FRMW per cycle keeps
// them locked (continuous compensation); 0x092C shows the remaining difference.
#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "cyclic_frame.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

// ET1100 datasheet I §9.1.1: a frame passes the ports in the order 0, 3, 1, 2.
constexpr std::array<unsigned, 4> kPortOrder{0, 3, 1, 2};
// DC system time counts ns from 2000-01-01 00:00 UTC (ETG.1000.4 §9.1.3.1).
constexpr std::chrono::sys_seconds kDcEpoch{std::chrono::seconds{946684800}};

std::uint64_t master_time(const Clock& clock) {
  const auto since = clock.utc_now() - kDcEpoch;
  return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(since).count());
}

// Ports after 0 that lead to a neighbour, in processing order.
std::vector<unsigned> child_ports(const SlaveInfo& s) {
  std::vector<unsigned> out;
  for (const auto port : kPortOrder) {
    if (port != 0 && s.port_open(port)) {
      out.push_back(port);
    }
  }
  return out;
}

// The port whose receive time is when the frame left towards `port`'s
// neighbour: the open port processed just before it (0 if none).
unsigned previous_open_port(const SlaveInfo& s, unsigned port) {
  unsigned prev = 0;
  for (const auto p : kPortOrder) {
    if (p == port) {
      return prev;
    }
    if (p == 0 || s.port_open(p)) {
      prev = p;
    }
  }
  return prev;
}

}  // namespace

Status Master::latch_and_read_receive_times(std::vector<std::size_t>& dc_slaves) {
  dc_slaves.clear();
  // Any write to 0x0900 latches the receive times of every port (datasheet II 0x0900).
  const std::array<std::uint8_t, 4> zero{};
  auto wkc = bus_.write(Command::BWR, Datagram::physical(0, reg::kDcReceiveTimePort0), zero);
  if (!wkc) {
    return wkc.error().with_context("DC latch");
  }
  for (auto& s : slaves_) {
    if (!s.dc.supported) {
      continue;
    }
    std::array<std::uint8_t, 16> ports{};
    SF_TRY(bus_.read_one(Command::FPRD, s.station, reg::kDcReceiveTimePort0, ports));
    for (unsigned p = 0; p < 4; ++p) {
      s.dc.port_receive_time[p] = load_le<std::uint32_t>(&ports[std::size_t{4} * p]);
    }
    auto unit = bus_.fprd<std::uint64_t>(s.station, reg::kDcReceiveTimeProcessingUnit);
    if (!unit) {
      return unit.error();
    }
    s.dc.processing_unit_time = *unit;
    auto dl = bus_.fprd<std::uint16_t>(s.station, reg::kDlStatus);
    if (!dl) {
      return dl.error();
    }
    s.dl_status = DlStatus{*dl};
    dc_slaves.push_back(s.position);
  }
  return {};
}

void Master::compute_topology_and_delays(const std::vector<std::size_t>& dc_slaves) {
  // Parents from the open ports (like SOEM's ecx_configdc): each slave hangs
  // on the nearest earlier slave that still has an unused open port.
  std::vector<std::size_t> free_ports(slaves_.size(), 0);
  std::vector<std::size_t> used_ports(slaves_.size(), 0);
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    auto& s = slaves_[i];
    free_ports[i] = child_ports(s).size();
    s.dc.parent.reset();
    if (i == 0) {
      continue;
    }
    std::optional<std::size_t> p = i - 1;
    while (p && free_ports[*p] == 0) {
      p = slaves_[*p].dc.parent;
    }
    if (p) {
      s.dc.parent = p;
      const auto ports = child_ports(slaves_[*p]);
      s.dc.parent_port = used_ports[*p] < ports.size() ? ports[used_ports[*p]] : 1;
      ++used_ports[*p];
      --free_ports[*p];
    }
  }
  // Delay of the link to a child = (loop time through the child's subtree
  // seen by the parent − the child's own internal loop time) / 2.
  for (const auto i : dc_slaves) {
    auto& s = slaves_[i];
    s.dc.delay_ns = 0;
    if (dc_reference_ && i == *dc_reference_) {
      continue;
    }
    if (!s.dc.parent || !slaves_[*s.dc.parent].dc.supported) {
      continue;
    }
    const auto& parent = slaves_[*s.dc.parent];
    const auto port = s.dc.parent_port;
    const std::uint32_t parent_loop =
        parent.dc.port_receive_time[port] - parent.dc.port_receive_time[previous_open_port(parent, port)];
    std::uint32_t child_loop = 0;
    const auto children = child_ports(s);
    if (!children.empty()) {
      child_loop = s.dc.port_receive_time[children.back()] - s.dc.port_receive_time[0];
    }
    const std::uint32_t link = parent_loop > child_loop ? (parent_loop - child_loop) / 2 : 0;
    s.dc.delay_ns = parent.dc.delay_ns + link;
  }
}

Status Master::write_dc_offsets(const std::vector<std::size_t>& dc_slaves) {
  // The reference's system time at the latch becomes the master's time; a
  // slave saw the same frame delay_i later, so its system time then was
  // that plus delay_i: offset_i = master time + delay_i − local latch time.
  const std::uint64_t ref_system = master_time(clock_);
  for (const auto i : dc_slaves) {
    auto& s = slaves_[i];
    s.dc.offset_ns = ref_system + s.dc.delay_ns - s.dc.processing_unit_time;
    SF_TRY(bus_.fpwr<std::uint64_t>(s.station, reg::kDcSystemTimeOffset, s.dc.offset_ns));
    SF_TRY(bus_.fpwr<std::uint32_t>(s.station, reg::kDcSystemTimeDelay, s.dc.delay_ns));
    // Restart the drift filters now that the offset jumped (datasheet II 0x0930).
    SF_TRY(bus_.fpwr<std::uint16_t>(s.station, reg::kDcSpeedCounterStart, 0x1000));
  }
  return {};
}

Status Master::static_drift_compensation() {
  const auto& ref = slaves_[*dc_reference_];
  const Bytes time(8, 0);
  auto next = clock_.now();
  // Each FRMW is one sample for the slaves' drift filters (ETG.1000.4 §9.1.3.6): a lost one is
  // not sent again and costs nothing but that sample. Only a reference that stops answering
  // for a while (many frames in a row) ends the bring-up.
  std::size_t lost_in_row = 0;
  for (std::size_t i = 0; i < options_.dc_static_drift_frames; ++i) {
    Datagram d;
    d.command = Command::FRMW;
    d.address = Datagram::physical(ref.station, reg::kDcSystemTime);
    d.data = time;
    std::array<Datagram, 1> one{std::move(d)};
    if (auto st = bus_.transceive(one, 0); st.ok()) {
      lost_in_row = 0;
    } else if (st.error().code != Errc::timeout || ++lost_in_row > options_.dc_static_drift_max_lost_in_row) {
      return st.error().with_context(
          fmt::format("DC static drift compensation (frame {} of {}, {} lost in a row)", i + 1,
                      options_.dc_static_drift_frames, lost_in_row));
    }
    next += options_.dc_static_drift_interval;
    clock_.sleep_until(next);
  }
  return {};
}

Status Master::configure_sync0(const std::vector<std::size_t>& dc_slaves) {
  if (options_.sync0_cycle.count() <= 0) {
    return {};
  }
  const auto& ref = slaves_[*dc_reference_];
  auto now = bus_.fprd<std::uint64_t>(ref.station, reg::kDcSystemTime);
  if (!now) {
    return now.error();
  }
  // Start on a whole cycle some time ahead, the same instant for every slave
  // (datasheet II 0x0990: start time in system time).
  const auto cycle = static_cast<std::uint64_t>(options_.sync0_cycle.count());
  const auto ahead = *now + static_cast<std::uint64_t>(options_.sync0_start_delay.count());
  const auto start = (ahead / cycle + 1) * cycle;
  for (const auto i : dc_slaves) {
    const auto station = slaves_[i].station;
    SF_TRY(bus_.fpwr<std::uint8_t>(station, reg::kDcActivation, 0));
    SF_TRY(bus_.fpwr<std::uint32_t>(station, reg::kDcSync0CycleTime, static_cast<std::uint32_t>(cycle)));
    SF_TRY(bus_.fpwr<std::uint64_t>(station, reg::kDcStartTimeCyclic, start));
    SF_TRY(bus_.fpwr<std::uint8_t>(station, reg::kDcActivation,
                                   reg::kDcActivationCyclic | reg::kDcActivationSync0));
  }
  return {};
}

Status Master::configure_dc() {
  std::scoped_lock lock(control_mutex_, bus_.mutex());
  std::vector<std::size_t> dc_slaves;
  SF_TRY(latch_and_read_receive_times(dc_slaves));
  if (dc_slaves.empty()) {
    dc_reference_.reset();
    log_->info("DC: no slave supports distributed clocks");
    return {};
  }
  dc_reference_ = dc_slaves.front();
  compute_topology_and_delays(dc_slaves);
  SF_TRY(write_dc_offsets(dc_slaves));
  SF_TRY(static_drift_compensation());
  SF_TRY(configure_sync0(dc_slaves));
  if (process_data_configured_) {
    SF_TRY(build_cyclic_frames());  // adds the FRMW to the cycle
  }
  for (const auto i : dc_slaves) {
    log_->debug("DC slave {}: delay {} ns, offset {}", i, slaves_[i].dc.delay_ns, slaves_[i].dc.offset_ns);
  }
  log_->info("DC: reference clock slave {}, {} DC slaves", *dc_reference_, dc_slaves.size());
  return {};
}

Result<std::int32_t> Master::read_dc_difference(std::size_t position) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  auto raw = bus_.fprd<std::uint32_t>(slaves_[position].station, reg::kDcSystemTimeDifference);
  if (!raw) {
    return raw.error();
  }
  // Sign and magnitude: bit 31 set = local copy smaller than received time.
  const auto magnitude = static_cast<std::int32_t>(*raw & 0x7fffffffU);
  return (*raw & 0x80000000U) != 0 ? -magnitude : magnitude;
}

Status Master::restore_dc(std::size_t position) {
  auto& s = slaves_[position];
  if (!dc_reference_ || !s.dc.supported) {
    return {};
  }
  const auto& ref = slaves_[*dc_reference_];
  // Latch once more and carry the reference's time over, as at start-up.
  const std::array<std::uint8_t, 4> zero{};
  auto wkc = bus_.write(Command::BWR, Datagram::physical(0, reg::kDcReceiveTimePort0), zero);
  if (!wkc) {
    return wkc.error();
  }
  auto local = bus_.fprd<std::uint64_t>(s.station, reg::kDcReceiveTimeProcessingUnit);
  if (!local) {
    return local.error();
  }
  if (position == *dc_reference_) {
    s.dc.offset_ns = master_time(clock_) - *local;
  } else {
    auto ref_local = bus_.fprd<std::uint64_t>(ref.station, reg::kDcReceiveTimeProcessingUnit);
    if (!ref_local) {
      return ref_local.error();
    }
    s.dc.offset_ns = *ref_local + ref.dc.offset_ns + s.dc.delay_ns - *local;
  }
  SF_TRY(bus_.fpwr<std::uint64_t>(s.station, reg::kDcSystemTimeOffset, s.dc.offset_ns));
  SF_TRY(bus_.fpwr<std::uint32_t>(s.station, reg::kDcSystemTimeDelay, s.dc.delay_ns));
  return bus_.fpwr<std::uint16_t>(s.station, reg::kDcSpeedCounterStart, 0x1000);
}

}  // namespace sf::ethercat::master
