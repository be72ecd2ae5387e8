// OEE from PackML states and counters (oee.hpp): a scripted run against its hand computation,
// and each rule the definitions state (counter restarts, ranges between samples, no data,
// undefined factors, the clamp, Maintenance mode, the line's constraint, trend buckets).
#include "sf/dashboard/oee.hpp"

#include <gtest/gtest.h>

#include "scripted_run.hpp"

namespace sf::dashboard {
namespace {

using factory::PackMLMode;
using factory::PackMLState;
using test::at;
using test::kRunEnd;
using test::S;

constexpr double kEps = 1e-12;

TimeRange seconds(double from, double to) {
  return {at(from), at(to)};
}

Micros secs(std::int64_t s) {
  return std::chrono::seconds{s};
}

// The scripted run of scripted_run.hpp, worked by hand over [0, 1000) s:
//   planned downtime  Stopped 0-100 (from -50, before the range) + Idle 110-120 + Stopped 970-1000
//                     = 100 + 10 + 30 = 140 s
//   APT               Execute 130-530 + 650-850 = 400 + 200 = 600 s
//   busy, not making  Resetting 10 + Starting 10 + Holding 10 + Held 100 + Unholding 10
//                     + Aborting 5 + Aborted 105 + Clearing 10 = 260 s
//   PBT               1000 − 140 = 860 s (= 600 + 260)
//   PQ                ProdProcessedCount 40 at −50 s … 250 at 840 s: 250 − 40 = 210
//   SQ                ProdDefectiveCount 2 at −50 s … 12 at 840 s: 12 − 2 = 10;  GQ = 200
//   availability      600 / 860 = 0.6976744…
//   performance       PRI × PQ / APT = 2 s × 210 / 600 s = 0.7
//   quality           200 / 210 = 0.9523809…
//   OEE               0.6976744 × 0.7 × 0.9523809 = 0.4651162…  (= PRI × GQ / PBT = 400 / 860)
TEST(Oee, ScriptedRunEqualsTheHandComputation) {
  const MachineOee m = machine_oee(test::scripted_run(), seconds(0, 1000), 2.0);
  ASSERT_FALSE(m.no_data);
  EXPECT_EQ(m.planned_downtime, secs(140));
  EXPECT_EQ(m.actual_production_time, secs(600));
  EXPECT_EQ(m.busy_not_producing, secs(260));
  EXPECT_EQ(m.planned_busy_time, secs(860));
  EXPECT_EQ(m.unknown_time, secs(0));
  EXPECT_EQ(m.time_in_state[static_cast<std::size_t>(PackMLState::Aborted)], secs(105));
  EXPECT_EQ(m.time_in_state[static_cast<std::size_t>(PackMLState::Stopped)], secs(130));
  EXPECT_EQ(m.produced, 210U);
  EXPECT_EQ(m.defective, 10U);
  EXPECT_EQ(m.good, 200U);
  EXPECT_NEAR(*m.availability, 600.0 / 860.0, kEps);
  EXPECT_NEAR(*m.performance, 0.7, kEps);
  EXPECT_NEAR(*m.quality, 200.0 / 210.0, kEps);
  EXPECT_NEAR(*m.oee, 400.0 / 860.0, kEps);
  EXPECT_NEAR(*m.oee, 0.4651162790697674, 1e-12);
}

TEST(Oee, StatesCountAsTheirTimeElement) {
  EXPECT_EQ(time_element(PackMLState::Execute, PackMLMode::Production), TimeElement::production);
  EXPECT_EQ(time_element(PackMLState::Held, PackMLMode::Production), TimeElement::busy_not_producing);
  EXPECT_EQ(time_element(PackMLState::Suspended, PackMLMode::Production), TimeElement::busy_not_producing);
  EXPECT_EQ(time_element(PackMLState::Aborted, PackMLMode::Production), TimeElement::busy_not_producing);
  EXPECT_EQ(time_element(PackMLState::Idle, PackMLMode::Production), TimeElement::planned_downtime);
  EXPECT_EQ(time_element(PackMLState::Complete, PackMLMode::Production), TimeElement::planned_downtime);
  EXPECT_EQ(time_element(PackMLState::Execute, PackMLMode::Maintenance), TimeElement::planned_downtime);
  EXPECT_EQ(time_element(PackMLState::Execute, PackMLMode::Manual), TimeElement::busy_not_producing);
  EXPECT_EQ(time_element(PackMLState::Stopped, PackMLMode::Manual), TimeElement::busy_not_producing);
  EXPECT_EQ(time_element(PackMLState::Undefined, PackMLMode::Production), TimeElement::unknown);
  EXPECT_EQ(time_element(std::nullopt, PackMLMode::Production), TimeElement::unknown);
}

// A restart sets the counters back to 0: 100 → 105 is +5, 105 → 3 is +3 counted since the
// restart, 3 → 8 is +5; 13 in all.
TEST(Oee, CounterResetStartsANewBase) {
  const std::vector<CounterSample> c{{at(-10), 100}, {at(10), 105}, {at(20), 3}, {at(30), 8}};
  EXPECT_EQ(counter_increments(c, seconds(0, 40)), 13U);
  EXPECT_EQ(counter_increments(c, seconds(15, 40)), 8U);   // base 105 at 10 s
  EXPECT_EQ(counter_increments(c, seconds(-20, 15)), 5U);  // nothing before: 100 is the base
  EXPECT_EQ(counter_increments(c, seconds(0, 10)), 0U);    // a base, no change in the range
  EXPECT_EQ(counter_increments(c, seconds(-30, -20)), std::nullopt);

  MachineHistory h{"m", {{at(-10), PackMLState::Execute}}, {}, c, {}};
  const MachineOee m = machine_oee(h, seconds(0, 40), 1.0);
  EXPECT_EQ(m.produced, 13U);
  EXPECT_EQ(m.defective, 0U);  // no defective counter published: none counted
  EXPECT_NEAR(*m.performance, 13.0 / 40.0, kEps);
}

// Execute from 0 s, Held from 100 s: a range from 50 s starts in Execute.
TEST(Oee, RangeStartingMidStateTakesTheStateBefore) {
  MachineHistory h{"m", {{at(0), PackMLState::Execute}, {at(100), PackMLState::Held}}, {}, {}, {}};
  const MachineOee m = machine_oee(h, seconds(50, 150), std::nullopt);
  EXPECT_EQ(m.actual_production_time, secs(50));
  EXPECT_EQ(m.busy_not_producing, secs(50));
  EXPECT_NEAR(*m.availability, 0.5, kEps);
  // Before the first state sample the state is unknown: not downtime, not busy.
  const MachineOee early = machine_oee(h, seconds(-50, 50), std::nullopt);
  EXPECT_FALSE(early.no_data);
  EXPECT_EQ(early.unknown_time, secs(50));
  EXPECT_EQ(early.planned_busy_time, secs(50));
  EXPECT_NEAR(*early.availability, 1.0, kEps);
}

TEST(Oee, NoDataIsSaidNotZeroed) {
  const MachineOee empty = machine_oee(MachineHistory{"m", {}, {}, {}, {}}, seconds(0, 100), 2.0);
  EXPECT_TRUE(empty.no_data);
  EXPECT_FALSE(empty.availability || empty.performance || empty.quality || empty.oee || empty.produced);
  EXPECT_EQ(empty.planned_busy_time, secs(0));
  // Data only after the range, or only unknown states in it: no data either.
  MachineHistory later{"m", {{at(200), PackMLState::Execute}}, {}, {{at(200), 5}}, {}};
  EXPECT_TRUE(machine_oee(later, seconds(0, 100), 2.0).no_data);
  MachineHistory bad{"m", {{at(0), std::nullopt}}, {}, {}, {}};
  EXPECT_TRUE(machine_oee(bad, seconds(0, 100), 2.0).no_data);
  // States without counters: availability only.
  MachineHistory no_counts{"m", {{at(0), PackMLState::Execute}}, {}, {}, {}};
  const MachineOee m = machine_oee(no_counts, seconds(0, 100), 2.0);
  EXPECT_FALSE(m.no_data);
  EXPECT_NEAR(*m.availability, 1.0, kEps);
  EXPECT_FALSE(m.produced || m.performance || m.quality || m.oee);
}

TEST(Oee, ZeroProducedLeavesQualityUndefined) {
  MachineHistory h{"m", {{at(0), PackMLState::Execute}}, {}, {{at(0), 7}, {at(50), 7}}, {}};
  const MachineOee m = machine_oee(h, seconds(0, 100), 2.0);
  EXPECT_EQ(m.produced, 0U);
  EXPECT_FALSE(m.quality);
  EXPECT_NEAR(*m.performance, 0.0, kEps);
  EXPECT_EQ(m.oee, 0.0);  // executing and making nothing is an OEE of 0 whatever the quality
  // Planned busy but never executing: availability 0, performance undefined, OEE 0.
  MachineHistory held{"m", {{at(0), PackMLState::Held}}, {}, {{at(0), 7}}, {}};
  const MachineOee h0 = machine_oee(held, seconds(0, 100), 2.0);
  EXPECT_NEAR(*h0.availability, 0.0, kEps);
  EXPECT_FALSE(h0.performance);
  EXPECT_EQ(h0.oee, 0.0);
  // Only planned downtime: nothing was planned, so nothing is defined.
  MachineHistory idle{"m", {{at(0), PackMLState::Idle}}, {}, {{at(0), 7}}, {}};
  const MachineOee i = machine_oee(idle, seconds(0, 100), 2.0);
  EXPECT_FALSE(i.no_data);
  EXPECT_FALSE(i.availability || i.oee);
}

// 55 units of an ideal 2 s in 100 s of Execute: 1.1 measured, 1 in the OEE.
TEST(Oee, PerformanceAboveOneIsClampedAndKept) {
  MachineHistory h{"m", {{at(0), PackMLState::Execute}}, {}, {{at(0), 0}, {at(99), 55}}, {}};
  const MachineOee m = machine_oee(h, seconds(0, 100), 2.0);
  EXPECT_NEAR(*m.performance_measured, 1.1, kEps);
  EXPECT_NEAR(*m.performance, 1.0, kEps);
  EXPECT_NEAR(*m.oee, 1.0, kEps);
  EXPECT_FALSE(machine_oee(h, seconds(0, 100), std::nullopt).performance);  // no ideal, no performance
}

// Execute throughout, Maintenance mode from 40 s to 70 s: 30 s of planned downtime.
TEST(Oee, MaintenanceModeIsPlannedDowntime) {
  MachineHistory h{
      "m",
      {{at(0), PackMLState::Execute}},
      {{at(0), PackMLMode::Production}, {at(40), PackMLMode::Maintenance}, {at(70), PackMLMode::Production}},
      {},
      {}};
  const MachineOee m = machine_oee(h, seconds(0, 100), std::nullopt);
  EXPECT_EQ(m.planned_downtime, secs(30));
  EXPECT_EQ(m.actual_production_time, secs(70));
  EXPECT_EQ(m.time_in_state[static_cast<std::size_t>(PackMLState::Execute)], secs(100));
  EXPECT_NEAR(*m.availability, 1.0, kEps);
}

// Three machines: the slowest ideal cycle (5 s) is the constraint and its OEE the line's.
TEST(Oee, LineOeeIsTheConstraints) {
  auto machine = [](std::string name, std::uint64_t made, double ideal) {
    MachineHistory h{std::move(name), {{at(0), PackMLState::Execute}}, {}, {{at(0), 0}, {at(10), made}}, {}};
    return machine_oee(h, seconds(0, 100), ideal > 0 ? std::optional(ideal) : std::nullopt);
  };
  std::vector<MachineOee> all{machine("uploader", 40, 2.0), machine("scara-robot-1", 10, 5.0),
                              machine("conveyor1", 90, 0.0)};
  auto line = line_oee(all);
  ASSERT_TRUE(line) << line.error().describe();
  EXPECT_EQ(line->constraint, "scara-robot-1");
  EXPECT_NEAR(*line->oee, 0.5, kEps);  // 5 s × 10 / 100 s
  EXPECT_NEAR(*line->performance, 0.5, kEps);
  EXPECT_EQ(line->machines.size(), 3U);
  auto chosen = line_oee(all, "Uploader");
  ASSERT_TRUE(chosen);
  EXPECT_EQ(chosen->constraint, "uploader");
  EXPECT_NEAR(*chosen->oee, 0.8, kEps);
  EXPECT_EQ(line_oee(all, "palletiser").error().code, Errc::not_found);
  auto none = line_oee({machine("conveyor1", 90, 0.0)});
  ASSERT_TRUE(none);
  EXPECT_FALSE(none->constraint || none->oee);
}

// The scripted run in 250 s buckets. Second bucket [250, 500) by hand: Execute throughout
// (availability 1); processed 60 at 200 s → 120 at 400 s = 60; defective 2 → 5 = 3;
// performance 2 × 60 / 250 = 0.48; quality 57 / 60 = 0.95; OEE 0.456.
TEST(Oee, TrendBuckets) {
  auto trend = machine_oee_trend(test::scripted_run(), seconds(0, 1000), secs(250), 2.0);
  ASSERT_TRUE(trend) << trend.error().describe();
  ASSERT_EQ(trend->size(), 4U);
  const MachineOee& b = (*trend)[1];
  EXPECT_EQ(b.range, seconds(250, 500));
  EXPECT_NEAR(*b.availability, 1.0, kEps);
  EXPECT_EQ(b.produced, 60U);
  EXPECT_NEAR(*b.performance, 0.48, kEps);
  EXPECT_NEAR(*b.quality, 0.95, kEps);
  EXPECT_NEAR(*b.oee, 0.456, kEps);
  // The buckets share the run out: times and counts add up to the whole range's.
  Micros apt{0};
  std::uint64_t made = 0;
  for (const MachineOee& m : *trend) {
    apt += m.actual_production_time;
    made += m.produced.value_or(0);
  }
  EXPECT_EQ(apt, secs(600));
  EXPECT_EQ(made, 210U);
  // The last bucket ends at the range's end.
  auto ragged = buckets(seconds(0, kRunEnd - 100), secs(250));
  ASSERT_TRUE(ragged);
  ASSERT_EQ(ragged->size(), 4U);
  EXPECT_EQ(ragged->back(), seconds(750, 900));

  auto line = line_oee_trend({test::scripted_run()}, seconds(0, 1000), secs(500), {{"Uploader", 2.0}});
  ASSERT_TRUE(line) << line.error().describe();
  ASSERT_EQ(line->size(), 2U);
  EXPECT_EQ((*line)[0].constraint, "Uploader");
  EXPECT_EQ((*line)[1].range, seconds(500, 1000));
}

TEST(Oee, BadBucketsAreRefused) {
  EXPECT_EQ(buckets(seconds(10, 10), secs(1)).error().code, Errc::invalid_argument);
  EXPECT_EQ(buckets(seconds(10, 0), secs(1)).error().code, Errc::invalid_argument);
  EXPECT_EQ(buckets(seconds(0, 10), secs(0)).error().code, Errc::invalid_argument);
  EXPECT_EQ(buckets(seconds(0, 100'000), Micros{1}).error().code, Errc::limit_exceeded);
  EXPECT_EQ(buckets(seconds(0, 10'000), secs(1))->size(), kMaxBuckets);
}

TEST(Oee, IdealCycleTimesFromTheLayout) {
  auto layout = line::default_layout();
  ASSERT_TRUE(layout) << layout.error().describe();
  const IdealCycleTimes ideal = ideal_cycle_times(*layout);
  EXPECT_EQ(ideal_cycle_of(ideal, layout->uploader.name), layout->uploader.cycle_s);
  EXPECT_EQ(ideal_cycle_of(ideal, "Downloader"), layout->downloader.cycle_s);
  EXPECT_EQ(ideal_cycle_of(ideal, "scara-robot-1"), std::nullopt);
}

}  // namespace
}  // namespace sf::dashboard
