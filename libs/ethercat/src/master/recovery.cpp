// Diagnosis and recovery while the segment runs (compare SOEM's ecatcheck):
// when a cycle's WKC or AL status broadcast is off, read every slave's AL
// status in one frame, name who is missing or not in the segment's state,
// and walk those slaves back step by step — a few datagrams per maintain()
// call, never a blocking wait — while the others keep exchanging data.
// A slave that lost power comes back in INIT with station address 0
// (ET1100 datasheet II 0x0010): it is re-addressed by position, checked
// against the identity read at scan time, and configured again.
#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "recovery.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

constexpr std::size_t kStatusBytes = 6;  // 0x0130 status, 0x0132 reserved, 0x0134 code
constexpr std::size_t kStatesPerFrame =
    (kMaxFrameSize - kEthernetHeaderSize - kEcatHeaderSize) / (kStatusBytes + kDatagramOverhead);
constexpr auto kRetryBackoff = std::chrono::milliseconds{100};

}  // namespace

Result<std::vector<std::pair<AlStatus, std::uint16_t>>> Master::read_all_states(std::vector<bool>& answered) {
  std::vector<std::pair<AlStatus, std::uint16_t>> states(slaves_.size());
  answered.assign(slaves_.size(), false);
  for (std::size_t first = 0; first < slaves_.size(); first += kStatesPerFrame) {
    const std::size_t n = std::min(kStatesPerFrame, slaves_.size() - first);
    std::vector<Datagram> datagrams(n);
    for (std::size_t i = 0; i < n; ++i) {
      datagrams[i].command = Command::FPRD;
      datagrams[i].address = Datagram::physical(slaves_[first + i].station, reg::kAlStatus);
      datagrams[i].data.assign(kStatusBytes, 0);
    }
    SF_TRY(bus_.transceive(datagrams));
    for (std::size_t i = 0; i < n; ++i) {
      answered[first + i] = datagrams[i].wkc == 1;
      states[first + i] = {AlStatus::decode(load_le<std::uint16_t>(datagrams[i].data.data())),
                           load_le<std::uint16_t>(datagrams[i].data.data() + 4)};
    }
  }
  return states;
}

