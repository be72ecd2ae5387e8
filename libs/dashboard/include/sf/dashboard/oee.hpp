// OEE (overall equipment effectiveness) of the line's machines from their PackML state and Admin
// counters (OPC 30050 §6.3.3-4, after ANSI/ISA-TR88.00.02), with the KPI definitions of
// ISO 22400-2:2014 (work unit KPIs "Availability", "Effectiveness", "Quality ratio" and
// "OEE index"; time and quantity elements):
//
//   PBT  planned busy time         the range minus planned downtime and minus unknown time
//   APT  actual production time    time in Execute (in Production mode)
//   PQ   produced quantity         increments of Admin.ProdProcessedCount
//   SQ   scrap quantity            increments of Admin.ProdDefectiveCount
//   GQ   good quantity             PQ − SQ
//   PRI  planned runtime per item  the machine's ideal cycle time (an input)
//
//   availability = APT / PBT    performance ("effectiveness") = PRI × PQ / APT    quality = GQ / PQ
//   OEE = availability × performance × quality
//
// Which state's time counts where (time_element()):
//   production (APT):          Execute. TR88.00.02 §4.3: the unit is producing.
//   busy, not producing:       in PBT, lowers availability (ISO 22400-2 unit down and delay
//                              times ADOT/ADET). Held, Holding, Unholding (TR88 §4.3: internal
//                              conditions stop production, a machine or operator problem);
//                              Suspended, Suspending, Unsuspending (external conditions: starved
//                              or blocked by its neighbours, still a loss of this unit's busy
//                              time); Aborting, Aborted, Clearing (a fault); the acting states
//                              on the way into or out of production (Starting, Resetting,
//                              Stopping, Completing), setup time in ISO 22400 terms.
//   planned downtime:          outside PBT. Stopped, Idle, Complete: the unit has not been
//                              asked to produce (no Start, or its run completed), so it is not
//                              planned busy. Any state in Maintenance mode (UnitModeCurrent 2,
//                              OPC 30050 §6.5.2), which PackML "shall [use] to document planned
//                              maintenance occurrence and duration" (its mode descriptions as
//                              OPC 30060 §11.8 gives them) and ISO 22400-2 keeps out of busy
//                              time (APMT). Manual mode (3, "fault diagnosis of unplanned
//                              technical intervention") is busy, not producing, in any state.
//   unknown:                   Undefined, a sample with a Bad status, and time before the first
//                              state sample: no data, counted in none of the above.
//
// Everything here is pure: the histories come in as values (oee_history.hpp reads them from the
// historian), times are historian timestamps (µs, UTC).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/factory/packml.hpp"
#include "sf/historian/types.hpp"
#include "sf/line/layout.hpp"

