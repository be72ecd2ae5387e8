// Each kind of gateway doing its job on the plant's PLCs, through Modbus
// only: the uploader, a conveyor between stations and onto the next belt, a
// legacy robot's loads, the downloader's inspection, and the whole chain.
#include "gateway_rig.hpp"

namespace sf::factory::testing {
namespace {

using S = PackMLState;

TEST(GatewayUploader, PutsABoxOnTheLineAndReportsItsId) {
  GatewayRig rig;
  Gateway& up = rig.add("uploader", "uploader");
  rig.run_for(200ms);
  ASSERT_EQ(up.status().packml.state, S::Execute);
  EXPECT_EQ(up.operations(), std::vector<std::string>{"upload"});
  auto estimate = up.estimate({"upload", {{"box_type", 1}}});
  ASSERT_TRUE(estimate);
  EXPECT_EQ(estimate->duration, 1500ms + 20ms);  // the layout's cycle and the poll that sees its end

  const JobOutcome o = rig.run_job(up, "u1", {"upload", {{"box_type", 1}}});
  ASSERT_TRUE(o.ok) << o.detail;
  const auto id = static_cast<plant::BoxId>(o.results.at("box"));
  const plant::Box* box = rig.world().box(id);
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->type, 1U);
  EXPECT_EQ(rig.world().box_in_place(0, 0), box);  // conveyor1/upload
  EXPECT_NE(o.detail.find("large-box"), std::string::npos) << o.detail;

  const ControllerStatus s = up.status();
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "plc.box_id").value), id);
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "plc.jobs_done").value), 1);
  EXPECT_TRUE(std::get<bool>(tag(s, "plc.box_present").value));
  EXPECT_EQ(tag(s, "plc.box_present").quality, Tag::Quality::good);
  EXPECT_EQ(s.packml.produced, 1U);
  EXPECT_EQ(s.packml.defective, 0U);
  EXPECT_FALSE(has_tag(s, "plc.weight"));  // the uploader shows only its own registers
  EXPECT_TRUE(has_tag(s, "plc.box_type"));
}

TEST(GatewayConveyor, CarriesABoxBetweenStationsOfItsBelt) {
  GatewayRig rig;
  auto [c4, id] = rig.add_with_box("conveyor4", "conveyor", "conveyor4/denso");
  const Operation op = rig.transport(id, "conveyor4/denso", "conveyor4/download");
  auto estimate = c4.estimate(op);
  ASSERT_TRUE(estimate);
  EXPECT_EQ(estimate->duration, 3200ms + 20ms);  // 1.6 m at 0.5 m/s, and a poll

  const auto start = rig.clock().now();
  const JobOutcome o = rig.run_job(c4, "t1", op);
  ASSERT_TRUE(o.ok) << o.detail;
  EXPECT_NEAR(std::chrono::duration<double>(rig.clock().now() - start).count(), 3.2, 0.1);
  EXPECT_EQ(rig.world().box_in_place(3, 1), rig.world().box(id));
  const ControllerStatus s = c4.status();
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "plc.station_box.download").value), id);
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "plc.station_box.denso").value), 0);
  EXPECT_TRUE(std::get<bool>(tag(s, "plc.station_eye.download").value));
  EXPECT_TRUE(std::get<bool>(tag(s, "plc.stopper.denso").value));  // raised again behind the box
  rig.run_for(100ms);
  EXPECT_FALSE(std::get<bool>(tag(c4.status(), "plc.running").value));
}

TEST(GatewayConveyor, HandsABoxOverToTheNextBeltThroughTheDiverter) {
  GatewayRig rig;
  Gateway& c1 = rig.add("conveyor1", "conveyor");
  auto [c3, id] = rig.add_with_box("conveyor3", "conveyor", "conveyor1/upload");
  // conveyor3 is the second belt conveyor1 feeds: the diverter sends the box there.
  JobOutcome o = rig.run_job(c1, "t1", rig.transport(id, "conveyor1/upload", "conveyor3"));
  ASSERT_TRUE(o.ok) << o.detail;
  EXPECT_EQ(rig.world().box(id)->belt, 2U);
  EXPECT_TRUE(std::get<bool>(tag(c1.status(), "plc.divert").value));
  o = rig.run_job(c3, "t2", rig.transport(id, "conveyor3", "conveyor3/toshiba"));
  ASSERT_TRUE(o.ok) << o.detail;
  EXPECT_EQ(rig.world().box_in_place(2, 0), rig.world().box(id));
}

