#include "dc_unit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "sf/ethercat/registers.hpp"

namespace sf::ethercat::slave::detail {

namespace {
constexpr std::uint16_t kDefaultSpeedCounterStart = 0x1000;
constexpr std::uint8_t kDefaultTimeDiffFilterDepth = 0x04;
constexpr std::uint8_t kDefaultSpeedCounterFilterDepth = 0x0C;
constexpr double kNominalLoopTimeConstantNs = 50e6;  // at Speed Counter Start 0x1000
constexpr double kMaxCorrection = 1e-3;              // the loop slews at most 1000 ppm
constexpr double kSpeedCounterUnit = 1e-7;           // 0x0932 in 0.1 ppm
constexpr std::uint8_t kActivationAutoActivate = 1U << 3;
constexpr std::uint8_t kActivationPlausibilityCheck = 1U << 5;
constexpr std::uint8_t kActivationStatusSync0Pending = 1U << 0;
}  // namespace

void DcUnit::configure(double drift_ppm, std::int64_t local_offset_ns) {
  drift_ = drift_ppm * 1e-6;
  anchor_t_ = 0;
  anchor_local_ = static_cast<double>(local_offset_ns);
  rate_ = 1.0 + drift_;
}

void DcUnit::power_on(EscMemory& m, std::int64_t now_ns) {
  // The oscillator keeps running through a power cycle of the ESC logic in
  // this model; the control loop and the registers start over.
  set_rate(now_ns, 0.0);
  frequency_ = 0.0;
  mean_ = 0.0;
  have_update_ = false;
  sync_active_ = false;
  sync_pending_ = false;
  next_sync0_ = 0;
  std::fill(m.at(0x0900), m.at(0x0A00), std::uint8_t{0});
  m.put<std::uint16_t>(reg::kDcSpeedCounterStart, kDefaultSpeedCounterStart);
  *m.at(reg::kDcSystemTimeDiffFilterDepth) = kDefaultTimeDiffFilterDepth;
  *m.at(reg::kDcSpeedCounterFilterDepth) = kDefaultSpeedCounterFilterDepth;
}

std::int64_t DcUnit::local(std::int64_t t) const {
  const double elapsed = static_cast<double>(t - anchor_t_) * rate_;
  return static_cast<std::int64_t>(std::llround(anchor_local_ + elapsed));
}

std::uint64_t DcUnit::system(const EscMemory& m, std::int64_t t) const {
  return static_cast<std::uint64_t>(local(t)) + m.get<std::uint64_t>(reg::kDcSystemTimeOffset);
}

void DcUnit::set_rate(std::int64_t t, double correction) {
  anchor_local_ += static_cast<double>(t - anchor_t_) * rate_;
  anchor_t_ = t;
  rate_ = 1.0 + drift_ + correction;
}

void DcUnit::latch_receive_times(EscMemory& m, const DcPorts& ports) {
  const std::int64_t at0 = local(ports.port0);
  m.put<std::uint32_t>(reg::dc_receive_time(0), static_cast<std::uint32_t>(at0));
  m.put<std::uint64_t>(reg::kDcReceiveTimeProcessingUnit, static_cast<std::uint64_t>(at0));
  if (ports.port1_valid) {
    m.put<std::uint32_t>(reg::dc_receive_time(1), static_cast<std::uint32_t>(local(ports.port1)));
  }
}

void DcUnit::refresh_system_time(EscMemory& m, std::int64_t t) const {
  m.put<std::uint64_t>(reg::kDcSystemTime, system(m, t));
}

void DcUnit::on_speed_counter_start_written(EscMemory& m) {
  frequency_ = 0.0;
  mean_ = 0.0;
  have_update_ = false;
  m.put<std::uint16_t>(reg::kDcSpeedCounterDiff, 0);
  m.put<std::uint32_t>(reg::kDcSystemTimeDifference, 0);
}

void DcUnit::on_system_time_written(EscMemory& m, std::uint32_t received, std::int64_t t) {
  // Δt = (t_local + t_offset − t_delay) − t_received, on the lower 32 bits
  // (section I §9.1.5); positive: the local copy runs ahead.
  const auto copy = static_cast<std::uint32_t>(system(m, t) - m.get<std::uint32_t>(reg::kDcSystemTimeDelay));
  const auto delta = static_cast<double>(static_cast<std::int32_t>(copy - received));

  const unsigned depth = *m.at(reg::kDcSystemTimeDiffFilterDepth) & 0x0FU;
  mean_ = have_update_ ? mean_ + (delta - mean_) / static_cast<double>(1U << depth) : delta;
  const double magnitude = std::min(std::fabs(mean_), 2147483647.0);
  std::uint32_t diff = static_cast<std::uint32_t>(std::llround(magnitude));
  if (mean_ < 0) {
    diff |= 0x80000000U;
  }
  m.put<std::uint32_t>(reg::kDcSystemTimeDifference, diff);

  // PI loop, critically damped with time constant tau (longer than 4 update
  // intervals so it stays stable for slow masters).
  double interval = have_update_ ? static_cast<double>(t - last_update_t_) : 1e6;
  interval = std::clamp(interval, 1e3, 1e8);
  have_update_ = true;
  last_update_t_ = t;
  const unsigned start = std::max<unsigned>(m.get<std::uint16_t>(reg::kDcSpeedCounterStart) & 0x7FFFU, 0x80U);
  const double tau = std::max(kNominalLoopTimeConstantNs * start / kDefaultSpeedCounterStart, 4.0 * interval);
  const double kp = 2.0 / tau;
  const double ki = 1.0 / (tau * tau);
  const double limit = static_cast<double>(start - 0x7FU) * kSpeedCounterUnit;
  frequency_ = std::clamp(frequency_ - ki * delta * interval, -limit, limit);
  const double correction = std::clamp(frequency_ - kp * delta, -kMaxCorrection, kMaxCorrection);
  m.put<std::int16_t>(reg::kDcSpeedCounterDiff,
                      static_cast<std::int16_t>(std::llround(frequency_ / kSpeedCounterUnit)));
  set_rate(t, correction);
}

void DcUnit::on_cyclic_written(EscMemory& m, std::int64_t t) {
  std::uint8_t activation = *m.at(reg::kDcActivation);
  if ((activation & kActivationAutoActivate) != 0) {
    activation |= reg::kDcActivationCyclic;
    *m.at(reg::kDcActivation) = activation;
  }
  const bool active =
      (activation & reg::kDcActivationCyclic) != 0 && (activation & reg::kDcActivationSync0) != 0;
  if (!active) {
    sync_active_ = false;
    *m.at(reg::kDcActivationStatus) = 0;
    return;
  }
  if (sync_active_) {
    return;
  }
  sync_active_ = true;
  next_sync0_ = m.get<std::uint64_t>(reg::kDcStartTimeCyclic);
  const std::uint64_t now = system(m, t);
  // A start time in the past is only reached after the 64-bit time wraps
  // unless the plausibility check (0x0981 bit 5) starts at once.
  sync_pending_ = next_sync0_ < now && (activation & kActivationPlausibilityCheck) == 0;
  if (next_sync0_ < now && !sync_pending_) {
    next_sync0_ = now;
  }
  *m.at(reg::kDcActivationStatus) = kActivationStatusSync0Pending;
}

std::uint32_t DcUnit::poll_sync0(EscMemory& m, std::int64_t t, std::uint64_t* last) {
  if (!sync_active_ || sync_pending_) {
    return 0;
  }
  const std::uint64_t now = system(m, t);
  if (now < next_sync0_) {
    return 0;
  }
  const std::uint64_t cycle = m.get<std::uint32_t>(reg::kDcSync0CycleTime);
  const std::uint64_t n = cycle == 0 ? 1 : (now - next_sync0_) / cycle + 1;
  if (last != nullptr) {
    *last = next_sync0_ + (n - 1) * cycle;
  }
  if (cycle == 0) {
    sync_active_ = false;  // single shot
  } else {
    next_sync0_ += n * cycle;
  }
  m.put<std::uint64_t>(reg::kDcStartTimeCyclic, next_sync0_);  // reads as "next SYNC0 pulse"
  *m.at(reg::kDcActivationStatus) = 0;
  sync0_events_ += n;
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(n, 0xFFFFFFFFU));
}

}  // namespace sf::ethercat::slave::detail