namespace sf::dashboard {

using historian::Micros;
using historian::Timestamp;

// [from, to)
struct TimeRange {
  Timestamp from{};
  Timestamp to{};
  [[nodiscard]] Micros length() const { return to - from; }
  bool operator==(const TimeRange&) const = default;
};

enum class TimeElement : std::uint8_t { production, busy_not_producing, planned_downtime, unknown };
std::string_view to_string(TimeElement element);

// nullopt state: unknown. A mode outside the PackMLMode values follows the state.
TimeElement time_element(std::optional<factory::PackMLState> state, std::optional<factory::PackMLMode> mode);

// A value of PackML.Status.StateCurrent from its source time on; nullopt: unknown from then on
// (a Bad sample, a number that is no state).
struct StateChange {
  Timestamp time{};
  std::optional<factory::PackMLState> state;
};

// A value of PackML.Status.UnitModeCurrent from its source time on.
struct ModeChange {
  Timestamp time{};
  std::optional<factory::PackMLMode> mode;
};

// A value of a counter (ProdProcessedCount, ProdDefectiveCount) at its source time.
struct CounterSample {
  Timestamp time{};
  std::uint64_t value = 0;
};

// What the historian holds of one machine, each series oldest first. A series may start before
// the range: the last state (and mode, and counter value) before `from` is what holds at `from`.
struct MachineHistory {
  std::string machine;
  std::vector<StateChange> states;
  std::vector<ModeChange> modes;  // empty: Production mode throughout (the default mode)
  std::vector<CounterSample> processed;
  std::vector<CounterSample> defective;
};

// Increments of a counter over the range: the samples with from <= time < to against the last
// value before them. A value lower than the one before is a restart of the machine (its Admin
// counters start at 0, packml.hpp), so the value itself is what was counted since. Without a
// sample before the range the first sample in it is only the base: what it counts happened at
// an unknown time. nullopt: no sample at or before the range's end (nothing known).
std::optional<std::uint64_t> counter_increments(const std::vector<CounterSample>& samples, TimeRange range);

struct MachineOee {
  std::string machine;
  TimeRange range;
  // No state known anywhere in the range (no sample before its end, or all unknown): every
  // figure below is empty or zero, and no KPI is given.
  bool no_data = true;
  std::array<Micros, factory::kPackMLStates> time_in_state{};  // by OPC 30050 state number
  Micros unknown_time{0};                                      // of the range, state unknown
  Micros planned_busy_time{0};                                 // PBT
  Micros actual_production_time{0};                            // APT
  Micros busy_not_producing{0};                                // PBT − APT
  Micros planned_downtime{0};
  std::optional<std::uint64_t> produced;   // PQ; nullopt: no counter data
  std::optional<std::uint64_t> defective;  // SQ
  std::optional<std::uint64_t> good;       // GQ (PQ − SQ, at least 0)
  std::optional<double> ideal_cycle_s;     // PRI
  // nullopt: undefined (a zero denominator or a missing element), never a zero standing in.
  std::optional<double> availability;          // PBT = 0: undefined
  std::optional<double> performance;           // clamped to 1, see performance_measured
  std::optional<double> performance_measured;  // PRI × PQ / APT as measured; APT = 0: undefined
  std::optional<double> quality;               // PQ = 0: undefined (nothing made, nothing to judge)
  std::optional<double> oee;
};

// Performance above 1 means the machine made more than its ideal cycle time allows: the ideal is
// a nominal figure rather than the machine's best (the uploader's cycle varies ±10 % around the
// layout's cycle_s), or products whose Execute time fell into the range before are counted in
// this one (counters are sampled on change). OEE keeps to 0..1 with performance clamped at 1;
// the measured figure stays in performance_measured so a wrong ideal cycle time shows.
inline constexpr double kPerformanceLimit = 1.0;

// The OEE of one machine over `range`. A factor that is 0 makes OEE 0 even when another factor is
// undefined (a machine planned busy that never executed, or one that executed and made nothing,
// has OEE 0 whatever the quality of its non-existent products). An empty range (to <= from) has
// no data.
MachineOee machine_oee(const MachineHistory& history, TimeRange range, std::optional<double> ideal_cycle_s);

// Machine (OPC UA model name, line::iri_name of the layout name) → ideal cycle time, seconds per
// unit counted (one job: a box loaded or unloaded, a robot's load of candies).
using IdealCycleTimes = std::map<std::string, double, std::less<>>;

// What the layout knows: the box uploader's and downloader's cycle_s. The robots' and belts'
// cycle depends on the job (distances, candy counts), so their ideal comes from configuration.
IdealCycleTimes ideal_cycle_times(const line::Layout& layout);

// The ideal cycle time of a machine (by layout or model name), if known.
std::optional<double> ideal_cycle_of(const IdealCycleTimes& ideal, std::string_view machine);

// The line's OEE is its constraint's: a line cannot turn out more than its slowest machine
// lets through, so the machine with the longest ideal cycle time sets the line's ideal rate and
// its losses are the line's (the bottleneck rate of a serial line; OEE measured at the
// constraint, as TPM practice does). A product of the machines' OEEs would count every
// machine's loss as a loss of the line, wrong when buffers or parallel robots absorb it; the
// mean would hide the constraint. ISO 22400-2 defines OEE per work unit only.
struct LineOee {
  TimeRange range;
  std::vector<MachineOee> machines;
  std::optional<std::string> constraint;  // nullopt: no machine has an ideal cycle time
  std::optional<double> availability;     // the constraint's figures
  std::optional<double> performance;
  std::optional<double> quality;
  std::optional<double> oee;
};

// `constraint`: the machine to take (e.g. configured by the line's engineer); empty: the
// machine with the longest ideal cycle time (ties: the lower OEE).
Result<LineOee> line_oee(std::vector<MachineOee> machines, std::string_view constraint = {});

// Consecutive buckets [from + k·bucket, from + (k+1)·bucket) of the range, the last one ending
// at `to`. Errors: an empty range, bucket <= 0, more than kMaxBuckets.
inline constexpr std::size_t kMaxBuckets = 10'000;
Result<std::vector<TimeRange>> buckets(TimeRange range, Micros bucket);

// The OEE of each bucket (the trend of one machine).
Result<std::vector<MachineOee>> machine_oee_trend(const MachineHistory& history, TimeRange range,
                                                  Micros bucket, std::optional<double> ideal_cycle_s);

// The line's OEE per bucket.
Result<std::vector<LineOee>> line_oee_trend(const std::vector<MachineHistory>& histories, TimeRange range,
                                            Micros bucket, const IdealCycleTimes& ideal,
                                            std::string_view constraint = {});

}  // namespace sf::dashboard
