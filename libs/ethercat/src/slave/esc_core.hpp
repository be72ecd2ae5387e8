// The implementation behind sf::ethercat::slave::Esc. Split by concern:
//   esc_core.cpp      construction, power-on, observers, frame hooks, timers
//   esc_datagram.cpp  addressing, commands, physical/logical access, WKC
//   esc_registers.cpp register side effects (write protection, DL, reset...)
//   esc_al.cpp        AL state machine, SyncManager checks, watchdog
//   esc_pdi.cpp       the firmware side: process data and mailbox service
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "dc_unit.hpp"
#include "esc_memory.hpp"
#include "fmmu_unit.hpp"
#include "mailbox_unit.hpp"
#include "register_map.hpp"
#include "sf/core/clock.hpp"
#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/slave/device.hpp"
#include "sf/ethercat/slave/esc.hpp"
#include "sf/ethercat/slave/pdo.hpp"
#include "sii_unit.hpp"
#include "sync_manager_unit.hpp"

namespace sf::ethercat::slave::detail {

class EscCore {
 public:
  EscCore(std::unique_ptr<Device> device, const Clock& clock, EscOptions options);

  void begin_frame(const FramePass& pass);
  void process(DatagramView datagram);
  void end_frame();
  void poll();
  // The emulation did not run for `ns` (see Esc::emulation_paused).
  void emulation_paused(std::int64_t ns) { watchdog_last_ += ns; }
  void power_on();
  void set_link(unsigned port, bool up);
  [[nodiscard]] bool forwards(unsigned port) const;

  [[nodiscard]] const EscMemory& memory() const { return mem_; }
  [[nodiscard]] AlState state() const { return state_; }
  [[nodiscard]] std::uint16_t al_status_code() const { return al_code_; }
  [[nodiscard]] Device& device() { return *device_; }
  [[nodiscard]] const Device& device() const { return *device_; }
  [[nodiscard]] const SiiUnit& sii() const { return sii_; }
  [[nodiscard]] const DcUnit& dc() const { return dc_; }
  [[nodiscard]] std::uint32_t watchdog_expirations() const { return watchdog_expirations_; }
  [[nodiscard]] const Bytes& last_outputs() const { return last_outputs_; }
  [[nodiscard]] const Bytes& last_inputs() const { return last_inputs_; }
  [[nodiscard]] const EscOptions& options() const { return options_; }

 private:
  // --- esc_datagram.cpp ---
  void physical(DatagramView& dg, Command cmd, bool addressed);
  void logical(DatagramView& dg, Command cmd);
  bool ecat_read(std::uint32_t address, std::uint8_t* dst, std::size_t n);
  bool ecat_write(std::uint32_t address, const std::uint8_t* src, std::size_t n);
  void write_plain(std::uint32_t address, const std::uint8_t* src, std::size_t n);
  void write_registers(std::uint32_t address, const std::uint8_t* src, std::size_t n);
  bool read_bits(std::uint64_t physical_bit, std::uint64_t bits, std::uint8_t* dst, std::uint64_t dst_bit);
  bool write_bits(std::uint64_t physical_bit, std::uint64_t bits, const std::uint8_t* src,
                  std::uint64_t src_bit);
  void set_irq(DatagramView& dg);

  // --- esc_registers.cpp ---
  [[nodiscard]] bool write_blocked(std::uint32_t address, RegGroup group) const;
  void before_read(std::uint32_t address, std::size_t n);
  void after_read(std::uint32_t address, std::size_t n);
  void dispatch_writes();
  void on_esc_reset(std::uint8_t value);
  void update_dl_status();
  // ECAT event request 0x0210, computed when read or needed for the IRQ field.
  void update_event_request();
  [[nodiscard]] bool loop_closed(unsigned port) const;

  // --- esc_al.cpp ---
  void on_al_control();
  [[nodiscard]] std::uint16_t transition_check(AlState from, AlState to);
  [[nodiscard]] std::uint16_t check_mailbox(std::uint16_t error_code) const;
  [[nodiscard]] std::uint16_t check_process_data();
  [[nodiscard]] std::uint16_t check_sm(int sm, std::size_t bytes, bool outputs) const;
  [[nodiscard]] std::uint16_t check_dc_sync() const;
  void change_state(AlState to);
  void refuse(std::uint16_t code);
  void write_al_status();
  void apply_pdi_sync_managers();
  void check_watchdog(std::int64_t now);
  void trigger_watchdog(std::int64_t now);
  [[nodiscard]] std::int64_t watchdog_time_ns() const;

  // --- esc_pdi.cpp ---
  void timers(std::int64_t now);
  void publish_inputs();
  void exchange_outputs(std::uint16_t written);
  void service_mailbox(std::uint16_t written, std::uint16_t read);
  void fill_read_mailbox();
  void repeat_mailbox();

  std::unique_ptr<Device> device_;
  const Clock* clock_;
  EscOptions options_;
  const RegisterMap* map_;
  EscMemory mem_;
  std::array<std::uint8_t, kRegisterAreaSize> last_written_{};  // raw ECAT writes to registers
  std::uint32_t ram_end_ = 0;

  SiiUnit sii_;
  SyncManagerUnit sms_;
  FmmuUnit fmmus_;
  DcUnit dc_;
  MailboxUnit mailbox_;
  PdoMap rx_pdo_;  // outputs (0x1C12)
  PdoMap tx_pdo_;  // inputs (0x1C13)

  // SyncManager roles from the device's SII (−1: none).
  int mbx_out_sm_ = -1;
  int mbx_in_sm_ = -1;
  int out_sm_ = -1;
  int in_sm_ = -1;

  // Frame state.
  FramePass pass_;
  std::int64_t now_ns_ = 0;
  bool register_write_enable_ = false;
  bool esc_write_enable_ = false;
  std::uint32_t touched_ = 0;  // RegGroup bits
  std::uint16_t touched_fmmu_ = 0;
  std::uint16_t touched_sm_ = 0;
  std::uint16_t sm_written_ = 0;  // accumulated over the frame
  std::uint16_t sm_read_ = 0;
  bool al_control_pending_ = false;
  bool repeat_pending_ = false;
  bool reset_pending_ = false;
  unsigned reset_sequence_ = 0;
  std::vector<std::uint8_t> scratch_;
  std::vector<std::uint8_t> scratch_bits_;

  // Ports.
  std::array<bool, 4> link_{};

  // Application layer.
  AlState state_ = AlState::Init;
  bool al_error_ = false;
  std::uint16_t al_code_ = 0;
  bool id_requested_ = false;
  bool al_event_ = false;
  bool op_pending_ = false;
  std::int64_t op_pending_since_ = 0;
  bool outputs_received_ = false;

  // Copies of the last process data in each direction, for observers
  // (assign() reuses the capacity: no allocation once sized).
  Bytes last_outputs_;
  Bytes published_inputs_;  // offered to this frame
  Bytes last_inputs_;       // what the master last read
  // Process-data watchdog.
  std::int64_t watchdog_last_ = 0;
  bool watchdog_expired_ = false;
  std::uint32_t watchdog_expirations_ = 0;
};

}  // namespace sf::ethercat::slave::detail
