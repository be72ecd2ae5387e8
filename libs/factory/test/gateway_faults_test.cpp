// Gateways under the plant's faults: an unreachable PLC, a PLC answering with
// Modbus exceptions, an empty dispenser, a jammed belt, a box lost on the way.
#include "gateway_rig.hpp"

namespace sf::factory::testing {
namespace {

using S = PackMLState;
using Q = Tag::Quality;

bool all_tags(const ControllerStatus& s, Q quality, std::string_view reason_part) {
  return !s.tags.empty() && std::all_of(s.tags.begin(), s.tags.end(), [&](const Tag& t) {
    return t.quality == quality && t.reason.find(reason_part) != std::string::npos;
  });
}

TEST(GatewayLink, AnUnreachablePlcTurnsTheTagsBadStopsTheBidsAndRecovers) {
  GatewayRig rig;
  auto [c4, id] = rig.add_with_box("conveyor4", "conveyor", "conveyor4/denso");
  ASSERT_TRUE(c4.submit("t1", rig.transport(id, "conveyor4/denso", "conveyor4/download")));
  rig.run_for(1s);
  ASSERT_TRUE(all_tags(c4.status(), Q::good, ""));

  rig.inject("plc-unreachable:conveyor4");
  // The first poll without an answer: the values are stale, not yet wrong.
  ASSERT_TRUE(rig.run_until([&] { return !c4.link_up(); }, 100ms));
  ControllerStatus s = c4.status();
  EXPECT_TRUE(all_tags(s, Q::uncertain, "stale: conveyor4 does not answer: timeout"))
      << s.tags.front().reason;
  std::string why;
  EXPECT_FALSE(c4.estimate(rig.transport(id, "conveyor4", "conveyor4/denso"), &why));
  EXPECT_NE(why.find("conveyor4 does not answer"), std::string::npos) << why;

  // Once the last answer is stale_after old: Bad, and production held with the reason.
  ASSERT_TRUE(rig.run_until([&] { return c4.status().packml.state == S::Held; }, 3s));
  s = c4.status();
  EXPECT_TRUE(all_tags(s, Q::bad, "conveyor4 does not answer: timeout")) << s.tags.front().reason;
  EXPECT_EQ(s.packml.stop_reason->id, kStopPlcUnreachable);
  EXPECT_NE(s.fault.find("does not answer"), std::string::npos) << s.fault;
  EXPECT_EQ(s.job, "t1");  // the job in work waits for the device
  EXPECT_FALSE(c4.submit("t2", rig.transport(id, "conveyor4", "conveyor4/denso")));
  rig.run_for(5s);
  EXPECT_FALSE(rig.ended("t1"));

  // The PLC kept its belt running: the box arrived meanwhile, and the gateway sees it when the
  // device answers again; the hold of its own making is lifted.
  rig.clear("plc-unreachable:conveyor4");
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("t1"); }, 1s));
  EXPECT_TRUE(rig.outcome("t1").ok) << rig.outcome("t1").detail;
  ASSERT_TRUE(rig.run_until([&] { return c4.status().packml.state == S::Execute; }, 1s));
  s = c4.status();
  EXPECT_TRUE(all_tags(s, Q::good, ""));
  EXPECT_EQ(s.fault, "");
  EXPECT_EQ(std::get<std::int64_t>(tag(s, "plc.station_box.download").value), id);
  EXPECT_TRUE(c4.estimate(rig.transport(id, "conveyor4", "conveyor4/denso"), &why)) << why;
}

TEST(GatewayLink, ModbusExceptionsAreReportedAndSurvived) {
  GatewayRig rig;
  Gateway& up = rig.add("uploader", "uploader");
  rig.run_for(100ms);
  ASSERT_EQ(up.status().packml.state, S::Execute);
  rig.inject("plc-exception:uploader:6");
  ASSERT_TRUE(rig.run_until([&] { return up.status().packml.state == S::Held; }, 3s));
  const ControllerStatus s = up.status();
  EXPECT_TRUE(all_tags(s, Q::bad,
                       "uploader answers with a Modbus exception: remote error: server_device_busy (0x06)"))
      << s.tags.front().reason;
  EXPECT_EQ(s.packml.stop_reason->id, kStopPlcException);
  std::string why;
  EXPECT_FALSE(up.estimate({"upload", {{"box_type", 0}}}, &why));
  EXPECT_NE(why.find("server_device_busy"), std::string::npos) << why;

  rig.clear("plc-exception:uploader:6");
  ASSERT_TRUE(rig.run_until([&] { return up.status().packml.state == S::Execute; }, 1s));
  const JobOutcome o = rig.run_job(up, "u1", {"upload", {{"box_type", 0}}});
  EXPECT_TRUE(o.ok) << o.detail;
}

