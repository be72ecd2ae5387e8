#include "esc_core.hpp"

#include <algorithm>
#include <chrono>

#include "sf/core/log.hpp"
#include "sf/ethercat/sii.hpp"

namespace sf::ethercat::slave {

namespace detail {

namespace {

std::int64_t to_ns(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

Bytes eeprom_image(const Device& device) {
  auto image = encode_sii(device.sii());
  if (!image) {
    log::get("ethercat")
        ->error("slave {}: cannot encode its SII: {}", device.kind(), image.error().describe());
    return {};
  }
  return std::move(*image);
}

}  // namespace

EscCore::EscCore(std::unique_ptr<Device> device, const Clock& clock, EscOptions options)
    : device_(std::move(device)),
      clock_(&clock),
      options_(options),
      map_(&register_map(options.fmmus, options.sync_managers)),
      mailbox_(device_->objects()) {
  ram_end_ = std::min<std::uint32_t>(reg::kProcessRam + 1024U * options_.ram_kib, EscMemory::kSize);
  scratch_.resize(kMaxDatagramLength + 8);
  scratch_bits_.resize(kMaxDatagramLength + 8);
  const auto& sms = device_->sii().sync_managers;
  for (std::size_t n = 0; n < sms.size() && n < reg::kMaxSyncManagers; ++n) {
    const int idx = static_cast<int>(n);
    switch (sms[n].type) {
      case SiiSyncManagerType::mailbox_out:
        mbx_out_sm_ = idx;
        break;
      case SiiSyncManagerType::mailbox_in:
        mbx_in_sm_ = idx;
        break;
      case SiiSyncManagerType::outputs:
        out_sm_ = out_sm_ < 0 ? idx : out_sm_;
        break;
      case SiiSyncManagerType::inputs:
        in_sm_ = in_sm_ < 0 ? idx : in_sm_;
        break;
      case SiiSyncManagerType::unused:
        break;
    }
  }
  sii_.load(eeprom_image(*device_), options_.sii_read_8_bytes,
            SiiTiming{options_.sii_busy_time, options_.sii_busy_polls});
  dc_.configure(options_.drift_ppm, options_.local_time_offset_ns);
  device_->set_emergency_sink([this](const CoeEmergency& e) {
    if (state_ != AlState::Init && mbx_in_sm_ >= 0) {
      mailbox_.push_emergency(e);
    }
  });
  link_[0] = true;
  power_on();
}

void EscCore::power_on() {
  now_ns_ = to_ns(clock_->now());
  mem_.bytes.fill(0);
  last_written_.fill(0);
  mem_.put<std::uint8_t>(reg::kType, options_.type);
  mem_.put<std::uint8_t>(reg::kRevision, options_.revision);
  mem_.put<std::uint16_t>(reg::kBuild, options_.build);
  mem_.put<std::uint8_t>(reg::kFmmuCount, options_.fmmus);
  mem_.put<std::uint8_t>(reg::kSyncManagerCount, options_.sync_managers);
  mem_.put<std::uint8_t>(reg::kRamSize, options_.ram_kib);
  mem_.put<std::uint8_t>(reg::kPortDescriptor, options_.port_descriptor);
  mem_.put<std::uint16_t>(reg::kFeatures, options_.features);
  mem_.put<std::uint32_t>(reg::kDlControl, 0x00070001);  // forwarding rule 1, RX FIFO size 7
  mem_.put<std::uint16_t>(reg::kAlControl, static_cast<std::uint16_t>(AlState::Init));
  mem_.put<std::uint16_t>(reg::kWatchdogDivider, reg::kDefaultWatchdogDivider);
  mem_.put<std::uint16_t>(reg::kWatchdogTimePdi, reg::kDefaultWatchdogTime);
  mem_.put<std::uint16_t>(reg::kWatchdogTimeProcessData, reg::kDefaultWatchdogTime);
  mem_.put<std::uint16_t>(reg::kWatchdogStatusProcessData, 1);
  sii_.power_on(mem_);
  sms_.power_on(mem_, options_.sync_managers);
  fmmus_.power_on(mem_, options_.fmmus);
  dc_.power_on(mem_, now_ns_);
  mailbox_.reset();
  rx_pdo_.clear();
  tx_pdo_.clear();
  touched_ = 0;
  touched_fmmu_ = touched_sm_ = 0;
  sm_written_ = sm_read_ = 0;
  al_control_pending_ = repeat_pending_ = reset_pending_ = false;
  reset_sequence_ = 0;
  state_ = AlState::Init;
  al_error_ = false;
  al_code_ = 0;
  id_requested_ = false;
  al_event_ = false;
  op_pending_ = false;
  outputs_received_ = false;
  watchdog_expired_ = false;
  watchdog_last_ = now_ns_;
  device_->power_on();
  apply_pdi_sync_managers();
  write_al_status();
  update_dl_status();
}

void EscCore::set_link(unsigned port, bool up) {
  if (port < link_.size()) {
    link_[port] = up;
    update_dl_status();
  }
}

bool EscCore::forwards(unsigned port) const {
  return port < link_.size() && link_[port] && !loop_closed(port);
}

void EscCore::begin_frame(const FramePass& pass) {
  pass_ = pass;
  now_ns_ = pass.port0;
  register_write_enable_ = esc_write_enable_ = false;
  mem_.put<std::uint8_t>(reg::kRegisterWriteEnable, 0);
  mem_.put<std::uint8_t>(reg::kEscWriteEnable, 0);
  timers(now_ns_);
  publish_inputs();
}

void EscCore::end_frame() {
  if (reset_pending_) {
    power_on();
    return;
  }
  const std::uint16_t written = std::exchange(sm_written_, std::uint16_t{0});
  const std::uint16_t read = std::exchange(sm_read_, std::uint16_t{0});
  exchange_outputs(written);
  if (in_sm_ >= 0 && (read & (1U << static_cast<unsigned>(in_sm_))) != 0) {
    last_inputs_.assign(published_inputs_.begin(), published_inputs_.end());
  }
  if (al_control_pending_) {
    al_control_pending_ = false;
    on_al_control();
  }
  service_mailbox(written, read);
}

void EscCore::poll() {
  now_ns_ = to_ns(clock_->now());
  timers(now_ns_);
}

}  // namespace detail

// --- Esc: forwards to the core ---

Esc::Esc(std::unique_ptr<Device> device, const Clock& clock, EscOptions options)
    : core_(std::make_unique<detail::EscCore>(std::move(device), clock, options)) {}
Esc::~Esc() = default;
Esc::Esc(Esc&&) noexcept = default;
Esc& Esc::operator=(Esc&&) noexcept = default;

void Esc::begin_frame(const FramePass& pass) {
  core_->begin_frame(pass);
}
void Esc::process(DatagramView datagram) {
  core_->process(datagram);
}
ByteSpan Esc::last_outputs() const {
  return core_->last_outputs();
}
ByteSpan Esc::last_inputs() const {
  return core_->last_inputs();
}
void Esc::end_frame() {
  core_->end_frame();
}
void Esc::poll() {
  core_->poll();
}
void Esc::emulation_paused(std::chrono::nanoseconds gap) {
  core_->emulation_paused(gap.count());
}
void Esc::power_on() {
  core_->power_on();
}
void Esc::set_link(unsigned port, bool up) {
  core_->set_link(port, up);
}
bool Esc::forwards(unsigned port) const {
  return core_->forwards(port);
}

ByteSpan Esc::memory() const {
  return ByteSpan(core_->memory().bytes);
}
std::uint8_t Esc::read8(std::uint16_t address) const {
  return core_->memory().get<std::uint8_t>(address);
}
std::uint16_t Esc::read16(std::uint16_t address) const {
  return core_->memory().get<std::uint16_t>(address);
}
std::uint32_t Esc::read32(std::uint16_t address) const {
  return core_->memory().get<std::uint32_t>(address);
}
std::uint64_t Esc::read64(std::uint16_t address) const {
  return core_->memory().get<std::uint64_t>(address);
}
AlStatus Esc::al_status() const {
  return AlStatus::decode(read16(reg::kAlStatus));
}
AlState Esc::state() const {
  return core_->state();
}
std::uint16_t Esc::al_status_code() const {
  return core_->al_status_code();
}
std::uint16_t Esc::station_address() const {
  return read16(reg::kStationAddress);
}
Bytes Esc::eeprom() const {
  return core_->sii().image();
}
Device& Esc::device() {
  return core_->device();
}
const Device& Esc::device() const {
  return core_->device();
}
ObjectDictionary& Esc::objects() {
  return core_->device().objects();
}
std::int64_t Esc::local_time(std::int64_t segment_ns) const {
  return core_->dc().local(segment_ns);
}
std::uint64_t Esc::system_time(std::int64_t segment_ns) const {
  return core_->dc().system(core_->memory(), segment_ns);
}
std::uint64_t Esc::sync0_events() const {
  return core_->dc().sync0_events();
}
std::uint32_t Esc::watchdog_expirations() const {
  return core_->watchdog_expirations();
}
const EscOptions& Esc::options() const {
  return core_->options();
}

}  // namespace sf::ethercat::slave
