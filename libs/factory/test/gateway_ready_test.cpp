// Many boxes on the line: a gateway begins the first queued job whose box
// stands at its station (the station's tag reader) or whose way is clear, and
// the others wait for theirs instead of failing or taking the wrong box.
#include "gateway_rig.hpp"

namespace sf::factory::testing {
namespace {

Operation load(const GatewayRig& rig, std::string_view candy, std::uint16_t box, int slot) {
  return {"load", {{"candy", rig.candy(candy)}, {"count", 1}, {"box", box}, {"slot", slot}}};
}

// Takes the box standing at `station` off the line (an operator's hand), then lets the PLCs scan.
void take_off(GatewayRig& rig, std::string_view station) {
  ASSERT_TRUE(rig.world().take_box(*line::find_station(rig.plant().layout(), station), "test"));
  rig.step();
}

// Boxes put at `first` and `second` (in that order), then a few polls.
std::pair<std::uint16_t, std::uint16_t> two_boxes(GatewayRig& rig, std::string_view first,
                                                  std::string_view second) {
  const std::uint16_t a = rig.put_box(first);
  const std::uint16_t b = rig.put_box(second);
  rig.run_for(100ms);
  return {a, b};
}

TEST(GatewayReady, ALegacyRobotLoadsTheBoxAtItsStationFirstAndTheEarlierJobWaitsForItsOwn) {
  GatewayRig rig;
  Gateway& toshiba = rig.add("toshiba", "legacy-robot");
  const auto [b1, b2] = two_boxes(rig, "conveyor1/upload", "conveyor3/toshiba");
  EXPECT_EQ(std::get<std::int64_t>(tag(toshiba.status(), "robot.station_box.toshiba").value), b2);
  ASSERT_TRUE(toshiba.submit("for-b1", load(rig, "gummy", b1, 0)));
  const JobOutcome second = rig.run_job(toshiba, "for-b2", load(rig, "toffee", b2, 3));
  ASSERT_TRUE(second.ok) << second.detail;
  EXPECT_EQ(rig.world().box(b2)->slots[3], static_cast<int>(rig.candy("toffee")));
  EXPECT_EQ(rig.world().box(b2)->slots[0], -1);  // b1's gummy did not go into b2
  EXPECT_FALSE(rig.ended("for-b1"));
  EXPECT_EQ(toshiba.status().queued, 1U);

  // b2 leaves, b1 comes: its job begins once the reader reads it.
  take_off(rig, "conveyor3/toshiba");
  Gateway& c1 = rig.add("conveyor1", "conveyor");
  Gateway& c3 = rig.add("conveyor3", "conveyor");
  rig.run_for(100ms);
  ASSERT_TRUE(rig.run_job(c1, "c1", rig.transport(b1, "conveyor1/upload", "conveyor3")).ok);
  ASSERT_TRUE(rig.run_job(c3, "c3", rig.transport(b1, "conveyor3", "conveyor3/toshiba")).ok);
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("for-b1"); }, 30s));
  EXPECT_TRUE(rig.outcome("for-b1").ok) << rig.outcome("for-b1").detail;
  EXPECT_EQ(rig.world().box(b1)->slots[0], static_cast<int>(rig.candy("gummy")));
}

TEST(GatewayReady, TheDownloaderTakesOffOnlyItsJobsBox) {
  GatewayRig rig;
  Gateway& down = rig.add("downloader", "downloader");
  Gateway& c4 = rig.add("conveyor4", "conveyor");
  const auto [b1, b2] = two_boxes(rig, "conveyor4/denso", "conveyor4/download");
  EXPECT_EQ(std::get<std::int64_t>(tag(down.status(), "plc.station_box").value), b2);
  ASSERT_TRUE(down.submit("for-b1", {"download", {{"box", b1}}}));
  // b2 stands there: for-b1 does not take it off.
  rig.run_for(3s);
  EXPECT_FALSE(rig.ended("for-b1"));
  EXPECT_TRUE(rig.at(b2, "conveyor4/download"));
  // b2's own job, queued later, goes first.
  const JobOutcome second = rig.run_job(down, "for-b2", {"download", {{"box", b2}}});
  ASSERT_TRUE(second.ok) << second.detail;
  EXPECT_EQ(second.results.at("box"), b2);
  EXPECT_FALSE(rig.ended("for-b1"));
  ASSERT_TRUE(rig.world().box(b1) != nullptr);  // still on the line
  // b1 is carried to the station and taken off by its job.
  ASSERT_TRUE(rig.run_job(c4, "c4", rig.transport(b1, "conveyor4/denso", "conveyor4/download")).ok);
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("for-b1"); }, 10s));
  EXPECT_TRUE(rig.outcome("for-b1").ok) << rig.outcome("for-b1").detail;
  EXPECT_EQ(rig.outcome("for-b1").results.at("box"), b1);
  EXPECT_EQ(rig.world().box(b1), nullptr);
}

