// The smart robot's controller against the plant: our EtherCAT master on the
// robot's in-memory segment, the plant on a ManualClock, one millisecond per
// step (the controller's cycle, then the plant's physics). Boxes are put at
// the robot's station by the plant's hand; conveying is the gateways' work.
#include "smart_robot_rig.hpp"

namespace sf::factory {
namespace {

using namespace std::chrono_literals;
using testing::kRobot;

class SmartRobotTest : public ::testing::Test {
 protected:
  SmartRobotTest() {
    robot_.on_job_end([this](const JobOutcome& o) { outcomes_.push_back(o); });
  }
  void SetUp() override { rig.start(); }

  // Reset (homing) and Start.
  void to_execute() {
    ASSERT_TRUE(robot_.command(PackMLCommand::Reset));
    ASSERT_TRUE(until(PackMLState::Idle, 5s)) << to_string(state());
    ASSERT_TRUE(robot_.command(PackMLCommand::Start));
    ASSERT_TRUE(until(PackMLState::Execute, 100ms)) << to_string(state());
  }

  PackMLState state() const { return robot_.status().packml.state; }
  bool until(PackMLState s, std::chrono::milliseconds limit) {
    return rig_.run_until([&] { return state() == s; }, limit);
  }
  bool until_outcomes(std::size_t n, std::chrono::milliseconds limit = 30s) {
    return rig_.run_until([&] { return outcomes_.size() >= n; }, limit);
  }

  Operation load(std::string_view candy_name, int count, int slot, plant::BoxId box = 1) const {
    return Operation{std::string(kLoad),
                     {{"candy", static_cast<double>(candy(candy_name))},
                      {"count", count},
                      {"slot", slot},
                      {"box", static_cast<double>(box)},
                      {"box_type", static_cast<double>(rig.box_type("small-box"))}}};
  }

  const Tag* tag(const ControllerStatus& s, std::string_view name) const {
    for (const auto& t : s.tags) {
      if (t.name == name) {
        return &t;
      }
    }
    return nullptr;
  }

  int candy(std::string_view name) const { return rig.candy(name); }
  plant::BoxId place_box() { return rig.place_box(); }
  // An empty small box at the uploader's station, on its way to the robot.
  plant::BoxId upload_box() {
    auto id = rig_.world().place_box(rig.box_type("small-box"),
                                     *line::find_station(rig_.layout(), "conveyor1/upload"), "test");
    EXPECT_TRUE(id) << id.error().describe();
    return id ? *id : 0;
  }
  void inject(std::string_view fault) { rig.inject(fault); }
  void clear(std::string_view fault) { rig.clear(fault); }

  testing::SmartRobotRig rig;
  plant::testing::Rig& rig_ = rig.rig;
  SmartRobot& robot_ = rig.robot;
  std::vector<JobOutcome> outcomes_;
};

TEST_F(SmartRobotTest, ResetEnablesTheDrivesAndHomes) {
  EXPECT_EQ(state(), PackMLState::Stopped);
  to_execute();
  EXPECT_TRUE(robot_.arm().enabled());
  const auto index = static_cast<std::size_t>(rig_.layout().robot(kRobot) - rig_.layout().robots.data());
  const auto tool = rig_.world().tool(index);
  const auto home = *rig_.layout().robot(kRobot)->home;
  EXPECT_NEAR(tool.pose.position.x, home.x, 1e-3);
  EXPECT_NEAR(tool.pose.position.y, home.y, 1e-3);
  EXPECT_NEAR(tool.pose.position.z, home.z, 1e-3);
  EXPECT_EQ(robot_.identification().manufacturer, rig_.layout().robot(kRobot)->vendor);
  EXPECT_NE(robot_.identification().serial_number, "0");
}

TEST_F(SmartRobotTest, ALoadPutsTheCandiesIntoTheirSlotsAndReportsDone) {
  to_execute();
  const plant::BoxId box = place_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 3, 4, box)));
  // Along the way the status shows the job and the axes moving.
  ASSERT_TRUE(rig_.run_until([&] { return robot_.arm().moving(); }, 1s));
  const ControllerStatus during = robot_.status();
  EXPECT_EQ(during.job, "j1");
  ASSERT_NE(tag(during, "axis1.position"), nullptr);
  EXPECT_EQ(tag(during, "axis1.position")->quality, Tag::Quality::good);
  // SI with their units (UNECE codes): radians for θ1, metres for z.
  EXPECT_EQ(tag(during, "axis1.position")->unit, "C81");
  ASSERT_NE(tag(during, "axis3.position"), nullptr);
  EXPECT_EQ(tag(during, "axis3.position")->unit, "MTR");
  EXPECT_EQ(tag(during, "axis1.state")->unit, "");
  EXPECT_EQ(std::get<std::string>(tag(during, "axis1.state")->value), "operation enabled");

  ASSERT_TRUE(until_outcomes(1));
  EXPECT_TRUE(outcomes_[0].ok) << outcomes_[0].detail;
  EXPECT_EQ(outcomes_[0].job, "j1");
  EXPECT_NE(outcomes_[0].detail.find("3 gummy in slots 4-6"), std::string::npos) << outcomes_[0].detail;
  const plant::Box* b = rig_.world().box(box);
  ASSERT_NE(b, nullptr);
  for (int slot = 0; slot < static_cast<int>(b->slots.size()); ++slot) {
    const int expected = slot >= 4 && slot <= 6 ? candy("gummy") : -1;
    EXPECT_EQ(b->slots[static_cast<std::size_t>(slot)], expected) << "slot " << slot;
  }
  EXPECT_EQ(rig_.world().counters().dropped, 0U);
  const auto status = robot_.status();
  EXPECT_EQ(status.packml.produced, 1U);
  EXPECT_EQ(status.packml.defective, 0U);
  EXPECT_FALSE(status.job);
}