std::vector<SlaveDiagnosis> Master::diagnose() {
  std::lock_guard lock(bus_.mutex());
  std::vector<SlaveDiagnosis> out;
  std::vector<bool> answered;
  auto states = read_all_states(answered);
  if (!states) {
    SlaveDiagnosis d;
    d.lost = true;
    d.message = "segment: " + states.error().message;
    out.push_back(std::move(d));
    return out;
  }
  for (std::size_t p = 0; p < slaves_.size(); ++p) {
    SlaveDiagnosis d;
    d.position = p;
    d.lost = !answered[p];
    d.al_status = (*states)[p].first;
    d.al_status_code = (*states)[p].second;
    if (d.lost) {
      d.message = fmt::format("slave {} ({}): lost (no answer at station 0x{:04x})", p, slaves_[p].name(),
                              slaves_[p].station);
    } else if (d.al_status.state() != target_state_ || d.al_status.error) {
      d.message = fmt::format("slave {} ({}): {}", p, slaves_[p].name(), d.al_status.to_string());
      if (d.al_status.error || d.al_status_code != 0) {
        d.message += ", AL status code " + describe_al_status_code(d.al_status_code);
      }
    } else {
      continue;
    }
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<std::size_t> Master::lost_slaves() const {
  std::lock_guard lock(bus_.mutex());  // maintain() changes the flags in the cyclic thread
  std::vector<std::size_t> out;
  for (const auto& s : slaves_) {
    if (s.lost) {
      out.push_back(s.position);
    }
  }
  return out;
}

void Master::maintain() {
  std::lock_guard lock(bus_.mutex());
  if (slaves_.empty() || !process_data_configured_) {
    return;
  }
  const auto target_bits = static_cast<std::uint16_t>(target_state_);
  const bool healthy = last_.ok() && last_.responding == slaves_.size() &&
                       (last_.al_state_or & (reg::kAlStateMask | reg::kAlErrorFlag)) == target_bits;
  if (healthy && recoveries_.empty()) {
    return;
  }
  const auto now = clock_.now();
  if (now < next_maintenance_) {
    return;
  }
  next_maintenance_ = now + options_.maintenance_interval;
  std::vector<bool> answered;
  auto read = read_all_states(answered);
  if (!read && read.error().code != Errc::timeout) {
    log_->warn("diagnosis failed: {}", read.error().describe());
    return;
  }
  // No frame came back at all: the segment is cut right behind the master.
  const auto states =
      read ? std::move(*read) : std::vector<std::pair<AlStatus, std::uint16_t>>(slaves_.size());
  if (!read) {
    answered.assign(slaves_.size(), false);
  }
  for (std::size_t p = 0; p < slaves_.size(); ++p) {
    auto& s = slaves_[p];
    const bool recovering = std::any_of(recoveries_.begin(), recoveries_.end(),
                                        [&](const Recovery& r) { return r.position == p; });
    if (!answered[p]) {
      if (!s.lost && ++s.unanswered < options_.lost_after) {
        continue;  // asked again at the next maintenance
      }
      if (!s.lost) {
        s.lost = true;
        report(SlaveEvent::Kind::lost, p, fmt::format("slave {} ({}) lost", p, s.name()));
      }
      if (!recovering) {
        recoveries_.push_back(Recovery{p, Recovery::Step::probe, {}, {}});
      }
      continue;
    }
    s.unanswered = 0;
    s.al_status = states[p].first;
    s.al_status_code = states[p].second;
    if (recovering || (s.al_status.state() == target_state_ && !s.al_status.error)) {
      continue;
    }
    report(SlaveEvent::Kind::left_state, p,
           fmt::format(
               "slave {} ({}) left {}: {}{}", p, s.name(), to_string(target_state_), s.al_status.to_string(),
               s.al_status.error ? ", AL status code " + describe_al_status_code(s.al_status_code) : ""));
    const auto state = s.al_status.state().value_or(AlState::Init);
    auto step = Recovery::Step::configure;
    if (state == AlState::PreOp) {
      step = Recovery::Step::wait_preop;
    } else if (state == AlState::SafeOp || state == AlState::Op) {
      step = Recovery::Step::wait_safeop;
    }
    recoveries_.push_back(Recovery{p, step, {}, {}});
  }
  if (std::any_of(recoveries_.begin(), recoveries_.end(),
                  [](const Recovery& r) { return r.step == Recovery::Step::probe; })) {
    locate_lost_slaves();
  }
  for (auto& r : recoveries_) {
    recover_step(r);
  }
  std::erase_if(recoveries_, [](const Recovery& r) { return r.step == Recovery::Step::done; });
}

Result<std::vector<std::uint16_t>> Master::read_ring() {
  // How many slaves answer (BRD), then each ring position's station address
  // (APRD 0x0010), all in one frame.
  std::array<std::uint8_t, 2> type{};
  auto present = bus_.read(Command::BRD, Datagram::physical(0, reg::kType), type);
  if (!present) {
    return present.error();
  }
  if (*present > slaves_.size()) {
    return make_error(Errc::state,
                      fmt::format("{} slaves answer, {} were scanned", *present, slaves_.size()));
  }
  std::vector<Datagram> ring(*present);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    ring[k].command = Command::APRD;
    ring[k].address = Datagram::physical(Bus::auto_increment_address(k), reg::kStationAddress);
    ring[k].data.assign(2, 0);
  }
  if (!ring.empty()) {
    SF_TRY(bus_.transceive(ring));
  }
  std::vector<std::uint16_t> stations;
  for (const auto& d : ring) {
    if (d.wkc != 1) {
      return make_error(Errc::state, "the ring changed while it was read");
    }
    stations.push_back(load_le<std::uint16_t>(d.data.data()));
  }
  return stations;
}

void Master::locate_lost_slaves() {
  // A lost slave has shifted the ring positions behind it, so positions
  // alone say nothing; the known neighbours do. A slave answering right
  // after known slave a (or first) is a's lost successor a + 1 — or a lost
  // slave that kept its address (a link flap). Each must then prove its
  // identity (SII vendor and product) before it is configured.
  auto ring = read_ring();
  if (!ring) {
    return;
  }
  std::optional<std::size_t> previous;  // the slave seen last in ring order
  for (std::size_t k = 0; k < ring->size(); ++k) {
    const auto station = (*ring)[k];
    const auto known = std::find_if(slaves_.begin(), slaves_.end(),
                                    [&](const SlaveInfo& s) { return s.station == station; });
    std::size_t candidate = previous ? *previous + 1 : 0;
    if (known != slaves_.end()) {
      candidate = known->position;
    }
    previous = candidate;
    auto r = std::find_if(recoveries_.begin(), recoveries_.end(), [&](const Recovery& x) {
      return x.position == candidate && x.step == Recovery::Step::probe;
    });
    if (candidate >= slaves_.size() || !slaves_[candidate].lost || r == recoveries_.end()) {
      continue;
    }
    if (readdress(candidate, k)) {
      report(SlaveEvent::Kind::found, candidate,
             fmt::format("slave {} ({}) found again at ring position {}", candidate,
                         slaves_[candidate].name(), k));
      r->step = Recovery::Step::configure;
    }
  }
}

bool Master::readdress(std::size_t position, std::size_t ring_position) {
  const auto& s = slaves_[position];
  std::array<std::uint8_t, 2> addr{};
  store_le(addr.data(), s.station);
  if (!bus_.write_one(Command::APWR, Bus::auto_increment_address(ring_position), reg::kStationAddress,
                      addr)) {
    return false;
  }
  auto identity = read_sii(position, sii::kVendorId, 4);
  if (!identity || load_le<std::uint32_t>(identity->data()) != s.sii.identity.vendor_id ||
      load_le<std::uint32_t>(identity->data() + 4) != s.sii.identity.product_code) {
    log_->warn("slave {}: the device now at ring position {} is not the one scanned", position,
               ring_position);
    // Do not leave our address on a stranger.
    store_le<std::uint16_t>(addr.data(), 0);
    (void)bus_.write_one(Command::APWR, Bus::auto_increment_address(ring_position), reg::kStationAddress,
                         addr);
    return false;
  }
  return true;
}

Result<bool> Master::replay_startup_sdos(std::size_t position) {
  const auto& sdos = slaves_[position].startup_sdos;
  if (sdos.empty()) {
    return true;
  }
  // We hold the bus lock here; taking the control lock the other way round
  // than everyone else could deadlock with a thread in an SDO transfer, so
  // only try, and come back next time if it is busy.
  std::unique_lock control(control_mutex_, std::try_to_lock);
  if (!control.owns_lock()) {
    return false;
  }
  // Blocking mailbox transfers inside the cycle: only slaves whose start-up
  // included SDO writes pay for it.
  for (const auto& sdo : sdos) {
    SF_TRY(sdo_download(position, sdo.index, sdo.subindex, sdo.data, sdo.complete_access));
  }
  return true;
}

Status Master::reconfigure_slave(std::size_t position) {
  auto& s = slaves_[position];
  SF_TRY(bus_.fpwr<std::uint16_t>(s.station, reg::kAlControl, AlControl::of(AlState::Init, true).encode()));
  const Bytes fmmus(reg::kFmmuSize * reg::kMaxFmmus, 0);
  SF_TRY(bus_.write_one(Command::FPWR, s.station, reg::kFmmuBase, fmmus));
  SF_TRY(configure_mailbox(position));
  return bus_.fpwr<std::uint16_t>(s.station, reg::kAlControl, AlControl::of(AlState::PreOp).encode());
}

void Master::report(SlaveEvent::Kind kind, std::size_t position, std::string message) {
  const bool bad = kind == SlaveEvent::Kind::lost || kind == SlaveEvent::Kind::left_state;
  log_->log(bad ? spdlog::level::warn : spdlog::level::info, "{}", message);
  if (event_handler_) {
    event_handler_(SlaveEvent{kind, position, std::move(message)});
  }
}

void Master::recovery_failed(Recovery& r, std::string_view why) {
  log_->warn("slave {} recovery: {}", r.position, why);
  r.step = slaves_[r.position].lost ? Recovery::Step::probe : Recovery::Step::configure;
  r.not_before = clock_.now() + kRetryBackoff;
}

void Master::recovery_reached(Recovery& r, AlState reached, RecoveryStep next) {
  auto& s = slaves_[r.position];
  if (reached == target_state_) {
    s.lost = false;
    r.step = Recovery::Step::done;
    report(SlaveEvent::Kind::recovered, r.position,
           fmt::format("slave {} ({}) back in {}", r.position, s.name(), to_string(target_state_)));
    return;
  }
  r.step = next;
  r.deadline = clock_.now() + options_.state_timeout;
}

void Master::recover_step(Recovery& r) {
  using Step = Recovery::Step;
  if (r.step == Step::probe || clock_.now() < r.not_before) {
    return;  // locate_lost_slaves() moves a probe on once the slave is back
  }
  if (r.step == Step::configure) {
    auto st = reconfigure_slave(r.position);
    return st ? recovery_reached(r, AlState::Init, Step::wait_preop) : recovery_failed(r, st.error().message);
  }
  auto status = read_state(r.position);
  if (!status) {
    slaves_[r.position].lost = true;
    return recovery_failed(r, status.error().message);
  }
  if (status->error) {
    (void)acknowledge_error(r.position);
    if (r.step != Step::wait_safeop) {
      return recovery_failed(r, state_error(r.position, target_state_, *status).message);
    }
  }
  const auto state = status->state().value_or(AlState::Init);
  const auto station = slaves_[r.position].station;
  const auto request = [&](AlState next) {
    return bus_.fpwr<std::uint16_t>(station, reg::kAlControl, AlControl::of(next, status->error).encode());
  };
  Status st;
  if (r.step == Step::wait_preop && state == AlState::PreOp) {
    auto replayed = replay_startup_sdos(r.position);
    if (replayed && !*replayed) {
      return;  // the mailbox is busy with another transfer: next time
    }
    st = replayed ? write_process_data_config(r.position) : Status{replayed.error()};
    if (st && options_.distributed_clocks) {
      st = restore_dc(r.position);
    }
    if (st && target_state_ != AlState::PreOp) {
      st = request(AlState::SafeOp);
    }
    return st ? recovery_reached(r, AlState::PreOp, Step::wait_safeop)
              : recovery_failed(r, st.error().message);
  }
  if (r.step == Step::wait_safeop && (state == AlState::SafeOp || state == AlState::Op)) {
    if (state == AlState::Op && !status->error) {
      return recovery_reached(r, AlState::Op, Step::done);
    }
    st = target_state_ == AlState::Op ? request(AlState::Op) : Status{};
    return st ? recovery_reached(r, AlState::SafeOp, Step::wait_op) : recovery_failed(r, st.error().message);
  }
  if (r.step == Step::wait_op && state == AlState::Op) {
    return recovery_reached(r, AlState::Op, Step::done);
  }
  if (clock_.now() >= r.deadline) {
    recovery_failed(r, fmt::format("stuck in {}", status->to_string()));
  }
}

}  // namespace sf::ethercat::master
