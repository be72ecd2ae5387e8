// Drive devices: the smart controller (8 axes + digital IO) and the servo
// (1 axis), CoE slaves with DC, as ETG.6010 multi-axis drives lay them out.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "sf/core/log.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/pdo.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"

namespace sf::ethercat::slave {

namespace {

constexpr std::uint32_t kDeviceTypeServoDrive = 0x00020192;  // CiA 402 (0x192), servo drive
constexpr double kMaxStep = 1e-3;        // the motor model integrates in steps of at most 1 ms
constexpr unsigned kMaxSubsteps = 1000;  // beyond that (a long pause) in larger steps
constexpr std::uint8_t kErrorRegisterGeneric = 0x01;
constexpr std::uint8_t kErrorRegisterProfile = 0x20;  // device profile specific

}  // namespace

DriveDevice::DriveDevice(const Config& config, const DeviceOptions& options) : kind_(config.kind) {
  build_objects(config, options);
  build_sii(config, options);
}

void DriveDevice::build_objects(const Config& config, const DeviceOptions& options) {
  add_identity_objects(od_, DeviceIdentity{kDeviceTypeServoDrive, kVendorId, config.product_code, 0x00010000,
                                           options.serial, config.name, "1.0", "1.0"});
  error_register_ = od_.find(0x1001, 0);
  std::vector<std::uint16_t> rx;
  std::vector<std::uint16_t> tx;
  for (unsigned n = 0; n < config.axes; ++n) {
    axes_.push_back(std::make_unique<Cia402Axis>(od_, n, options.axis));
    const Cia402Axis& a = *axes_.back();
    const PdoEntryRef rx_entries[] = {{a.object(0x6040), 0, 16}, {a.object(0x607A), 0, 32}};
    const PdoEntryRef tx_entries[] = {
        {a.object(0x6041), 0, 16}, {a.object(0x6064), 0, 32}, {a.object(0x606C), 0, 32}};
    const auto rx_index = static_cast<std::uint16_t>(kRxPdoMappingFirst + n);
    const auto tx_index = static_cast<std::uint16_t>(kTxPdoMappingFirst + n);
    add_pdo_mapping(od_, rx_index, "Axis " + std::to_string(n) + " RxPDO", rx_entries, true);
    add_pdo_mapping(od_, tx_index, "Axis " + std::to_string(n) + " TxPDO", tx_entries, true);
    rx.push_back(rx_index);
    tx.push_back(tx_index);
  }
  reported_errors_.assign(config.axes, 0);
  if (config.digital_io) {
    inputs_ = &od_.add_var(0x6000, "Digital inputs", DataType::Unsigned32, access::kRO | access::kTxPdo);
    outputs_ = &od_.add_var(0x7000, "Digital outputs", DataType::Unsigned32, access::kRW | access::kRxPdo);
    const PdoEntryRef rx_entries[] = {{0x7000, 0, 32}};
    const PdoEntryRef tx_entries[] = {{0x6000, 0, 32}};
    const auto rx_index = static_cast<std::uint16_t>(kRxPdoMappingFirst + config.axes);
    const auto tx_index = static_cast<std::uint16_t>(kTxPdoMappingFirst + config.axes);
    add_pdo_mapping(od_, rx_index, "Digital outputs", rx_entries, true);
    add_pdo_mapping(od_, tx_index, "Digital inputs", tx_entries, true);
    rx.push_back(rx_index);
    tx.push_back(tx_index);
  }
  add_pdo_assignment(od_, kRxPdoAssignment, rx, true);
  add_pdo_assignment(od_, kTxPdoAssignment, tx, true);
}

void DriveDevice::build_sii(const Config& config, const DeviceOptions& options) {
  PdoMap rx;
  PdoMap tx;
  (void)rx.build(od_, kRxPdoAssignment);
  (void)tx.build(od_, kTxPdoAssignment);
  sii_.pdi_control = 0x0005;        // SPI PDI
  sii_.sync_impulse_length = 1000;  // 10 µs
  sii_.station_alias = options.station_alias;
  sii_.identity = SiiIdentity{kVendorId, config.product_code, 0x00010000, options.serial};
  sii_.standard_mailbox = SiiMailbox{kMailboxOutStart, kMailboxSize, kMailboxInStart, kMailboxSize};
  sii_.bootstrap_mailbox = sii_.standard_mailbox;
  sii_.mailbox_protocols = sii::protocol::kCoE;
  SiiGeneral general;
  general.group = "smartfactory";
  general.order = std::string(config.kind);
  general.name = config.name;
  general.coe_details = sii::coe_details::kSdo | sii::coe_details::kSdoInfo | sii::coe_details::kPdoAssign |
                        sii::coe_details::kPdoConfiguration | sii::coe_details::kSdoCompleteAccess;
  general.physical_port = 0x0011;  // ports 0 and 1: MII
  sii_.general = general;
  sii_.fmmus = {SiiFmmuUsage::outputs, SiiFmmuUsage::inputs, SiiFmmuUsage::sm_status};
  sii_.sync_managers = {
      SiiSyncManager{kMailboxOutStart, kMailboxSize, 0x26, 0, 0x01, SiiSyncManagerType::mailbox_out},
      SiiSyncManager{kMailboxInStart, kMailboxSize, 0x22, 0, 0x01, SiiSyncManagerType::mailbox_in},
      SiiSyncManager{kOutputsStart, static_cast<std::uint16_t>(rx.byte_size()), 0x64, 0, 0x01,
                     SiiSyncManagerType::outputs},
      SiiSyncManager{kInputsStart, static_cast<std::uint16_t>(tx.byte_size()), 0x20, 0, 0x01,
                     SiiSyncManagerType::inputs},
  };
  add_sync_manager_objects(od_, sii_.sync_managers);
  sii_.rx_pdos = sii_pdos(od_, kRxPdoAssignment, 2, false);
  sii_.tx_pdos = sii_pdos(od_, kTxPdoAssignment, 3, false);
  SiiDcMode free_run;
  free_run.name = "SM-Synchron";
  SiiDcMode dc;
  dc.name = "DC-Synchron";
  dc.assign_activate = 0x0300;  // cyclic unit + SYNC0
  sii_.dc_modes = {free_run, dc};
  if (auto fitted = fit_eeprom_size(sii_); !fitted) {
    log::get("ethercat")->error("{}: {}", config.kind, fitted.error().describe());
  }
}

void DriveDevice::on_state_change(AlState from, AlState to) {
  if (from == AlState::Op && to != AlState::Op) {
    for (auto& a : axes_) {
      a->communication_lost();
    }
  }
}

void DriveDevice::on_outputs() {
  for (auto& a : axes_) {
    a->apply_controlword();
  }
}

void DriveDevice::update_inputs() {
  report_faults();
}

void DriveDevice::tick(Clock::time_point now) {
  if (!have_tick_) {
    have_tick_ = true;
    last_tick_ = now;
  }
  double dt = std::chrono::duration<double>(now - last_tick_).count();
  last_tick_ = std::max(last_tick_, now);
  dt = std::max(dt, 0.0);
  const auto steps = static_cast<unsigned>(std::clamp(std::ceil(dt / kMaxStep), 1.0, double{kMaxSubsteps}));
  for (auto& a : axes_) {
    a->apply_controlword();  // also picks up controlwords written by SDO
    for (unsigned i = 0; i < steps; ++i) {
      a->step(dt / steps);
    }
  }
  report_faults();
}

void DriveDevice::report_faults() {
  bool any = false;
  for (std::size_t n = 0; n < axes_.size(); ++n) {
    const std::uint16_t error = axes_[n]->error_code();
    any |= error != 0;
    if (error != reported_errors_[n]) {
      reported_errors_[n] = error;
      if (error != 0) {
        CoeEmergency e;
        e.error_code = error;
        e.error_register = kErrorRegisterGeneric | kErrorRegisterProfile;
        e.data[0] = static_cast<std::uint8_t>(n);  // which axis
        emergency(e);
      }
    }
  }
  error_register_->set<std::uint8_t>(any ? kErrorRegisterGeneric | kErrorRegisterProfile : 0);
}

void DriveDevice::on_sync0(std::uint64_t system_time, std::uint32_t events) {
  sync0_events_ += events;
  last_sync0_ = system_time;
}

void DriveDevice::apply_safe_outputs() {
  if (outputs_ != nullptr) {
    outputs_->set<std::uint32_t>(0);
  }
  for (auto& a : axes_) {
    a->communication_lost();
  }
}

bool DriveDevice::outputs_safe() const {
  if (outputs_ != nullptr && outputs_->get<std::uint32_t>() != 0) {
    return false;
  }
  return std::none_of(axes_.begin(), axes_.end(),
                      [](const auto& a) { return a->state() == Cia402State::OperationEnabled; });
}

void DriveDevice::power_on() {
  for (auto& a : axes_) {
    a->power_on();
  }
  std::fill(reported_errors_.begin(), reported_errors_.end(), std::uint16_t{0});
  if (outputs_ != nullptr) {
    outputs_->set<std::uint32_t>(0);
  }
  have_tick_ = false;
  sync0_events_ = 0;
  last_sync0_ = 0;
}

void DriveDevice::set_digital_inputs(std::uint32_t value) {
  if (inputs_ != nullptr) {
    inputs_->set<std::uint32_t>(value);
  }
}

std::uint32_t DriveDevice::digital_inputs() const {
  return inputs_ != nullptr ? inputs_->get<std::uint32_t>() : 0;
}
std::uint32_t DriveDevice::digital_outputs() const {
  return outputs_ != nullptr ? outputs_->get<std::uint32_t>() : 0;
}

SmartController::SmartController(const DeviceOptions& options)
    : DriveDevice(Config{kSmartControllerKind, "Smart controller (8 axes, 32 DI, 32 DO)",
                         kSmartControllerProductCode, kAxes, true},
                  options) {}

Servo::Servo(const DeviceOptions& options)
    : DriveDevice(Config{kServoKind, "Servo drive (1 axis)", kServoProductCode, 1, false}, options) {}

}  // namespace sf::ethercat::slave