TEST_F(SmartRobotTest, AJobWaitsForItsBox) {
  to_execute();
  ASSERT_TRUE(robot_.submit("j1", load("chocolate", 1, 0, 1)));
  rig_.run_for(500ms);
  EXPECT_FALSE(robot_.arm().moving());
  EXPECT_TRUE(outcomes_.empty());
  const plant::BoxId box = place_box();
  ASSERT_TRUE(until_outcomes(1));
  EXPECT_TRUE(outcomes_[0].ok) << outcomes_[0].detail;
  EXPECT_EQ(rig_.world().box(box)->slots[0], candy("chocolate"));
}

TEST_F(SmartRobotTest, EstimatesComeFromThePlannedPathsAndTheQueue) {
  std::string why;
  EXPECT_FALSE(robot_.estimate(load("gummy", 1, 0), &why));
  EXPECT_NE(why.find("is in Stopped"), std::string::npos) << why;
  to_execute();
  auto one = robot_.estimate(load("gummy", 1, 0), &why);
  auto three = robot_.estimate(load("gummy", 3, 0), &why);
  ASSERT_TRUE(one && three) << why;
  EXPECT_GT(one->duration, 200ms);
  EXPECT_GT(three->duration, 2 * one->duration);
  EXPECT_EQ(one->start_in, 0ns);
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 3, 0)));
  auto behind = robot_.estimate(load("gummy", 1, 3), &why);
  ASSERT_TRUE(behind);
  EXPECT_EQ(behind->start_in, three->duration);
  EXPECT_EQ(behind->queue_length, 1U);
}

TEST_F(SmartRobotTest, OperationsItCannotDoAreRefusedWithTheReason) {
  to_execute();
  std::string why;
  Operation liquorice = load("gummy", 1, 0);
  liquorice.params["candy"] = static_cast<double>(candy("toffee"));
  EXPECT_FALSE(robot_.estimate(liquorice, &why));
  EXPECT_NE(why.find("has no dispenser of toffee"), std::string::npos) << why;
  EXPECT_FALSE(robot_.estimate(load("gummy", 3, 10), &why));
  EXPECT_NE(why.find("do not fit"), std::string::npos) << why;
  Operation no_box = load("gummy", 1, 0);
  no_box.params.erase("box_type");
  EXPECT_FALSE(robot_.estimate(no_box, &why));
  EXPECT_NE(why.find("needs the parameter 'box_type'"), std::string::npos) << why;
  EXPECT_FALSE(robot_.estimate(Operation{"download", {}}, &why));
  EXPECT_NE(why.find("does not do 'download'"), std::string::npos) << why;
  auto refused = robot_.submit("j1", liquorice);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().code, Errc::state);
  ASSERT_TRUE(robot_.submit("j2", load("gummy", 1, 0)));
  EXPECT_EQ(robot_.submit("j2", load("gummy", 1, 1)).error().code, Errc::invalid_argument);
}

