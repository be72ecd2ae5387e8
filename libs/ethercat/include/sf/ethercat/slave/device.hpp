// Device: the application behind an emulated ESC's process data interface
// (PDI) — what the firmware of a real slave does. The ESC owns the EtherCAT
// side (registers, SyncManagers, mailbox, AL state machine); the device
// supplies its SII contents and object dictionary and reacts to hooks.
//
// Process data flows through the object dictionary: the ESC unpacks received
// RxPDOs into the mapped objects and then calls on_outputs(); it calls
// update_inputs() and then packs the mapped objects into the TxPDOs.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>

#include "sf/core/clock.hpp"
#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/sii.hpp"
#include "sf/ethercat/slave/object_dictionary.hpp"

namespace sf::ethercat::slave {

// Where a device sends CoE emergencies (ETG.1000.6 §5.6.4); the ESC queues
// them for the read mailbox.
using EmergencySink = std::function<void(const CoeEmergency&)>;

class Device {
 public:
  virtual ~Device() = default;

  // "servo", "digital-io", "smart-controller" (the segment spec names).
  [[nodiscard]] virtual std::string_view kind() const = 0;
  // Identity, mailbox layout, SyncManagers, PDOs; the ESC writes
  // encode_sii() of it into its EEPROM at power-on.
  [[nodiscard]] virtual const SiiInfo& sii() const = 0;
  // Communication objects (0x1000–0x1FFF) and device objects. Devices
  // without a mailbox keep one too: their fixed PDO mapping lives in it.
  [[nodiscard]] virtual ObjectDictionary& objects() = 0;

  // A device may refuse a state transition with an AL status code (0 = ok);
  // called after the ESC's own checks passed.
  virtual std::uint16_t check_transition(AlState /*from*/, AlState /*to*/) { return 0; }
  virtual void on_state_change(AlState /*from*/, AlState /*to*/) {}
  // Received outputs have been unpacked into the object dictionary (OP).
  virtual void on_outputs() {}
  // Refresh input objects; they are packed into the TxPDOs right after.
  virtual void update_inputs() {}
  // Advance the device model to `now` (before every frame and poll).
  virtual void tick(Clock::time_point /*now*/) {}
  // `events` SYNC0 pulses happened since the last call, the latest at
  // `system_time` (ns, DC system time).
  virtual void on_sync0(std::uint64_t /*system_time*/, std::uint32_t /*events*/) {}
  // Outputs must go to their safe state: watchdog expired or OP was left.
  virtual void apply_safe_outputs() {}
  // True while every physical output is in its safe state (outputs off,
  // drives not powering their motors): what an operator checks after a trip.
  [[nodiscard]] virtual bool outputs_safe() const = 0;
  // Power-on: the device restarts (state lost).
  virtual void power_on() {}
  // Set by the ESC; devices without a mailbox ignore it.
  void set_emergency_sink(EmergencySink sink) { emergency_sink_ = std::move(sink); }

 protected:
  void emergency(const CoeEmergency& e) const {
    if (emergency_sink_) {
      emergency_sink_(e);
    }
  }

 private:
  EmergencySink emergency_sink_;
};

}  // namespace sf::ethercat::slave
