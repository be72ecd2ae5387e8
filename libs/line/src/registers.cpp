#include "sf/line/registers.hpp"

#include <fmt/format.h>

namespace sf::line {

using modbus::Table;

std::string_view to_string(FaultCode code) {
  switch (code) {
    case FaultCode::none:
      return "none";
    case FaultCode::jam:
      return "jam";
    case FaultCode::dispenser_empty:
      return "dispenser empty";
    case FaultCode::no_box:
      return "no box at the station";
    case FaultCode::place_failed:
      return "place failed";
    case FaultCode::bad_job:
      return "bad job";
    case FaultCode::station_occupied:
      return "station occupied";
    case FaultCode::unreachable:
      return "target out of reach";
    case FaultCode::part_lost:
      return "part lost";
    case FaultCode::axis_fault:
      return "axis fault";
  }
  return "unknown fault";
}

namespace conveyor_plc {
namespace {
constexpr RegisterEntry kMap[] = {
    {Table::coils, kMotorRun, "motor_run", "belt motor on"},
    {Table::coils, kReverse, "reverse", "run backwards (no transfer to the next belt)"},
    {Table::coils, kDivert, "divert", "exit onto the second belt of `next` (diverter)"},
    {Table::coils, kFaultReset, "fault_reset", "rising edge clears a latched fault whose cause is gone"},
    {Table::coils, kStopper, "stopper[k]", "16 + k: stopper at station k raised (holds an arriving box)"},
    {Table::discrete_inputs, kEntryEye, "entry_eye", "photo-eye 5 cm after the entry sees a box"},
    {Table::discrete_inputs, kExitEye, "exit_eye", "photo-eye 5 cm before the exit sees a box"},
    {Table::discrete_inputs, kJam, "jam", "jam detected (the belt slips under its boxes)"},
    {Table::discrete_inputs, kRunning, "running", "motor running"},
    {Table::discrete_inputs, kFault, "fault", "latched fault; the motor is off until fault_reset"},
    {Table::discrete_inputs, kStationEye, "station_eye[k]", "16 + k: photo-eye at station k sees a box"},
    {Table::holding_registers, kSpeedSetpoint, "speed_setpoint", "mm/s; 0 = the layout's speed"},
    {Table::input_registers, kSpeed, "speed", "mm/s while running, else 0"},
    {Table::input_registers, kFaultCode, "fault_code", "FaultCode of the latched fault"},
    {Table::input_registers, kOdometer, "odometer", "belt travel in metres (wraps)"},
    {Table::input_registers, kStationCount, "station_count", "stations on this belt"},
    {Table::input_registers, kStationBox, "station_box[k]",
     "16 + k: id of the box in place at station k (its tag reader), 0 = none"},
};
}  // namespace
std::span<const RegisterEntry> map() {
  return kMap;
}
}  // namespace conveyor_plc

namespace transfer_plc {
namespace {
constexpr RegisterEntry kMap[] = {
    {Table::coils, kStart, "start", "job request (handshake)"},
    {Table::coils, kFaultReset, "fault_reset", "rising edge clears a latched fault"},
    {Table::discrete_inputs, kReady, "ready", "idle, no fault: a start is accepted"},
    {Table::discrete_inputs, kBusy, "busy", "a job runs"},
    {Table::discrete_inputs, kDone, "done", "the job finished; cleared with start"},
    {Table::discrete_inputs, kFault, "fault", "the job failed; see fault_code"},
    {Table::discrete_inputs, kBoxPresent, "box_present", "a box stands in place at the machine's station"},
    {Table::holding_registers, kBoxType, "box_type", "uploader: catalog box type + 1"},
    {Table::input_registers, kBoxId, "box_id", "box of the last job"},
    {Table::input_registers, kFaultCode, "fault_code", "FaultCode of the latched fault"},
    {Table::input_registers, kJobsDone, "jobs_done", "jobs finished since power-on"},
    {Table::input_registers, kWeight, "weight", "downloader: weight of the last box, 0.1 g"},
    {Table::input_registers, kCandyTotal, "candy_total", "downloader: candies counted in the last box"},
    {Table::input_registers, kStationBox, "station_box",
     "id of the box in place at the machine's station (its tag reader), 0 = none"},
    {Table::input_registers, kCandyCount, "candy_count[c]", "16 + c: downloader: candies of catalog type c"},
};
}  // namespace
std::span<const RegisterEntry> map() {
  return kMap;
}
}  // namespace transfer_plc

namespace robot_controller {
namespace {
constexpr RegisterEntry kMap[] = {
    {Table::coils, kStart, "start", "job request (handshake)"},
    {Table::coils, kFaultReset, "fault_reset", "rising edge clears a latched fault"},
    {Table::discrete_inputs, kReady, "ready", "idle, no fault: a start is accepted"},
    {Table::discrete_inputs, kBusy, "busy", "a job runs"},
    {Table::discrete_inputs, kDone, "done", "the job finished; cleared with start"},
    {Table::discrete_inputs, kFault, "fault", "the job failed; see fault_code"},
    {Table::discrete_inputs, kPartPresent, "part_present", "a candy is in the gripper"},
    {Table::discrete_inputs, kBoxInPlace, "box_in_place[k]", "16 + k: a box stands at the robot's station k"},
    {Table::holding_registers, kCandyType, "candy_type", "catalog candy type + 1"},
    {Table::holding_registers, kSlot, "slot", "slot of the box, from 0"},
    {Table::holding_registers, kStation, "station", "which of the robot's stations, from 0"},
    {Table::input_registers, kFaultCode, "fault_code", "FaultCode of the latched fault"},
    {Table::input_registers, kJobsDone, "jobs_done", "jobs finished since power-on"},
    {Table::input_registers, kJoint, "joint[j]",
     "2 + j, j < 6: joint position, signed mrad (revolute) or mm"},
    {Table::input_registers, kToolX, "tool_x", "tool point x, signed mm"},
    {Table::input_registers, kToolY, "tool_y", "tool point y, signed mm"},
    {Table::input_registers, kToolZ, "tool_z", "tool point z, signed mm"},
    {Table::input_registers, kPhase, "phase", "step of the running job, 0 = idle"},
    {Table::input_registers, kTemperature, "temperature", "the hottest drive's winding temperature, 0.1 °C"},
    {Table::input_registers, kStationBox, "station_box[k]",
     "16 + k: id of the box in place at the robot's station k (its tag reader), 0 = none"},
};
}  // namespace
std::span<const RegisterEntry> map() {
  return kMap;
}
}  // namespace robot_controller

namespace {
constexpr std::uint16_t kBits = kRepeatBase + kMaxRepeats;
constexpr std::uint16_t kWords = kRepeatBase + kMaxRepeats;
}  // namespace

modbus::BankLayout conveyor_bank_layout() {
  return {{0, kBits}, {0, kBits}, {0, 4}, {0, kWords}};
}
modbus::BankLayout transfer_bank_layout() {
  return {{0, 4}, {0, 8}, {0, 4}, {0, kWords}};
}
modbus::BankLayout robot_bank_layout() {
  return {{0, 4}, {0, kBits}, {0, 4}, {0, kWords}};
}

std::string markdown(std::span<const RegisterEntry> map) {
  std::string out = "| table | address | name | meaning |\n|---|---|---|---|\n";
  for (const auto& e : map) {
    out += fmt::format("| {} | {} | `{}` | {} |\n", modbus::to_string(e.table), e.address, e.name, e.meaning);
  }
  return out;
}

}  // namespace sf::line