TEST_F(SmartRobotTest, AnEmptyDispenserFailsTheJobAndStopsBidsForThatCandyUntilReset) {
  to_execute();
  inject("dispenser-empty:scara1-gummy");
  place_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 2, 0)));
  ASSERT_TRUE(until_outcomes(1));
  EXPECT_FALSE(outcomes_[0].ok);
  EXPECT_NE(outcomes_[0].detail.find("the dispenser is empty"), std::string::npos) << outcomes_[0].detail;
  EXPECT_EQ(state(), PackMLState::Execute);  // one job failed, not the machine
  std::string why;
  EXPECT_FALSE(robot_.estimate(load("gummy", 1, 0), &why));
  EXPECT_NE(why.find("gummy dispenser ran empty"), std::string::npos) << why;
  EXPECT_TRUE(robot_.estimate(load("chocolate", 1, 0), &why)) << why;
  EXPECT_EQ(robot_.status().packml.defective, 1U);

  clear("dispenser-empty:scara1-gummy");
  ASSERT_TRUE(robot_.command(PackMLCommand::Stop));
  ASSERT_TRUE(until(PackMLState::Stopped, 5s));
  to_execute();
  EXPECT_TRUE(robot_.estimate(load("gummy", 1, 0), &why)) << why;
}

TEST_F(SmartRobotTest, AnAxisFaultMidMoveAbortsWithTheErrorCodeAndClearResetRecovers) {
  to_execute();
  place_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 2, 0)));
  ASSERT_TRUE(robot_.submit("j2", load("gummy", 1, 2)));
  ASSERT_TRUE(rig_.run_until([&] { return robot_.arm().moving(); }, 1s));
  rig_.run_for(50ms);
  inject("axis-fault:scara-robot-1:1:0x7500");
  ASSERT_TRUE(until(PackMLState::Aborted, 1s)) << to_string(state());
  ASSERT_EQ(outcomes_.size(), 2U);
  EXPECT_FALSE(outcomes_[0].ok);
  EXPECT_NE(outcomes_[0].detail.find("axis 2 (θ2)"), std::string::npos) << outcomes_[0].detail;
  EXPECT_NE(outcomes_[1].detail.find("before it started"), std::string::npos) << outcomes_[1].detail;
  const auto reason = robot_.status().packml.stop_reason;
  ASSERT_TRUE(reason);
  EXPECT_EQ(reason->id, kStopAxisFault);
  EXPECT_NE(reason->message.find("axis 2 (θ2) fault, error code 0x7500"), std::string::npos)
      << reason->message;

  clear("axis-fault:scara-robot-1:1:0x7500");
  ASSERT_TRUE(robot_.command(PackMLCommand::Clear));
  ASSERT_TRUE(until(PackMLState::Stopped, 1s)) << to_string(state());
  to_execute();
  ASSERT_TRUE(robot_.submit("j3", load("gummy", 1, 5)));
  ASSERT_TRUE(until_outcomes(3));
  EXPECT_TRUE(outcomes_[2].ok) << outcomes_[2].detail;
}

TEST_F(SmartRobotTest, ADriveFaultWhileStoppedIsAcknowledgedByTheReset) {
  inject("axis-fault:scara-robot-1:3:0x2310");
  rig_.run_for(20ms);
  EXPECT_EQ(state(), PackMLState::Stopped);  // drives off: not a reason to abort
  ASSERT_TRUE(robot_.command(PackMLCommand::Reset));
  ASSERT_TRUE(until(PackMLState::Idle, 5s)) << to_string(state());
}

