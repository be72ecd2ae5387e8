// Faults the plant can inject at its hardware faces, on demand or timed:
//
//   jam:BELT                   the belt slips under its boxes; jam input and
//                              exit photo-eye stuck on; the PLC latches fault 1
//   dispenser-empty:DISPENSER  stock 0 (clearing refills it)
//   mixup:DISPENSER            refilled with the wrong candy: every pick there
//                              takes the catalog's next candy type (wrapping)
//   axis-fault:ROBOT:AXIS[:CODE]  a smart robot's drive faults (CiA 402 fault
//                              bit, 0x603F = CODE, default 0x7310 overspeed)
//   cable-cut:ROBOT            the smart robot's EtherCAT slave drops out of
//                              the ring (cleared: power and link return, INIT)
//   plc-unreachable:MACHINE    its Modbus server stops answering
//   plc-exception:MACHINE[:CODE]  every Modbus request answered with
//                              exception CODE (default 4, server device failure)
//   overheat:ROBOT             a legacy robot's drive cooling fails: its windings
//                              heat towards 85 °C (115 °C while moving), which
//                              its controller reports in its temperature register
//   box-drop:BOX               the box falls off the line (cannot be cleared)
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::plant {

enum class FaultKind {
  jam,
  dispenser_empty,
  mixup,
  axis_fault,
  cable_cut,
  plc_unreachable,
  plc_exception,
  overheat,
  box_drop
};
std::string_view to_string(FaultKind kind);

struct FaultSpec {
  FaultKind kind = FaultKind::jam;
  std::string target;          // belt, dispenser, robot, machine or box id
  std::uint32_t argument = 0;  // axis (axis-fault), exception code (plc-exception)
  std::uint16_t code = 0;      // axis-fault: CiA 402 error code
  // Timed faults: injected at `at` (simulated time since start) and cleared
  // `duration` later (none: stays until cleared).
  std::optional<std::chrono::nanoseconds> at;
  std::optional<std::chrono::nanoseconds> duration;
  bool operator==(const FaultSpec&) const = default;
};

// "kind:target[:argument[:code]]" as listed above; errors name the part.
Result<FaultSpec> parse_fault(std::string_view text);
// Back to the text form (without the timing).
std::string format(const FaultSpec& fault);

}  // namespace sf::plant
