// A gateway's PackML unit and job queue: operators' commands, jobs only in
// Execute, a hold in the middle of a robot's job, cancels, queued estimates.
#include "gateway_rig.hpp"

namespace sf::factory::testing {
namespace {

using S = PackMLState;
using C = PackMLCommand;

TEST(GatewayPackML, StartsStoppedAndRunsJobsOnlyInExecute) {
  GatewayRig rig;
  Gateway& up = rig.add("uploader", "uploader", "");
  rig.run_for(100ms);
  EXPECT_EQ(up.status().packml.state, S::Stopped);
  const Operation op{"upload", {{"box_type", 0}}};
  std::string why;
  EXPECT_FALSE(up.estimate(op, &why));
  EXPECT_EQ(why, "uploader is in Stopped");
  auto refused = up.submit("u1", op);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().message, "uploader declines upload: uploader is in Stopped");

  auto wrong = up.command(C::Start);
  ASSERT_FALSE(wrong);
  EXPECT_EQ(wrong.error().code, Errc::state);
  ASSERT_TRUE(up.command(C::Reset));
  EXPECT_EQ(up.status().packml.state, S::Resetting);
  rig.run_for(100ms);
  EXPECT_EQ(up.status().packml.state, S::Idle);
  EXPECT_FALSE(up.estimate(op));
  ASSERT_TRUE(up.command(C::Start));
  rig.run_for(100ms);
  EXPECT_EQ(up.status().packml.state, S::Execute);
  ASSERT_TRUE(up.estimate(op, &why)) << why;

  // Held: no bids, nothing starts; unheld, the queued job runs.
  ASSERT_TRUE(up.command(C::Hold));
  rig.run_for(100ms);
  EXPECT_EQ(up.status().packml.state, S::Held);
  EXPECT_EQ(up.status().packml.stop_reason->message, "operator: Hold");
  EXPECT_FALSE(up.estimate(op));
  ASSERT_TRUE(up.command(C::Unhold));
  rig.run_for(100ms);
  const JobOutcome o = rig.run_job(up, "u1", op);
  EXPECT_TRUE(o.ok) << o.detail;
  EXPECT_GT(up.status().packml.time_in_state[static_cast<std::size_t>(S::Held)].count(), 0);
}

TEST(GatewayPackML, AHoldLetsTheCandyInHandLandAndTheRestFollowsOnUnhold) {
  GatewayRig rig;
  auto [toshiba, id] = rig.add_with_box("toshiba", "legacy-robot", "conveyor3/toshiba");
  ASSERT_TRUE(toshiba.submit(
      "l1", {"load", {{"candy", rig.candy("gummy")}, {"count", 3}, {"box", id}, {"slot", 0}}}));
  rig.run_for(1s);  // the first candy is on its way
  ASSERT_TRUE(toshiba.command(C::Hold));
  rig.step();
  EXPECT_EQ(toshiba.status().packml.state, S::Holding);  // waits for the controller's job
  ASSERT_TRUE(rig.run_until([&] { return toshiba.status().packml.state == S::Held; }, 5s));
  const auto& slots = rig.world().box(id)->slots;
  EXPECT_EQ(std::count(slots.begin(), slots.end(), static_cast<int>(rig.candy("gummy"))), 1);
  rig.run_for(5s);
  EXPECT_EQ(std::count(slots.begin(), slots.end(), static_cast<int>(rig.candy("gummy"))), 1);
  EXPECT_FALSE(rig.ended("l1"));
  EXPECT_EQ(toshiba.status().job, "l1");

  ASSERT_TRUE(toshiba.command(C::Unhold));
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("l1"); }, 20s));
  EXPECT_TRUE(rig.outcome("l1").ok) << rig.outcome("l1").detail;
  EXPECT_EQ(std::count(slots.begin(), slots.end(), static_cast<int>(rig.candy("gummy"))), 3);
}

TEST(GatewayPackML, CancelDropsQueuedJobsAndStopsTheOneInWork) {
  GatewayRig rig;
  auto [c4, id] = rig.add_with_box("conveyor4", "conveyor", "conveyor4/denso");
  const Operation op = rig.transport(id, "conveyor4/denso", "conveyor4/download");
  ASSERT_TRUE(c4.submit("t1", op));
  ASSERT_TRUE(c4.submit("t2", op));
  // Queued behind t1: its start is t1's duration away, and the queue says two.
  auto e = c4.estimate(op);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->start_in, 2 * e->duration);
  EXPECT_EQ(e->queue_length, 2U);
  auto twice = c4.submit("t1", op);
  ASSERT_FALSE(twice);
  EXPECT_EQ(twice.error().code, Errc::invalid_argument);

  ASSERT_TRUE(c4.cancel("t2"));
  EXPECT_FALSE(rig.ended("t2"));  // outcomes are delivered from poll()
  rig.run_for(1s);
  ASSERT_TRUE(rig.ended("t2"));
  EXPECT_EQ(rig.outcome("t2").detail, "cancelled before it started");
  EXPECT_TRUE(std::get<bool>(tag(c4.status(), "plc.running").value));

  ASSERT_TRUE(c4.cancel("t1"));
  rig.run_for(100ms);
  ASSERT_TRUE(rig.ended("t1"));
  EXPECT_FALSE(rig.outcome("t1").ok);
  EXPECT_EQ(rig.outcome("t1").detail,
            fmt::format("conveyor4: box {} from conveyor4/denso to conveyor4/download cancelled", id));
  EXPECT_FALSE(std::get<bool>(tag(c4.status(), "plc.running").value));
  EXPECT_EQ(c4.cancel("t1").error().code, Errc::not_found);
  EXPECT_EQ(c4.status().packml.produced, 1U);  // t1 came into work, t2 did not
  EXPECT_EQ(c4.status().packml.defective, 1U);
}

TEST(GatewayPackML, IdentifiesItsMachineFromTheLayout) {
  GatewayRig rig;
  const Identification& conveyor =
      rig.add("conveyor2", "conveyor", "serial_number: S7-0002\n").identification();
  EXPECT_EQ(conveyor.name, "conveyor2");
  EXPECT_EQ(conveyor.kind, "conveyor");
  EXPECT_EQ(conveyor.manufacturer, "Siemens");
  EXPECT_EQ(conveyor.model, "S7-1200");
  EXPECT_EQ(conveyor.serial_number, "S7-0002");
  const Identification& denso = rig.add("denso", "legacy-robot").identification();
  EXPECT_EQ(denso.manufacturer, "DENSO");
  EXPECT_EQ(denso.model, "VS-6577G");
  EXPECT_EQ(rig.add("downloader", "downloader").identification().manufacturer, "Mitsubishi");
}

}  // namespace
}  // namespace sf::factory::testing
