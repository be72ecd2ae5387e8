// OEE through a real historian (SQLite in memory): the scripted run stored as the cloud gateway
// stores a machine's variables (server_link.cpp: one series per variable, keyed by the server's
// name and the node's stable id, found by its browse path), read back and computed.
#include "sf/dashboard/oee_history.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include "scripted_run.hpp"

namespace sf::dashboard {
namespace {

using historian::DataType;
using historian::Sample;
using historian::SeriesInfo;
using test::at;

constexpr double kHistoryEps = 1e-12;

class OeeHistoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = historian::open_store("sqlite::memory:");
    ASSERT_TRUE(store) << store.error().describe();
    store_ = std::move(*store);
  }

  // The series of `variable` ("PackML/Status/StateCurrent") of a machine's server, registered as
  // the gateway registers it: server = the process name, node id "nsu=<machine namespace>;s=
  // <Machine>.<dotted path>", browse path below /Objects/Machines/<Machine>.
  historian::SeriesId series(const std::string& server, const std::string& machine,
                             std::string_view variable) {
    std::string dotted(variable);
    std::replace(dotted.begin(), dotted.end(), '/', '.');
    SeriesInfo info{server, "nsu=urn:smartfactory:machines;s=" + machine + "." + dotted,
                    "/Objects/Machines/" + machine + "/" + std::string(variable), DataType::int64, ""};
    auto id = store_->register_series(info);
    EXPECT_TRUE(id) << id.error().describe();
    return id.value_or(0);
  }

  void store(historian::SeriesId id, Timestamp t, std::int64_t v,
             historian::StatusCode status = historian::kGood) {
    const Sample s{id, t, t, 0, status, v};
    ASSERT_TRUE(store_->append(std::span(&s, 1)));
  }

  // The scripted run of scripted_run.hpp as the server "uploader" delivered it.
  void store_scripted_run() {
    const MachineHistory run = test::scripted_run();
    const auto state = series("uploader", "Uploader", kStateCurrent);
    for (const StateChange& c : run.states) {
      store(state, c.time, static_cast<std::int64_t>(*c.state));
    }
    const auto mode = series("uploader", "Uploader", kUnitModeCurrent);
    store(mode, at(-50), 1);
    const auto processed = series("uploader", "Uploader", kProdProcessedCount);
    for (const CounterSample& c : run.processed) {
      store(processed, c.time, static_cast<std::int64_t>(c.value));
    }
    const auto defective = series("uploader", "Uploader", kProdDefectiveCount);
    for (const CounterSample& c : run.defective) {
      store(defective, c.time, static_cast<std::int64_t>(c.value));
    }
  }

  std::unique_ptr<historian::Store> store_;
};

// The hand computation of oee_test.cpp (ScriptedRunEqualsTheHandComputation) with the
// default layout's uploader cycle_s of 1.5 s as PRI: availability 600 / 860; performance
// 1.5 × 210 / 600 = 0.525; quality 200 / 210; OEE = 1.5 × 200 / 860 = 0.3488372….
TEST_F(OeeHistoryTest, ScriptedRunFromTheHistorian) {
  store_scripted_run();
  auto layout = line::default_layout();
  ASSERT_TRUE(layout) << layout.error().describe();
  ASSERT_EQ(layout->uploader.cycle_s, 1.5);
  auto m = machine_oee(*store_, "uploader", {at(0), at(1000)}, ideal_cycle_times(*layout));
  ASSERT_TRUE(m) << m.error().describe();
  EXPECT_EQ(m->machine, "Uploader");
  EXPECT_EQ(m->planned_busy_time, std::chrono::seconds{860});
  EXPECT_EQ(m->actual_production_time, std::chrono::seconds{600});
  EXPECT_EQ(m->produced, 210U);
  EXPECT_EQ(m->good, 200U);
  EXPECT_NEAR(*m->availability, 600.0 / 860.0, kHistoryEps);
  EXPECT_NEAR(*m->performance, 0.525, kHistoryEps);
  EXPECT_NEAR(*m->quality, 200.0 / 210.0, kHistoryEps);
  EXPECT_NEAR(*m->oee, 300.0 / 860.0, kHistoryEps);

  auto trend = machine_oee_trend(*store_, "Uploader", {at(0), at(1000)}, std::chrono::seconds{250},
                                 {{"Uploader", 2.0}});
  ASSERT_TRUE(trend) << trend.error().describe();
  ASSERT_EQ(trend->size(), 4U);
  EXPECT_NEAR(*(*trend)[1].oee, 0.456, kHistoryEps);  // oee_test.cpp TrendBuckets

  auto line = line_oee(*store_, {}, {at(0), at(1000)}, {{"Uploader", 1.5}});
  ASSERT_TRUE(line) << line.error().describe();
  EXPECT_EQ(line->constraint, "Uploader");
  EXPECT_NEAR(*line->oee, 300.0 / 860.0, kHistoryEps);
}

