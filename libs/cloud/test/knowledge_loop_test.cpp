// The knowledge loop over the repository's ontology, rules and default layout: inspections and
// machine faults as the gateway delivers them become facts, and the rules' violations alarms.
#include "sf/cloud/knowledge_loop.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sf/line/inspection.hpp"

namespace sf::cloud {
namespace {

using namespace std::chrono_literals;

std::string source_file(const std::string& path) {
  const char* root = std::getenv("SF_SOURCE_DIR");  // NOLINT(concurrency-mt-unsafe): no thread sets it
  std::ifstream in(std::string(root != nullptr ? root : ".") + "/" + path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class KnowledgeLoopTest : public ::testing::Test {
 protected:
  void make(std::chrono::seconds due_after = 0s) {
    auto layout = line::default_layout();
    ASSERT_TRUE(layout) << layout.error().describe();
    layout_ = std::move(*layout);
    KnowledgeLoopOptions o;
    o.ontology = source_file("ontology/candy-factory.ttl");
    o.rules = source_file("rules/candy-factory.rules");
    ASSERT_FALSE(o.ontology.empty() || o.rules.empty()) << "SF_SOURCE_DIR names the repository";
    o.due_after = due_after;
    auto loop = KnowledgeLoop::create(layout_, o, [this](const Alarm& a) { alarms.push_back(a); });
    ASSERT_TRUE(loop) << loop.error().describe();
    loop_ = std::move(*loop);
    // The static data of the default line violates nothing.
    ASSERT_TRUE(alarms.empty()) << alarms.front().message;
  }

  void value(std::string path, historian::Value v, bool replayed = false, std::string unit = {}) {
    historian::SeriesInfo info{"line", "ns=2;s=" + path, std::move(path), historian::DataType::string,
                               std::move(unit)};
    LiveUpdate u{&info, {}, replayed};
    u.sample.source_time = replayed ? now_ - 10s : now_;
    u.sample.value = std::move(v);
    now_ += 1s;
    loop_->on_value(u);
  }
  void inspect(const line::InspectionRecord& r) {
    value("/Objects/OrderService/LastInspection", format_inspection(r));
  }
  void fault(const std::string& machine, const std::string& text) {
    value("/Objects/Machines/" + machine + "/Fault", text);
  }
  // A machine's tag in the unit its EngineeringUnits name.
  void tag(const std::string& machine, const std::string& name, double v, std::string unit) {
    value("/Objects/Machines/" + machine + "/Tags/" + name, v, false, std::move(unit));
  }
  std::vector<Alarm> raised(std::string_view rule) const {
    std::vector<Alarm> out;
    for (const auto& a : alarms) {
      if (a.rule == rule && a.active) {
        out.push_back(a);
      }
    }
    return out;
  }

  line::Layout layout_;
  std::unique_ptr<KnowledgeLoop> loop_;
  std::vector<Alarm> alarms;
  historian::Timestamp now_{std::chrono::sys_days{std::chrono::November / 27 / 2026}};
};

line::InspectionRecord box(std::string order, std::uint32_t id, std::map<std::string, int> counted) {
  return {std::move(order),   id,   "small-box", {{"chocolate", 4}, {"gummy", 3}},
          std::move(counted), 80.0, 30.0};
}

TEST_F(KnowledgeLoopTest, ABoxHoldingItsOrderRaisesNothing) {
  make();
  inspect(box("alice-1", 7, {{"chocolate", 4}, {"gummy", 3}}));
  EXPECT_TRUE(alarms.empty()) << alarms.front().message;
  EXPECT_EQ(loop_->status().inspections, 1U);
  EXPECT_EQ(loop_->status().rejected, 0U);
}

TEST_F(KnowledgeLoopTest, ABoxWhoseContentDiffersRaisesOneContentMismatchWithItsExplanation) {
  make();
  inspect(box("alice-1", 7, {{"chocolate", 4}, {"gummy", 2}}));
  ASSERT_EQ(alarms.size(), 1U);
  const Alarm& a = alarms.front();
  EXPECT_EQ(a.rule, "contentMismatch");
  EXPECT_TRUE(a.active);
  EXPECT_EQ(a.message, "gummy bear: ordered 3, the box holds 2");
  EXPECT_TRUE(a.entity.ends_with("Box_alice-1_7")) << a.entity;
  bool quantity = false;
  for (const auto& f : a.facts) {
    quantity = quantity || (f.find("quantity") != std::string::npos && f.find("\"3\"") != std::string::npos);
  }
  EXPECT_TRUE(quantity) << "the explanation holds the order line's quantity";
  // The order made again in a good box: that box raises nothing; the rejected box's alarm stays.
  inspect(box("alice-1", 9, {{"chocolate", 4}, {"gummy", 3}}));
  EXPECT_EQ(alarms.size(), 1U);
  EXPECT_EQ(loop_->active_alarms().size(), 1U);
}

TEST_F(KnowledgeLoopTest, ACandyTypeMissingFromTheBoxOrNotOrderedIsAMismatchToo) {
  make();
  inspect(box("bob-1", 3, {{"chocolate", 4}, {"lollipop", 3}}));
  ASSERT_GE(raised("contentMismatch").size(), 1U);
  EXPECT_EQ(raised("contentMismatch").front().message, "gummy bear: ordered 3, the box holds 0");
  // The lollipops nobody ordered.
  ASSERT_EQ(raised("contentMismatch").size(), 2U);
  EXPECT_EQ(raised("contentMismatch").back().message, "lollipop: ordered 0, the box holds 3");
}

TEST_F(KnowledgeLoopTest, AnOrderLineOverTheBoxCapacityIsReported) {
  make();
  line::InspectionRecord r{"big-1", 4, "small-box", {{"toffee", 13}}, {{"toffee", 12}}, 140.0, 10.0};
  inspect(r);
  ASSERT_EQ(raised("overCapacity").size(), 1U);
  EXPECT_EQ(raised("overCapacity").front().message, "quantity 13 exceeds the box capacity 12");
}

TEST_F(KnowledgeLoopTest, ABoxInspectedAfterItsDueTimeIsLate) {
  make(60s);
  inspect(box("quick-1", 1, {{"chocolate", 4}, {"gummy", 3}}));  // 30 s after acceptance
  EXPECT_TRUE(raised("late").empty());
  auto slow = box("slow-1", 2, {{"chocolate", 4}, {"gummy", 3}});
  slow.lead_s = 90.0;
  inspect(slow);
  ASSERT_EQ(raised("late").size(), 1U);
  EXPECT_TRUE(raised("late").front().entity.ends_with("Box_slow-1_2"));
}

TEST_F(KnowledgeLoopTest, AMachineFaultIsRaisedOnceAndClearedWhenItGoes) {
  make();
  fault("Conveyor3", "jam (fault 1)");
  fault("Conveyor3", "jam (fault 1)");  // the same value again
  ASSERT_EQ(alarms.size(), 1U);
  EXPECT_EQ(alarms[0].rule, "fault");
  EXPECT_EQ(alarms[0].message, "in state fault: jam (fault 1)");
  fault("Conveyor3", "");
  ASSERT_EQ(alarms.size(), 2U);
  EXPECT_FALSE(alarms[1].active);
  EXPECT_EQ(alarms[1].id, alarms[0].id);
  EXPECT_TRUE(loop_->active_alarms().empty());
}

TEST_F(KnowledgeLoopTest, ValuesReadBackFromHistoryAddWhatWasMissedAndNeverTurnAStateBack) {
  make();
  const auto bad = format_inspection(box("alice-1", 7, {{"chocolate", 4}, {"gummy", 2}}));
  value("/Objects/OrderService/LastInspection", bad);
  value("/Objects/OrderService/LastInspection", bad, true);  // the same box again: nothing new
  EXPECT_EQ(alarms.size(), 1U);
  EXPECT_EQ(loop_->status().inspections, 1U);
  // A box inspected while the cloud was away, read back after a newer one arrived live.
  value("/Objects/OrderService/LastInspection", format_inspection(box("bob-1", 8, {{"gummy", 3}})), true);
  EXPECT_EQ(raised("contentMismatch").size(), 2U);
  fault("Conveyor3", "jam (fault 1)");
  fault("Conveyor3", "");
  value("/Objects/Machines/Conveyor3/Fault", std::string("jam (fault 1)"), true);  // older than the clearing
  EXPECT_TRUE(raised("fault").size() == 1U && loop_->active_alarms().size() == 2U);
}

TEST_F(KnowledgeLoopTest, UnreadableValuesAreCountedAndTheLoopGoesOn) {
  make();
  value("/Objects/OrderService/LastInspection", std::string("alice-1 box=x"));
  value("/Objects/Machines/Conveyor3/Fault", std::int64_t{3});
  value("/Objects/Machines/Conveyor3/Speed", 0.4);  // not a fact the loop knows: left alone
  EXPECT_EQ(loop_->status().rejected, 2U);
  EXPECT_NE(loop_->status().last_error.find("Fault"), std::string::npos) << loop_->status().last_error;
  inspect(box("alice-1", 7, {{"chocolate", 1}, {"gummy", 3}}));
  EXPECT_EQ(raised("contentMismatch").size(), 1U);
}

TEST_F(KnowledgeLoopTest, AnAlarmIsAHistorianEventWithItsRuleAndFacts) {
  make();
  inspect(box("alice-1", 7, {{"chocolate", 4}, {"gummy", 2}}));
  ASSERT_EQ(alarms.size(), 1U);
  const historian::Event e = alarm_event(alarms.front(), "knowledge");
  EXPECT_EQ(e.server, "knowledge");
  EXPECT_EQ(e.source_name, "Box_alice-1_7");
  EXPECT_EQ(e.message, alarms.front().message);
  EXPECT_EQ(e.time, alarms.front().time);
  const auto fields = nlohmann::json::parse(e.fields);
  EXPECT_EQ(fields["rule"], "contentMismatch");
  EXPECT_TRUE(fields["active"].get<bool>());
  EXPECT_EQ(fields["facts"].size(), alarms.front().facts.size());
  Alarm cleared = alarms.front();
  cleared.active = false;
  cleared.change = AlarmChange::cleared;
  EXPECT_NE(alarm_event(cleared, "knowledge").event_id, e.event_id);
}

TEST_F(KnowledgeLoopTest, ATemperatureOverItsMaximumRaisesOneAlarmThatClearsWhenItReturns) {
  make();
  tag("Denso", "robot.temperature", 65.0, "°C");  // sf:maxTemperature 70.0 (the line's individuals)
  EXPECT_TRUE(alarms.empty());
  tag("Denso", "robot.temperature", 74.5, "°C");
  ASSERT_EQ(alarms.size(), 1U);
  EXPECT_EQ(alarms[0].rule, "temperatureHigh");
  EXPECT_EQ(alarms[0].message, "temperature 74.5 above the maximum 70.0");
  EXPECT_TRUE(alarms[0].entity.ends_with("/Denso")) << alarms[0].entity;
  // Hotter still: the same alarm, its message follows the value.
  tag("Denso", "robot.temperature", 76.0, "°C");
  EXPECT_EQ(alarms.size(), 1U);
  ASSERT_EQ(loop_->active_alarms().size(), 1U);
  EXPECT_EQ(loop_->active_alarms()[0].message, "temperature 76.0 above the maximum 70.0");
  tag("Denso", "robot.temperature", 69.5, "°C");
  ASSERT_EQ(alarms.size(), 2U);
  EXPECT_FALSE(alarms[1].active);
  EXPECT_EQ(alarms[1].change, AlarmChange::cleared);
  EXPECT_EQ(alarms[1].id, alarms[0].id);
  EXPECT_TRUE(loop_->active_alarms().empty());
  // Kelvin is converted: 350 K = 76.85 °C.
  tag("Toshiba", "robot.temperature", 350.0, "K");
  ASSERT_EQ(raised("temperatureHigh").size(), 2U);
  EXPECT_EQ(raised("temperatureHigh").back().message, "temperature 76.85 above the maximum 70.0");
}

TEST_F(KnowledgeLoopTest, AnAxisOutsideItsTravelRaisesOneAlarmThatClearsWhenItReturns) {
  make();
  // The smart robot publishes SI units: radians for θ1 (travel -149.0..149.0°), metres for z
  // (0.0..300.0 mm).
  tag("ScaraRobot1", "axis1.position", 1.0, "rad");
  tag("ScaraRobot1", "axis2.position", -2.5, "rad");  // at its joint limit: inside its travel
  tag("ScaraRobot1", "axis3.position", 0.25, "m");
  EXPECT_TRUE(alarms.empty()) << alarms.front().message;
  tag("ScaraRobot1", "axis1.position", 2.7, "rad");  // 154.699°
  ASSERT_EQ(alarms.size(), 1U);
  EXPECT_EQ(alarms[0].rule, "axisTravel");
  EXPECT_EQ(alarms[0].message, "position 154.699 outside -149.0..149.0");
  EXPECT_TRUE(alarms[0].entity.ends_with("/ScaraRobot1Axis1")) << alarms[0].entity;
  tag("ScaraRobot1", "axis1.position", 2.8, "rad");  // further out: still the one alarm
  EXPECT_EQ(alarms.size(), 1U);
  tag("ScaraRobot1", "axis1.position", -0.5, "rad");
  ASSERT_EQ(alarms.size(), 2U);
  EXPECT_FALSE(alarms[1].active);
  EXPECT_EQ(alarms[1].id, alarms[0].id);
  tag("ScaraRobot1", "axis3.position", 0.31, "m");
  ASSERT_EQ(raised("axisTravel").size(), 2U);
  EXPECT_EQ(raised("axisTravel").back().message, "position 310.0 outside 0.0..300.0");
  tag("ScaraRobot1", "axis3.position", 0.3, "m");  // at the end of its travel: inside
  EXPECT_TRUE(loop_->active_alarms().empty());
  EXPECT_EQ(loop_->status().rejected, 0U);
}

TEST_F(KnowledgeLoopTest, AQuantityWithoutAUnitOfItsKindIsRejectedNotGuessed) {
  make();
  tag("ScaraRobot1", "axis1.position", 2.7, "");
  tag("ScaraRobot1", "axis1.position", 2.7, "°C");
  tag("Denso", "robot.temperature", 90.0, "furlong");
  value("/Objects/Machines/Denso/Tags/robot.temperature", std::string("hot"), false, "°C");
  EXPECT_TRUE(alarms.empty());
  EXPECT_EQ(loop_->status().rejected, 4U);
  EXPECT_NE(loop_->status().last_error.find("a temperature is a number"), std::string::npos)
      << loop_->status().last_error;
  tag("ScaraRobot1", "axis1.position", 154.7, "°");  // degrees as they are
  EXPECT_EQ(raised("axisTravel").size(), 1U);
}

TEST_F(KnowledgeLoopTest, ABoxWhoseContentDiffersRaisesOneAlarmThatClearsWhenTheBoxIsRightAgain) {
  make();
  inspect(box("carol-1", 5, {{"chocolate", 4}, {"gummy", 1}}));
  ASSERT_EQ(alarms.size(), 1U);
  EXPECT_EQ(alarms[0].rule, "contentMismatch");
  EXPECT_EQ(alarms[0].message, "gummy bear: ordered 3, the box holds 1");
  inspect(box("carol-1", 5, {{"chocolate", 4}, {"gummy", 2}}));  // refilled, one short still
  EXPECT_EQ(alarms.size(), 1U);
  ASSERT_EQ(loop_->active_alarms().size(), 1U);
  EXPECT_EQ(loop_->active_alarms()[0].message, "gummy bear: ordered 3, the box holds 2");
  inspect(box("carol-1", 5, {{"chocolate", 4}, {"gummy", 3}}));  // the box now holds its order
  ASSERT_EQ(alarms.size(), 2U);
  EXPECT_FALSE(alarms[1].active);
  EXPECT_EQ(alarms[1].id, alarms[0].id);
  EXPECT_TRUE(loop_->active_alarms().empty());
  EXPECT_EQ(loop_->status().rejected, 0U);
}

TEST_F(KnowledgeLoopTest, AnOperatorAcknowledgesAnAlarmOnce) {
  make();
  EXPECT_EQ(loop_->acknowledge("axisTravel-0000000000000000", "olga", "").error().code, Errc::not_found);
  tag("Denso", "robot.temperature", 75.0, "°C");
  ASSERT_EQ(alarms.size(), 1U);
  const std::string id = alarms[0].id;
  EXPECT_FALSE(alarms[0].acked);
  ASSERT_TRUE(loop_->acknowledge(id, "olga", "fan replaced"));
  ASSERT_EQ(alarms.size(), 2U);
  EXPECT_EQ(alarms[1].change, AlarmChange::acknowledged);
  EXPECT_TRUE(alarms[1].acked && alarms[1].active);
  EXPECT_EQ(alarms[1].acked_by, "olga");
  EXPECT_EQ(alarms[1].ack_comment, "fan replaced");
  EXPECT_EQ(loop_->acknowledge(id, "olga", "").error().code, Errc::state);
  // Cleared after its acknowledgement: no longer retained.
  tag("Denso", "robot.temperature", 60.0, "°C");
  EXPECT_TRUE(loop_->retained_alarms().empty());
  // Cleared before it: retained until an operator acknowledges it.
  tag("Denso", "robot.temperature", 75.0, "°C");
  tag("Denso", "robot.temperature", 60.0, "°C");
  ASSERT_EQ(loop_->retained_alarms().size(), 1U);
  EXPECT_FALSE(loop_->retained_alarms()[0].active);
  ASSERT_TRUE(loop_->acknowledge(id, "piet", ""));
  EXPECT_TRUE(loop_->retained_alarms().empty());
  const historian::Event e = alarm_event(alarms.back(), "knowledge");
  const auto fields = nlohmann::json::parse(e.fields);
  EXPECT_EQ(fields["change"], "acknowledged");
  EXPECT_TRUE(fields["acked"].get<bool>());
  EXPECT_EQ(fields["acked_by"], "piet");
  EXPECT_EQ(fields["id"], id);
  EXPECT_EQ(e.message, "acknowledged: temperature 75.0 above the maximum 70.0");
}

TEST(KnowledgeLoopCreate, BadRulesAreRefusedNamingTheirPlace) {
  auto layout = line::default_layout();
  ASSERT_TRUE(layout);
  KnowledgeLoopOptions o;
  o.rules = "[broken: (?a ?b ?c) -> ";
  o.rules_name = "mine.rules";
  auto loop = KnowledgeLoop::create(*layout, o, nullptr);
  ASSERT_FALSE(loop);
  EXPECT_NE(loop.error().message.find("mine.rules"), std::string::npos) << loop.error().message;
  o.rules = "";
  o.ontology = "@prefix x: <urn:x#> . x:a x:b";
  EXPECT_FALSE(KnowledgeLoop::create(*layout, o, nullptr));
}

}  // namespace
}  // namespace sf::cloud
