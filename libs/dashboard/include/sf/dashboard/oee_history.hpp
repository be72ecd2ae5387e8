// OEE from the historian: a machine's PackML series found by the browse paths the cloud gateway
// registers them under and read into a MachineHistory (oee.hpp computes from it).
//
// The gateway subscribes each controller's "/Objects/Machines/<M>" (line_configs.cpp) and
// registers one series per variable with the browse path it found it by (server_link.cpp), so the
// machine model's variables (factory/src/opcua/model_layout.hpp) are the series
//   /Objects/Machines/<M>/PackML/Status/StateCurrent        Int32, OPC 30050 state number
//   /Objects/Machines/<M>/PackML/Status/UnitModeCurrent     Int32, 1 Production, 2 Maintenance, 3 Manual
//   /Objects/Machines/<M>/PackML/Admin/ProdProcessedCount   Int32
//   /Objects/Machines/<M>/PackML/Admin/ProdDefectiveCount   Int32
// with <M> the layout's name as line::iri_name writes it ("scara-robot-1" → ScaraRobot1). The
// state's transitions, not Admin.StateCumulativeTime, give the times: the cumulative times are
// published in whole seconds and start again at a restart, the transitions are exact for any range.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/dashboard/oee.hpp"
#include "sf/historian/store.hpp"

namespace sf::dashboard {

// The machine model's variables OEE reads, below the machine.
inline constexpr std::string_view kStateCurrent = "PackML/Status/StateCurrent",
                                  kUnitModeCurrent = "PackML/Status/UnitModeCurrent",
                                  kProdProcessedCount = "PackML/Admin/ProdProcessedCount",
                                  kProdDefectiveCount = "PackML/Admin/ProdDefectiveCount";

// "/Objects/Machines/<iri_name(machine)>/<variable>"
std::string machine_series_path(std::string_view machine, std::string_view variable);

// The machines with a StateCurrent series in the store (model names, sorted, each once).
Result<std::vector<std::string>> oee_machines(historian::Store& store);

// A read stops with Errc::limit_exceeded past this many samples of one series: narrow the range.
inline constexpr std::size_t kMaxSamplesPerSeries = 2'000'000;

// The machine's series over the range, each with its last sample before `from`. Errors:
// Errc::not_found when the store has no StateCurrent series of the machine, Errc::invalid_argument
// when several servers hold one (the servers named), the store's errors as they come. A sample
// with a Bad status or a value that is no state makes the state unknown from its time on; such
// counter samples are left out.
Result<MachineHistory> read_machine_history(historian::Store& store, std::string_view machine,
                                            TimeRange range);

// machine_oee / machine_oee_trend / line_oee / line_oee_trend of oee.hpp over the store. For a
// live range clip `to` to now first: the last state holds until `to`. An empty `machines` list
// takes every machine oee_machines finds.
Result<MachineOee> machine_oee(historian::Store& store, std::string_view machine, TimeRange range,
                               const IdealCycleTimes& ideal);
Result<std::vector<MachineOee>> machine_oee_trend(historian::Store& store, std::string_view machine,
                                                  TimeRange range, Micros bucket,
                                                  const IdealCycleTimes& ideal);
Result<LineOee> line_oee(historian::Store& store, const std::vector<std::string>& machines, TimeRange range,
                         const IdealCycleTimes& ideal, std::string_view constraint = {});
Result<std::vector<LineOee>> line_oee_trend(historian::Store& store, const std::vector<std::string>& machines,
                                            TimeRange range, Micros bucket, const IdealCycleTimes& ideal,
                                            std::string_view constraint = {});

}  // namespace sf::dashboard