TEST(GatewayLink, AnOperatorStopsAGatewayWhoseDeviceIsGone) {
  GatewayRig rig;
  Gateway& up = rig.add("uploader", "uploader");
  rig.run_for(100ms);
  ASSERT_TRUE(up.submit("u1", {"upload", {{"box_type", 0}}}));
  rig.run_for(100ms);
  rig.inject("plc-unreachable:uploader");
  ASSERT_TRUE(rig.run_until([&] { return up.status().packml.state == S::Held; }, 3s));
  ASSERT_TRUE(up.command(PackMLCommand::Stop));
  ASSERT_TRUE(rig.run_until([&] { return up.status().packml.state == S::Stopped; }, 2s));
  ASSERT_TRUE(rig.ended("u1"));
  EXPECT_FALSE(rig.outcome("u1").ok);
  EXPECT_EQ(rig.outcome("u1").detail, "uploader stopped");
  // Back, it stays Stopped: the operator's Stop outranks the hold of the link.
  rig.clear("plc-unreachable:uploader");
  rig.run_for(1s);
  EXPECT_EQ(up.status().packml.state, S::Stopped);
  EXPECT_EQ(up.status().packml.stop_reason->message, "operator: Stop");
}

TEST(GatewayFaults, AnEmptyDispenserFailsTheJobAndStopsTheBidsForThatCandyUntilReset) {
  GatewayRig rig;
  auto [toshiba, id] = rig.add_with_box("toshiba", "legacy-robot", "conveyor3/toshiba");
  rig.inject("dispenser-empty:toshiba-toffee");
  const Operation toffee{"load", {{"candy", rig.candy("toffee")}, {"count", 2}, {"box", id}, {"slot", 0}}};
  const JobOutcome o = rig.run_job(toshiba, "l1", toffee);
  EXPECT_FALSE(o.ok);
  EXPECT_EQ(o.detail, "toshiba: slot 0: dispenser empty (PLC fault 2) after 0 of 2 toffee");
  EXPECT_EQ(o.results.at("placed"), 0);

  std::string why;
  EXPECT_FALSE(toshiba.estimate(toffee, &why));
  EXPECT_EQ(why, "toshiba's toffee dispenser ran empty; an operator's Reset clears it");
  const Operation gummy{"load", {{"candy", rig.candy("gummy")}, {"count", 1}, {"box", id}, {"slot", 0}}};
  EXPECT_TRUE(toshiba.estimate(gummy, &why)) << why;  // the other dispenser still serves
  EXPECT_EQ(toshiba.status().packml.state, S::Execute);
  EXPECT_EQ(toshiba.status().packml.defective, 1U);

  // Refilled, it still does not bid (it cannot see the stock) until an operator resets it.
  rig.clear("dispenser-empty:toshiba-toffee");
  rig.run_for(3s);
  EXPECT_FALSE(toshiba.estimate(toffee));
  for (auto c : {PackMLCommand::Stop, PackMLCommand::Reset, PackMLCommand::Start}) {
    ASSERT_TRUE(toshiba.command(c)) << to_string(c);
    rig.run_for(100ms);
  }
  ASSERT_EQ(toshiba.status().packml.state, S::Execute);
  EXPECT_TRUE(toshiba.estimate(toffee, &why)) << why;
  const JobOutcome again = rig.run_job(toshiba, "l2", toffee);
  EXPECT_TRUE(again.ok) << again.detail;
}