// A range that starts long after the last state sample before it (the look back over growing
// windows finds it) and ends before the newest one.
TEST_F(OeeHistoryTest, StateLongBeforeTheRangeHoldsAtItsStart) {
  const auto state = series("scara-robot-1", "ScaraRobot1", kStateCurrent);
  store(state, at(-3 * 86'400), static_cast<std::int64_t>(test::S::Execute));
  store(state, at(3'600), static_cast<std::int64_t>(test::S::Held));
  auto h = read_machine_history(*store_, "scara-robot-1", {at(0), at(100)});
  ASSERT_TRUE(h) << h.error().describe();
  ASSERT_EQ(h->states.size(), 1U);
  EXPECT_EQ(h->states.front().time, at(-3 * 86'400));
  EXPECT_TRUE(h->modes.empty() && h->processed.empty());
  const MachineOee m = machine_oee(*h, {at(0), at(100)}, std::nullopt);
  EXPECT_EQ(m.actual_production_time, std::chrono::seconds{100});
}

// A Bad sample (the server lost its controller) makes the state unknown until the next good one;
// a value that is no PackML state too.
TEST_F(OeeHistoryTest, BadSamplesAreUnknownTime) {
  const auto state = series("conveyor1", "Conveyor1", kStateCurrent);
  store(state, at(0), static_cast<std::int64_t>(test::S::Execute));
  store(state, at(40), 0, 0x80310000U);  // BadNoCommunication
  store(state, at(60), static_cast<std::int64_t>(test::S::Execute));
  store(state, at(80), 99);
  auto m = machine_oee(*store_, "conveyor1", {at(0), at(100)}, {});
  ASSERT_TRUE(m) << m.error().describe();
  EXPECT_EQ(m->unknown_time, std::chrono::seconds{40});
  EXPECT_EQ(m->actual_production_time, std::chrono::seconds{60});
  EXPECT_NEAR(*m->availability, 1.0, kHistoryEps);
}

TEST_F(OeeHistoryTest, MachinesAndMissingSeries) {
  store_scripted_run();
  series("scara-robot-1", "ScaraRobot1", kStateCurrent);
  series("scara-robot-1", "ScaraRobot1", "Fault");
  series("orders", "OrderService", "LastInspection");
  auto machines = oee_machines(*store_);
  ASSERT_TRUE(machines) << machines.error().describe();
  EXPECT_EQ(*machines, (std::vector<std::string>{"ScaraRobot1", "Uploader"}));

  // A machine without data in the store: not found, with the series named.
  auto none = machine_oee(*store_, "palletiser", {at(0), at(10)}, {});
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().code, Errc::not_found);
  EXPECT_NE(none.error().message.find("/Objects/Machines/Palletiser/PackML/Status/StateCurrent"),
            std::string::npos);
  // A machine registered but without samples: no data.
  auto empty = machine_oee(*store_, "ScaraRobot1", {at(0), at(10)}, {});
  ASSERT_TRUE(empty) << empty.error().describe();
  EXPECT_TRUE(empty->no_data);
  // The same browse path from two servers cannot be told apart.
  series("uploader-2", "Uploader", kStateCurrent);
  auto twice = machine_oee(*store_, "uploader", {at(0), at(10)}, {});
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error().code, Errc::invalid_argument);
  // A bad bucket is refused before anything is read.
  EXPECT_EQ(machine_oee_trend(*store_, "ScaraRobot1", {at(0), at(10)}, Micros{0}, {}).error().code,
            Errc::invalid_argument);
}

}  // namespace
}  // namespace sf::dashboard