TEST(GatewayConveyor, RefusesWhatItsBeltCannotDo) {
  GatewayRig rig;
  Gateway& c4 = rig.add("conveyor4", "conveyor");
  rig.run_for(100ms);
  std::string why;
  EXPECT_FALSE(c4.estimate(rig.transport(1, "conveyor4/download", "conveyor4/denso"), &why));
  EXPECT_EQ(why, "conveyor4 does not carry boxes from conveyor4/download to conveyor4/denso");
  EXPECT_FALSE(c4.estimate(rig.transport(1, "conveyor2/scara1", "conveyor4"), &why));
  EXPECT_FALSE(c4.estimate({"transport", {{"box", 1}, {"from", 7}}}, &why));
  EXPECT_EQ(why, "transport needs the parameter 'to'");
  EXPECT_FALSE(c4.estimate({"transport", {{"box", 1}, {"from", 7}, {"to", 99}}}, &why));
  EXPECT_NE(why.find("'to' = 99 is not a whole number in 0..9"), std::string::npos) << why;
  EXPECT_FALSE(c4.estimate({"load", {}}, &why));
  EXPECT_EQ(why, "conveyor4 does not do 'load'");
  auto refused = c4.submit("x", {"load", {}});
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().code, Errc::state);

  // A box that is not where the transport starts: the transport waits for it, nothing moves.
  const auto id = rig.put_box("conveyor4/denso");
  ASSERT_TRUE(c4.submit("t1", rig.transport(id + 1, "conveyor4/denso", "conveyor4/download")));
  rig.run_for(2s);
  EXPECT_FALSE(rig.ended("t1"));
  EXPECT_FALSE(c4.status().job);
  EXPECT_EQ(c4.status().queued, 1U);
  EXPECT_FALSE(std::get<bool>(tag(c4.status(), "plc.running").value));
  EXPECT_EQ(rig.world().box_in_place(3, 0), rig.world().box(id));
  ASSERT_TRUE(c4.cancel("t1"));
  rig.step();
  EXPECT_EQ(rig.outcome("t1").detail, "cancelled before it started");
  EXPECT_EQ(c4.status().packml.defective, 0U);
}

TEST(GatewayLegacyRobot, LoadsCandiesThroughItsControllersHandshake) {
  GatewayRig rig;
  auto [toshiba, id] = rig.add_with_box("toshiba", "legacy-robot", "conveyor3/toshiba");
  EXPECT_TRUE(std::get<bool>(tag(toshiba.status(), "robot.box_in_place.toshiba").value));
  const Operation op{
      "load", {{"candy", rig.candy("gummy")}, {"count", 3}, {"box", id}, {"slot", 2}, {"box_type", 0}}};
  auto estimate = toshiba.estimate(op);
  ASSERT_TRUE(estimate);

  const auto start = rig.clock().now();
  const JobOutcome o = rig.run_job(toshiba, "l1", op);
  ASSERT_TRUE(o.ok) << o.detail;
  EXPECT_EQ(o.detail, fmt::format("3 gummy in box {}, slots 2-4", id));
  EXPECT_EQ(o.results.at("placed"), 3);
  const auto& slots = rig.world().box(id)->slots;
  for (std::size_t s = 0; s < slots.size(); ++s) {
    EXPECT_EQ(slots[s], s >= 2 && s <= 4 ? static_cast<int>(rig.candy("gummy")) : -1) << "slot " << s;
  }
  // The estimate follows the controller's moves through the layout: within a poll per candy.
  const auto took = rig.clock().now() - start;
  EXPECT_LT(std::chrono::abs(took - estimate->duration), 3 * 20ms)
      << std::chrono::duration<double>(took).count() << " s against "
      << std::chrono::duration<double>(estimate->duration).count() << " s";
  const ControllerStatus s = toshiba.status();
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "robot.jobs_done").value), 3);
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "robot.phase").value), 0);
  EXPECT_EQ(s.packml.produced, 1U);  // one job
  // A SCARA controller reports four joints; its tool point (home: 15 cm over the station) in mm.
  EXPECT_TRUE(has_tag(s, "robot.joint3"));
  EXPECT_FALSE(has_tag(s, "robot.joint4"));
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "robot.tool_z").value), 950);
  // Its drives' temperature, from 0.1 °C in the register to °C, warmed by the job's moves.
  const Tag& temperature = tag(s, "robot.temperature");
  EXPECT_EQ(temperature.unit, "CEL");
  EXPECT_GT(std::get<double>(temperature.value), 25.0);
  EXPECT_LT(std::get<double>(temperature.value), 30.0);
  EXPECT_EQ(tag(s, "robot.phase").unit, "");
}

TEST(GatewayLegacyRobot, DeclinesCandiesItHasNoDispenserOf) {
  GatewayRig rig;
  Gateway& denso = rig.add("denso", "legacy-robot");
  rig.run_for(100ms);
  std::string why;
  const Operation gummy{"load", {{"candy", rig.candy("gummy")}, {"count", 1}, {"box", 1}, {"slot", 0}}};
  EXPECT_FALSE(denso.estimate(gummy, &why));
  EXPECT_EQ(why, "denso has no dispenser of gummy");
  const Operation lollipop{"load", {{"candy", rig.candy("lollipop")}, {"count", 1}, {"box", 1}, {"slot", 0}}};
  EXPECT_TRUE(denso.estimate(lollipop, &why)) << why;
  EXPECT_TRUE(has_tag(denso.status(), "robot.joint5"));  // an articulated arm: six joints
}

