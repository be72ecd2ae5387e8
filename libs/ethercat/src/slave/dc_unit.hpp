// Distributed clocks of one ESC (ET1100 datasheet section I §9, registers II
// §3.49, 0x0900–0x09FF):
//   - a local clock from its own oscillator (configurable drift and offset
//     against the segment clock), piecewise linear so the time control loop
//     can change its rate without jumps;
//   - receive-time latches per port on a write to 0x0900;
//   - the local copy of the system time, 0x0910 = local time + offset 0x0920;
//   - the time control loop: a write to 0x0910 (ARMW/FRMW from the master)
//     compares Δt = (local + offset − delay 0x0928) − received, shows the
//     filtered mean in 0x092C (bit 31: local copy smaller) and adjusts the
//     clock rate (speed counter diff 0x0932) until Δt vanishes;
//   - the SYNC0 cyclic unit: start time 0x0990, cycle time 0x09A0.
//
// The control loop is our model of the ESC's, not its gate-level design: a
// proportional-integral loop whose time constant scales with Speed Counter
// Start 0x0930 (default 0x1000 → 50 ms); 0x0932 holds the frequency part in
// units of 0.1 ppm, limited to ±(Speed Counter Start − 0x7F) as the datasheet
// limits the register.
#pragma once

#include <cstdint>

#include "esc_memory.hpp"

namespace sf::ethercat::slave::detail {

struct DcPorts {
  std::int64_t port0 = 0;
  std::int64_t port1 = 0;
  bool port1_valid = false;
};

class DcUnit {
 public:
  void configure(double drift_ppm, std::int64_t local_offset_ns);
  void power_on(EscMemory& m, std::int64_t now_ns);

  [[nodiscard]] std::int64_t local(std::int64_t t) const;
  [[nodiscard]] std::uint64_t system(const EscMemory& m, std::int64_t t) const;

  // 0x0900 written by a frame that passed at `ports`.
  void latch_receive_times(EscMemory& m, const DcPorts& ports);
  // 0x0910 written with `received` (lower 32 bits) by a frame processed at t.
  void on_system_time_written(EscMemory& m, std::uint32_t received, std::int64_t t);
  // 0x0930 written: reset the loop filters.
  void on_speed_counter_start_written(EscMemory& m);
  // Before an ECAT read of 0x0910: store the system time at t.
  void refresh_system_time(EscMemory& m, std::int64_t t) const;

  // SYNC0 cyclic unit: the master wrote activation/start/cycle registers.
  void on_cyclic_written(EscMemory& m, std::int64_t t);
  // SYNC0 pulses due at segment time t; returns how many (and the system
  // time of the latest in *last).
  std::uint32_t poll_sync0(EscMemory& m, std::int64_t t, std::uint64_t* last);
  [[nodiscard]] std::uint64_t sync0_events() const { return sync0_events_; }

 private:
  void set_rate(std::int64_t t, double correction);

  double drift_ = 0.0;  // relative, e.g. 50e-6
  // Piecewise-linear local clock: local = anchor_local + (t − anchor_t)·rate.
  std::int64_t anchor_t_ = 0;
  double anchor_local_ = 0.0;
  double rate_ = 1.0;
  // Control loop state.
  double frequency_ = 0.0;  // integral part (relative rate correction)
  double mean_ = 0.0;       // filtered Δt for 0x092C
  bool have_update_ = false;
  std::int64_t last_update_t_ = 0;
  // SYNC0.
  bool sync_active_ = false;
  bool sync_pending_ = false;
  std::uint64_t next_sync0_ = 0;
  std::uint64_t sync0_events_ = 0;
};

}  // namespace sf::ethercat::slave::detail
