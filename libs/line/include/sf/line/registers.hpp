// The register maps of the line's legacy controllers on Modbus TCP, one per
// device kind: the conveyor PLCs (Siemens in the paper), the box uploader and
// downloader PLCs (Mitsubishi) and the closed controllers of the legacy
// robots (TOSHIBA THL300, DENSO VS-6577G). A gateway reads and writes these
// addresses as it would on the real machines (they are the machines'
// documented interface); the plant serves them; docs/plant.md prints them
// from the same tables (`smartfactory plant registers`).
//
// Handshake of the job-driven devices (uploader, downloader, legacy robot):
// the client writes the job registers, then sets `start`; the device answers
// busy, then done (or fault with a code); the client clears `start`, and the
// device clears done and is ready again. `fault_reset` (rising edge)
// clears a latched fault once its cause is gone.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "sf/modbus/protocol.hpp"
#include "sf/modbus/register_bank.hpp"

namespace sf::line {

// The fault codes every legacy device reports in its fault_code register.
enum class FaultCode : std::uint16_t {
  none = 0,
  jam = 1,               // conveyor jammed
  dispenser_empty = 2,   // the gripper closed over an empty dispenser
  no_box = 3,            // no box in place at the station
  place_failed = 4,      // the candy did not land in the slot
  bad_job = 5,           // unknown box type, candy type, slot or station
  station_occupied = 6,  // the uploader's place on the belt stays taken
  unreachable = 7,       // a target outside the arm's reach
  part_lost = 8,         // no part in the gripper where one should be
  axis_fault = 9,        // a drive faulted (smart robot: CiA 402 error code)
};
std::string_view to_string(FaultCode code);

struct RegisterEntry {
  modbus::Table table;
  std::uint16_t address;
  std::string_view name;
  std::string_view meaning;
};

// Entries repeated per station or candy type start at kRepeatBase (+ index).
inline constexpr std::uint16_t kRepeatBase = 16;
inline constexpr std::uint16_t kMaxRepeats = 16;

namespace conveyor_plc {
// coils
inline constexpr std::uint16_t kMotorRun = 0;
inline constexpr std::uint16_t kReverse = 1;
inline constexpr std::uint16_t kDivert = 2;  // exit to the belt's second `next`
inline constexpr std::uint16_t kFaultReset = 3;
inline constexpr std::uint16_t kStopper = kRepeatBase;  // + station
// discrete inputs
inline constexpr std::uint16_t kEntryEye = 0;
inline constexpr std::uint16_t kExitEye = 1;
inline constexpr std::uint16_t kJam = 2;
inline constexpr std::uint16_t kRunning = 3;
inline constexpr std::uint16_t kFault = 4;
inline constexpr std::uint16_t kStationEye = kRepeatBase;  // + station
// holding registers
inline constexpr std::uint16_t kSpeedSetpoint = 0;  // mm/s, 0 = the layout's speed
// input registers
inline constexpr std::uint16_t kSpeed = 0;  // mm/s while running
inline constexpr std::uint16_t kFaultCode = 1;
inline constexpr std::uint16_t kOdometer = 2;  // belt travel, metres (wraps at 65536)
inline constexpr std::uint16_t kStationCount = 3;
inline constexpr std::uint16_t kStationBox =
    kRepeatBase;  // + station: box id read by its tag reader, 0 = none
std::span<const RegisterEntry> map();
}  // namespace conveyor_plc

namespace transfer_plc {  // box uploader and box downloader
// coils
inline constexpr std::uint16_t kStart = 0;
inline constexpr std::uint16_t kFaultReset = 1;
// discrete inputs
inline constexpr std::uint16_t kReady = 0;
inline constexpr std::uint16_t kBusy = 1;
inline constexpr std::uint16_t kDone = 2;
inline constexpr std::uint16_t kFault = 3;
inline constexpr std::uint16_t kBoxPresent = 4;  // a box in place at its station
// holding registers
inline constexpr std::uint16_t kBoxType = 0;  // uploader: catalog box type + 1
// input registers
inline constexpr std::uint16_t kBoxId = 0;  // the box of the last job
inline constexpr std::uint16_t kFaultCode = 1;
inline constexpr std::uint16_t kJobsDone = 2;
inline constexpr std::uint16_t kWeight = 3;      // downloader: inspected weight, 0.1 g
inline constexpr std::uint16_t kCandyTotal = 4;  // downloader: candies counted
inline constexpr std::uint16_t kStationBox = 5;  // its station's tag reader: box in place, 0 = none
inline constexpr std::uint16_t kCandyCount =
    kRepeatBase;  // + catalog candy type: counted by the vision check
std::span<const RegisterEntry> map();
}  // namespace transfer_plc

namespace robot_controller {  // legacy robots
// coils
inline constexpr std::uint16_t kStart = 0;
inline constexpr std::uint16_t kFaultReset = 1;
// discrete inputs
inline constexpr std::uint16_t kReady = 0;
inline constexpr std::uint16_t kBusy = 1;
inline constexpr std::uint16_t kDone = 2;
inline constexpr std::uint16_t kFault = 3;
inline constexpr std::uint16_t kPartPresent = 4;
inline constexpr std::uint16_t kBoxInPlace = kRepeatBase;  // + station of the robot
// holding registers
inline constexpr std::uint16_t kCandyType = 0;  // catalog candy type + 1
inline constexpr std::uint16_t kSlot = 1;       // slot of the box, from 0
inline constexpr std::uint16_t kStation = 2;    // index in the robot's stations, from 0
// input registers
inline constexpr std::uint16_t kFaultCode = 0;
inline constexpr std::uint16_t kJobsDone = 1;
inline constexpr std::uint16_t kJoint = 2;  // + joint (6): signed, mrad or mm
inline constexpr std::uint16_t kToolX = 8;  // signed mm
inline constexpr std::uint16_t kToolY = 9;
inline constexpr std::uint16_t kToolZ = 10;
inline constexpr std::uint16_t kPhase = 11;        // the job's step, 0 = idle
inline constexpr std::uint16_t kTemperature = 12;  // the hottest drive's winding, 0.1 °C
// The drives' rated winding temperature, °C: above it the controller's data sheet asks for a
// stop (the ontology's sf:maxTemperature of the robot).
inline constexpr double kMaxTemperature = 70.0;
inline constexpr std::uint16_t kStationBox =
    kRepeatBase;  // + station of the robot: box id read by its tag reader, 0 = none
std::span<const RegisterEntry> map();
}  // namespace robot_controller

// The bank layout of each kind (every table from address 0).
modbus::BankLayout conveyor_bank_layout();
modbus::BankLayout transfer_bank_layout();
modbus::BankLayout robot_bank_layout();

// A markdown table of a map: | table | address | name | meaning |.
std::string markdown(std::span<const RegisterEntry> map);

}  // namespace sf::line