TEST_F(SmartRobotTest, ACutCableStopsTheRobotAndTheReturnResetsItToIdle) {
  to_execute();
  place_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 2, 0)));
  ASSERT_TRUE(rig_.run_until([&] { return robot_.arm().moving(); }, 1s));
  inject("cable-cut:scara-robot-1");
  ASSERT_TRUE(until(PackMLState::Stopped, 1s)) << to_string(state());
  ASSERT_EQ(outcomes_.size(), 1U);
  EXPECT_FALSE(outcomes_[0].ok);
  const ControllerStatus down = robot_.status();
  ASSERT_TRUE(down.packml.stop_reason);
  EXPECT_EQ(down.packml.stop_reason->id, kStopEtherCatLost);
  EXPECT_FALSE(down.fault.empty());
  ASSERT_NE(tag(down, "axis1.position"), nullptr);
  EXPECT_EQ(tag(down, "axis1.position")->quality, Tag::Quality::bad);
  std::string why;
  EXPECT_FALSE(robot_.estimate(load("gummy", 1, 2), &why));
  EXPECT_NE(why.find("EtherCAT segment is down"), std::string::npos) << why;

  clear("cable-cut:scara-robot-1");
  ASSERT_TRUE(until(PackMLState::Idle, 20s)) << to_string(state());
  EXPECT_TRUE(robot_.arm().enabled());
  EXPECT_EQ(tag(robot_.status(), "axis1.position")->quality, Tag::Quality::good);
}

TEST_F(SmartRobotTest, HoldFinishesTheMoveAndUnholdGoesOn) {
  to_execute();
  const plant::BoxId box = place_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 2, 0, box)));
  ASSERT_TRUE(rig_.run_until([&] { return robot_.arm().moving(); }, 1s));
  ASSERT_TRUE(robot_.command(PackMLCommand::Hold));
  ASSERT_TRUE(until(PackMLState::Held, 5s)) << to_string(state());
  EXPECT_FALSE(robot_.arm().moving());
  rig_.run_for(300ms);
  EXPECT_FALSE(robot_.arm().moving());
  EXPECT_TRUE(outcomes_.empty());
  auto wrong = robot_.command(PackMLCommand::Start);
  ASSERT_FALSE(wrong);
  EXPECT_EQ(wrong.error().code, Errc::state);
  ASSERT_TRUE(robot_.command(PackMLCommand::Unhold));
  ASSERT_TRUE(until_outcomes(1));
  EXPECT_TRUE(outcomes_[0].ok) << outcomes_[0].detail;
  EXPECT_EQ(rig_.world().box(box)->slots[1], candy("gummy"));
}

TEST_F(SmartRobotTest, ACancelledJobEndsAndTheNextRuns) {
  to_execute();
  place_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 3, 0)));
  ASSERT_TRUE(robot_.submit("j2", load("chocolate", 1, 3)));
  ASSERT_TRUE(robot_.submit("j3", load("chocolate", 1, 4)));
  ASSERT_TRUE(robot_.cancel("j2"));
  ASSERT_TRUE(rig_.run_until([&] { return robot_.arm().moving(); }, 1s));
  ASSERT_TRUE(robot_.cancel("j1"));
  ASSERT_TRUE(until_outcomes(3));
  EXPECT_EQ(outcomes_[0].job, "j2");
  EXPECT_NE(outcomes_[0].detail.find("cancelled before it started"), std::string::npos);
  EXPECT_EQ(outcomes_[1].job, "j1");
  EXPECT_FALSE(outcomes_[1].ok);
  EXPECT_EQ(outcomes_[2].job, "j3");
  EXPECT_TRUE(outcomes_[2].ok) << outcomes_[2].detail;
  EXPECT_EQ(robot_.cancel("nope").error().code, Errc::not_found);
}