TEST(GatewayDownloader, TakesTheBoxOffAndReportsTheInspection) {
  GatewayRig rig;
  auto [down, id] = rig.add_with_box("downloader", "downloader", "conveyor4/download");
  const JobOutcome o = rig.run_job(down, "d1", {"download", {{"box", id}}});
  ASSERT_TRUE(o.ok) << o.detail;
  EXPECT_EQ(o.results.at("box"), id);
  EXPECT_EQ(o.results.at("weight_g"), 40.0);  // the small box's tare
  EXPECT_EQ(o.results.at("candy_total"), 0);
  EXPECT_EQ(rig.world().box(id), nullptr);
  EXPECT_EQ(std::get<double>(tag(down.status(), "plc.weight").value), 40.0);

  // No box at the station: the job waits for its box; the PLC is not started on an empty station.
  ASSERT_TRUE(down.submit("d2", {"download", {{"box", id + 1}}}));
  rig.run_for(2s);
  EXPECT_FALSE(rig.ended("d2"));
  EXPECT_EQ(down.status().queued, 1U);
  EXPECT_EQ(std::get<std::int64_t>(tag(down.status(), "plc.jobs_done").value), 1);
  EXPECT_EQ(down.status().packml.state, S::Execute);
  EXPECT_EQ(down.status().fault, "");
}

// upload → conveyor1 → conveyor3 → TOSHIBA loads toffee → conveyor3 → conveyor4 → DENSO loads a
// lollipop → conveyor4 → download and inspection.
TEST(GatewayChain, PacksOneBoxFromUploadToInspection) {
  GatewayRig rig;
  Gateway& up = rig.add("uploader", "uploader");
  Gateway& c1 = rig.add("conveyor1", "conveyor");
  Gateway& c3 = rig.add("conveyor3", "conveyor");
  Gateway& c4 = rig.add("conveyor4", "conveyor");
  Gateway& toshiba = rig.add("toshiba", "legacy-robot");
  Gateway& denso = rig.add("denso", "legacy-robot");
  Gateway& down = rig.add("downloader", "downloader");
  rig.run_for(200ms);

  std::vector<std::string> log;
  auto step = [&](Gateway& g, const std::string& job, const Operation& op) {
    const JobOutcome o = rig.run_job(g, job, op);
    log.push_back(fmt::format("{} {}: {}", g.identification().name, o.ok ? "done" : "FAILURE", o.detail));
    EXPECT_TRUE(o.ok) << o.detail;
    return o;
  };
  const auto id =
      static_cast<std::uint16_t>(step(up, "upload", {"upload", {{"box_type", 0}}}).results.at("box"));
  step(c1, "c1", rig.transport(id, "conveyor1/upload", "conveyor3"));
  step(c3, "c3a", rig.transport(id, "conveyor3", "conveyor3/toshiba"));
  step(toshiba, "toffee", {"load", {{"candy", rig.candy("toffee")}, {"count", 2}, {"box", id}, {"slot", 0}}});
  step(c3, "c3b", rig.transport(id, "conveyor3/toshiba", "conveyor4"));
  step(c4, "c4a", rig.transport(id, "conveyor4", "conveyor4/denso"));
  step(denso, "lollipop",
       {"load", {{"candy", rig.candy("lollipop")}, {"count", 1}, {"box", id}, {"slot", 5}}});
  step(c4, "c4b", rig.transport(id, "conveyor4/denso", "conveyor4/download"));
  const JobOutcome inspected = step(down, "download", {"download", {{"box", id}}});

  EXPECT_EQ(inspected.results.at("box"), id);
  EXPECT_EQ(inspected.results.at("count.toffee"), 2);
  EXPECT_EQ(inspected.results.at("count.lollipop"), 1);
  EXPECT_EQ(inspected.results.at("candy_total"), 3);
  EXPECT_DOUBLE_EQ(inspected.results.at("weight_g"), 40.0 + 2 * 8.0 + 15.0);
  EXPECT_EQ(inspected.detail, fmt::format("box {}: 71.0 g, 1 lollipop, 2 toffee", id));
  EXPECT_TRUE(rig.world().boxes().empty());
  EXPECT_EQ(log.size(), 9U);
  for (const auto& line : log) {
    EXPECT_EQ(line.find("FAILURE"), std::string::npos) << line;
  }
}

}  // namespace
}  // namespace sf::factory::testing