TEST(GatewayFaults, AJamFailsTheTransportAndAbortsWithTheStopReason) {
  GatewayRig rig;
  auto [c4, id] = rig.add_with_box("conveyor4", "conveyor", "conveyor4/denso");
  ASSERT_TRUE(c4.submit("t1", rig.transport(id, "conveyor4/denso", "conveyor4/download")));
  ASSERT_TRUE(c4.submit("t2", rig.transport(id, "conveyor4/download", "conveyor5")));
  rig.run_for(1s);
  rig.inject("jam:conveyor4");
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("t1") && rig.ended("t2"); }, 1s));
  EXPECT_FALSE(rig.outcome("t1").ok);
  EXPECT_EQ(
      rig.outcome("t1").detail,
      fmt::format("conveyor4: box {} from conveyor4/denso to conveyor4/download aborted (conveyor4: jam (PLC "
                  "fault 1))",
                  id));
  EXPECT_EQ(rig.outcome("t2").detail, "aborted (conveyor4: jam (PLC fault 1)) before it started");
  rig.run_for(100ms);
  ControllerStatus s = c4.status();
  EXPECT_EQ(s.packml.state, S::Aborted);
  EXPECT_EQ(s.packml.stop_reason->id, static_cast<std::int32_t>(line::FaultCode::jam));
  EXPECT_EQ(s.fault, "jam (PLC fault 1)");
  EXPECT_TRUE(std::get<bool>(tag(s, "plc.jam").value));
  EXPECT_FALSE(c4.estimate(rig.transport(id, "conveyor4/denso", "conveyor4/download")));

  // The jam cleared: Clear, Reset (the latched fault reset), Start, and the transport goes.
  rig.clear("jam:conveyor4");
  for (auto c : {PackMLCommand::Clear, PackMLCommand::Reset, PackMLCommand::Start}) {
    ASSERT_TRUE(c4.command(c)) << to_string(c);
    rig.run_for(100ms);
  }
  s = c4.status();
  ASSERT_EQ(s.packml.state, S::Execute);
  EXPECT_EQ(s.fault, "");
  EXPECT_FALSE(std::get<bool>(tag(s, "plc.fault").value));
  const JobOutcome o = rig.run_job(c4, "t3", rig.transport(id, "conveyor4", "conveyor4/download"));
  EXPECT_TRUE(o.ok) << o.detail;
}

TEST(GatewayFaults, ResettingWaitsWhileTheJamStays) {
  GatewayRig rig;
  Gateway& c2 = rig.add("conveyor2", "conveyor");
  rig.run_for(100ms);
  rig.inject("jam:conveyor2");
  ASSERT_TRUE(rig.run_until([&] { return c2.status().packml.state == S::Aborted; }, 100ms));
  ASSERT_TRUE(c2.command(PackMLCommand::Clear));
  rig.run_for(100ms);
  ASSERT_TRUE(c2.command(PackMLCommand::Reset));
  rig.run_for(1s);
  EXPECT_EQ(c2.status().packml.state, S::Resetting);
  rig.clear("jam:conveyor2");
  EXPECT_TRUE(rig.run_until([&] { return c2.status().packml.state == S::Idle; }, 200ms));
}

TEST(GatewayFaults, ABoxThatNeverArrivesTimesTheTransportOut) {
  GatewayRig rig;
  auto [c4, id] =
      rig.add_with_box("conveyor4", "conveyor", "conveyor4/denso", "start: execute\njob_timeout_s: 2\n");
  ASSERT_TRUE(c4.submit("t1", rig.transport(id, "conveyor4/denso", "conveyor4/download")));
  rig.run_for(1s);
  rig.inject(fmt::format("box-drop:{}", id));
  ASSERT_TRUE(rig.run_until([&] { return rig.ended("t1"); }, 10s));
  EXPECT_FALSE(rig.outcome("t1").ok);
  EXPECT_NE(rig.outcome("t1").detail.find("timed out (2.0 s over its estimate)"), std::string::npos)
      << rig.outcome("t1").detail;
  rig.run_for(100ms);
  EXPECT_FALSE(std::get<bool>(tag(c4.status(), "plc.running").value));
  EXPECT_EQ(c4.status().packml.state, S::Execute);  // the machine itself is fine
}

}  // namespace
}  // namespace sf::factory::testing