// Many boxes on the line: the job whose box stands at the station begins,
// the earlier one keeps waiting for its own box (no deadlock behind it).
TEST_F(SmartRobotTest, TheJobWhoseBoxArrivesFirstRunsFirstAndTheOtherWaitsForItsBox) {
  to_execute();
  const plant::BoxId b1 = upload_box();
  const plant::BoxId b2 = place_box();
  ASSERT_TRUE(robot_.submit("for-b1", load("gummy", 1, 0, b1)));
  ASSERT_TRUE(robot_.submit("for-b2", load("chocolate", 2, 5, b2)));
  ASSERT_TRUE(until_outcomes(1));
  EXPECT_EQ(outcomes_[0].job, "for-b2");
  EXPECT_TRUE(outcomes_[0].ok) << outcomes_[0].detail;
  EXPECT_EQ(rig_.world().box(b2)->slots[5], candy("chocolate"));
  EXPECT_EQ(rig_.world().box(b2)->slots[6], candy("chocolate"));
  EXPECT_EQ(rig_.world().box(b2)->slots[0], -1);  // b1's candy did not go into b2
  // b1's job waits while b1 is elsewhere.
  rig_.run_for(500ms);
  EXPECT_EQ(outcomes_.size(), 1U);
  EXPECT_EQ(robot_.status().queued, 1U);
  EXPECT_FALSE(robot_.arm().moving());
  // b2 leaves (the downloader's hand), b1 is carried to the station and gets its candy.
  ASSERT_TRUE(rig_.world().take_box(*line::find_station(rig_.layout(), "conveyor2/scara1"), "test"));
  rig_.step();  // the PLCs' next scan sees the station empty
  rig_.convey({"conveyor1", "conveyor2"}, 0);
  ASSERT_TRUE(until_outcomes(2));
  EXPECT_EQ(outcomes_[1].job, "for-b1");
  EXPECT_TRUE(outcomes_[1].ok) << outcomes_[1].detail;
  EXPECT_EQ(rig_.world().box(b1)->slots[0], candy("gummy"));
  const ControllerStatus status = robot_.status();
  const Tag* reader = tag(status, "io.station_box");
  ASSERT_NE(reader, nullptr);
  EXPECT_EQ(std::get<std::int64_t>(reader->value), b1);
}

TEST_F(SmartRobotTest, ABoxPassingThroughTheStationDoesNotStartItsJob) {
  to_execute();
  const plant::BoxId box = upload_box();
  ASSERT_TRUE(robot_.submit("j1", load("gummy", 1, 0, box)));
  // Every stopper down, conveyor1 and conveyor2 running: the box rides through the
  // robot's station and waits at the end of conveyor2 (conveyor4 stands still).
  for (const char* belt : {"conveyor1", "conveyor2"}) {
    rig_.coil(belt, line::conveyor_plc::kStopper, false);
    rig_.coil(belt, line::conveyor_plc::kMotorRun, true);
  }
  const std::size_t conveyor2 = *rig_.layout().belt_index("conveyor2");
  bool passed = false;
  ASSERT_TRUE(rig_.run_until(
      [&] {
        passed = passed || rig_.world().box_in_place(conveyor2, 0) != nullptr;
        return rig_.world().box(box)->belt == conveyor2 && rig_.world().box(box)->s > 2.5;
      },
      20s));
  EXPECT_TRUE(passed);
  rig_.run_for(200ms);
  EXPECT_TRUE(outcomes_.empty());
  EXPECT_FALSE(robot_.status().job) << "the job began for a box that only passed by";
  EXPECT_EQ(robot_.status().queued, 1U);
  EXPECT_FALSE(robot_.arm().moving());
}

TEST(SmartRobotRestart, ARestartedIpcResetsTheDrivesItsPredecessorLeftFaultedAndStarts) {
  // The IPC's process killed: the drives' process-data watchdog expires and they fault
  // (communication, 0x8100). The IPC the supervisor starts again finds them so; its auto start
  // (Reset acknowledges drive faults, OPC 30050 §6.7) brings the robot to Execute rather than
  // aborting on a fault that came before it.
  testing::SmartRobotRig first(true);
  first.start();
  auto& rig = first.rig;
  ASSERT_TRUE(rig.run_until([&] { return first.robot.status().packml.state == PackMLState::Execute; }, 10s));
  rig.on_cycle(nullptr);  // killed: nobody exchanges process data any more
  rig.run_for(500ms);

  ethercat::slave::SegmentLink link(rig.plant().smart_robot(testing::kRobot)->segment());
  ethercat::master::MasterOptions options;
  options.dc_static_drift_frames = 200;
  ethercat::master::Master master(link, rig.clock(), options);
  SmartRobotConfig config;
  config.robot = testing::kRobot;
  config.auto_start = true;
  SmartRobot again(config, rig.layout(), master, rig.clock());
  auto started = again.start();
  ASSERT_TRUE(started) << started.error().describe();
  rig.on_cycle([&] { again.poll(rig.clock().now()); });
  EXPECT_TRUE(rig.run_until([&] { return again.status().packml.state == PackMLState::Execute; }, 10s))
      << to_string(again.status().packml.state) << ": "
      << (again.status().packml.stop_reason ? again.status().packml.stop_reason->message : "");
  rig.on_cycle(nullptr);
}

}  // namespace
}  // namespace sf::factory