TEST(GatewayReady, TheUploaderWaitsUntilItsPlaceIsFree) {
  GatewayRig rig;
  Gateway& up = rig.add("uploader", "uploader");
  const std::uint16_t standing = rig.put_box("conveyor1/upload");
  rig.run_for(100ms);
  ASSERT_TRUE(up.submit("u1", {"upload", {{"box_type", 0}}}));
  rig.run_for(15s);  // longer than the PLC would wait for its place before it faults
  EXPECT_FALSE(rig.ended("u1"));
  EXPECT_EQ(std::get<std::int64_t>(tag(up.status(), "plc.jobs_done").value), 0);
  take_off(rig, "conveyor1/upload");
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("u1"); }, 10s));
  EXPECT_TRUE(rig.outcome("u1").ok) << rig.outcome("u1").detail;
  EXPECT_NE(rig.outcome("u1").results.at("box"), standing);
}

// b1 waits at conveyor4/denso for the download station, where b2 stands; b2's
// transport onto the next belt, queued later, goes first and clears the way.
TEST(GatewayReady, ATransportWaitsForItsTargetStationWhileALaterOneThatIsClearRuns) {
  GatewayRig rig;
  Gateway& c4 = rig.add("conveyor4", "conveyor");
  const auto [b1, b2] = two_boxes(rig, "conveyor4/denso", "conveyor4/download");
  ASSERT_TRUE(c4.submit("b1-to-download", rig.transport(b1, "conveyor4/denso", "conveyor4/download")));
  rig.run_for(1s);
  EXPECT_FALSE(rig.ended("b1-to-download"));  // waits, does not fail
  EXPECT_TRUE(rig.at(b1, "conveyor4/denso"));
  const JobOutcome cleared = rig.run_job(c4, "b2-away", rig.transport(b2, "conveyor4/download", "conveyor5"));
  ASSERT_TRUE(cleared.ok) << cleared.detail;
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("b1-to-download"); }, 10s));
  EXPECT_TRUE(rig.outcome("b1-to-download").ok) << rig.outcome("b1-to-download").detail;
  EXPECT_TRUE(rig.at(b1, "conveyor4/download"));
  EXPECT_EQ(c4.status().packml.defective, 0U);
}

// A box waiting at conveyor2's entry rides up to the first station (its
// stopper raised) while the belt runs for the box ahead of it; it is still at
// the place "conveyor2", and its transport from there runs.
TEST(GatewayReady, ABoxThatDriftedFromTheEntryIntoTheFirstStationIsTransportedFromTheEntry) {
  GatewayRig rig;
  Gateway& c1 = rig.add("conveyor1", "conveyor");
  Gateway& c2 = rig.add("conveyor2", "conveyor");
  Gateway& c4 = rig.add("conveyor4", "conveyor");
  const auto [ahead, behind] = two_boxes(rig, "conveyor2/scara1", "conveyor1/upload");
  ASSERT_TRUE(rig.run_job(c1, "behind-to-c2", rig.transport(behind, "conveyor1/upload", "conveyor2")).ok);
  ASSERT_TRUE(rig.run_job(c2, "ahead-on", rig.transport(ahead, "conveyor2/scara1", "conveyor4")).ok);
  ASSERT_TRUE(rig.run_job(c4, "ahead-to-denso", rig.transport(ahead, "conveyor4", "conveyor4/denso")).ok);
  ASSERT_TRUE(rig.at(behind, "conveyor2/scara1")) << "the box did not drift into the first station";
  const JobOutcome o = rig.run_job(c2, "behind-on", rig.transport(behind, "conveyor2", "conveyor4"));
  ASSERT_TRUE(o.ok) << o.detail;
  EXPECT_EQ(rig.world().box(behind)->belt, 3U);  // conveyor4
}

}  // namespace
}  // namespace sf::factory::testing
