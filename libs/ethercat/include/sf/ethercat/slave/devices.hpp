// The emulated device models and the factory the segment spec uses:
//   smart-controller  the paper's slave: 8 CiA 402 axes (CSP), 32 DI (0x6000),
//                     32 DO (0x7000), CoE mailbox, DC
//   servo             one CiA 402 axis, CoE mailbox, DC
//   digital-io        8 DI (0x6000), 8 DO (0x7000), no mailbox: the fixed
//                     mapping is only in the SII TxPDO/RxPDO categories
// Default PDO mapping per axis n (objects at 0x6000 + 0x800·n):
//   RxPDO 0x1600+n: controlword 0x6040:0 (16), target position 0x607A:0 (32)
//   TxPDO 0x1A00+n: statusword 0x6041:0 (16), position actual 0x6064:0 (32),
//                   velocity actual 0x606C:0 (32)
// and for the digital IO one more RxPDO/TxPDO after the axes' ones.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/ethercat/slave/cia402.hpp"
#include "sf/ethercat/slave/device.hpp"

namespace sf::ethercat::slave {

inline constexpr std::string_view kSmartControllerKind = "smart-controller";
inline constexpr std::string_view kServoKind = "servo";
inline constexpr std::string_view kDigitalIoKind = "digital-io";

inline constexpr std::uint32_t kSmartControllerProductCode = 0x00010008;
inline constexpr std::uint32_t kServoProductCode = 0x00020001;
inline constexpr std::uint32_t kDigitalIoProductCode = 0x00030808;

// Mailbox and process-data layout of the CoE devices (SII defaults).
inline constexpr std::uint16_t kMailboxOutStart = 0x1000;
inline constexpr std::uint16_t kMailboxInStart = 0x1080;
inline constexpr std::uint16_t kMailboxSize = 128;
inline constexpr std::uint16_t kOutputsStart = 0x1100;
inline constexpr std::uint16_t kInputsStart = 0x1800;

struct DeviceOptions {
  std::uint32_t serial = 0;
  std::uint16_t station_alias = 0;  // SII word 4 → register 0x0012
  AxisDefaults axis;
};

// A drive with N CiA 402 axes and optionally 32 digital inputs/outputs.
class DriveDevice : public Device {
 public:
  struct Config {
    std::string_view kind;
    std::string name;
    std::uint32_t product_code = 0;
    unsigned axes = 1;
    bool digital_io = false;
  };
  DriveDevice(const Config& config, const DeviceOptions& options);

  [[nodiscard]] std::string_view kind() const override { return kind_; }
  [[nodiscard]] const SiiInfo& sii() const override { return sii_; }
  [[nodiscard]] ObjectDictionary& objects() override { return od_; }

  void on_state_change(AlState from, AlState to) override;
  void on_outputs() override;
  void update_inputs() override;
  void tick(Clock::time_point now) override;
  void on_sync0(std::uint64_t system_time, std::uint32_t events) override;
  void apply_safe_outputs() override;
  void power_on() override;
  [[nodiscard]] bool outputs_safe() const override;

  [[nodiscard]] std::size_t axis_count() const { return axes_.size(); }
  [[nodiscard]] Cia402Axis& axis(std::size_t n) { return *axes_.at(n); }
  [[nodiscard]] const Cia402Axis& axis(std::size_t n) const { return *axes_.at(n); }
  [[nodiscard]] bool has_digital_io() const { return inputs_ != nullptr; }
  // Digital IO (0 without): inputs are set by the test/simulation, outputs
  // are what the master wrote (0 in their safe state).
  void set_digital_inputs(std::uint32_t value);
  [[nodiscard]] std::uint32_t digital_inputs() const;
  [[nodiscard]] std::uint32_t digital_outputs() const;
  [[nodiscard]] std::uint64_t sync0_events() const { return sync0_events_; }
  [[nodiscard]] std::uint64_t last_sync0_time() const { return last_sync0_; }

 private:
  void build_objects(const Config& config, const DeviceOptions& options);
  void build_sii(const Config& config, const DeviceOptions& options);
  void report_faults();

  std::string kind_;
  ObjectDictionary od_;
  SiiInfo sii_;
  std::vector<std::unique_ptr<Cia402Axis>> axes_;
  std::vector<std::uint16_t> reported_errors_;
  OdEntry* inputs_ = nullptr;
  OdEntry* outputs_ = nullptr;
  OdEntry* error_register_ = nullptr;
  bool have_tick_ = false;
  Clock::time_point last_tick_{};
  std::uint64_t sync0_events_ = 0;
  std::uint64_t last_sync0_ = 0;
};

class SmartController final : public DriveDevice {
 public:
  static constexpr unsigned kAxes = 8;
  explicit SmartController(const DeviceOptions& options = {});
};

class Servo final : public DriveDevice {
 public:
  explicit Servo(const DeviceOptions& options = {});
};

// 8 digital inputs and 8 digital outputs without a mailbox (like an
// EL1008/EL2008 pair in one device).
class DigitalIo final : public Device {
 public:
  explicit DigitalIo(const DeviceOptions& options = {});

  [[nodiscard]] std::string_view kind() const override { return kDigitalIoKind; }
  [[nodiscard]] const SiiInfo& sii() const override { return sii_; }
  [[nodiscard]] ObjectDictionary& objects() override { return od_; }
  void apply_safe_outputs() override;
  void power_on() override;
  [[nodiscard]] bool outputs_safe() const override { return outputs() == 0; }

  void set_inputs(std::uint8_t value) { inputs_->set<std::uint8_t>(value); }
  [[nodiscard]] std::uint8_t inputs() const { return inputs_->get<std::uint8_t>(); }
  [[nodiscard]] std::uint8_t outputs() const { return outputs_->get<std::uint8_t>(); }

 private:
  ObjectDictionary od_;
  SiiInfo sii_;
  OdEntry* inputs_ = nullptr;
  OdEntry* outputs_ = nullptr;
};

// One device model the segment spec can name: the table in device_factory.cpp is the one list
// of them (make_device, device_kinds and the CLI's help read it).
struct DeviceKind {
  std::string_view name;     // as in a segment spec: "smart-controller"
  std::string_view summary;  // one line for help texts
  std::unique_ptr<Device> (*make)(const DeviceOptions& options);
};
std::span<const DeviceKind> device_models();
// The names of device_models(), in the order of the list above.
std::span<const std::string_view> device_kinds();
// The model named `kind`; unknown kinds are an error listing the known ones.
Result<const DeviceKind*> find_device_model(std::string_view kind);
// A new device of that kind; unknown kinds are an error listing the known ones.
Result<std::unique_ptr<Device>> make_device(std::string_view kind, const DeviceOptions& options = {});

}  // namespace sf::ethercat::slave
