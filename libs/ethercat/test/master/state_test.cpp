// The AL state machine from the master's side, and how refusals are reported.
#include <algorithm>

#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

// A digital IO whose application refuses PREOP → SAFEOP with a chosen AL
// status code, as firmware does for a configuration it does not accept.
class RefusingDevice final : public slave::Device {
 public:
  explicit RefusingDevice(std::uint16_t code)
      : inner_(slave::make_device("digital-io").value()), code_(code) {}
  [[nodiscard]] std::string_view kind() const override { return inner_->kind(); }
  [[nodiscard]] const SiiInfo& sii() const override { return inner_->sii(); }
  [[nodiscard]] slave::ObjectDictionary& objects() override { return inner_->objects(); }
  std::uint16_t check_transition(AlState from, AlState to) override {
    if (refuse && from == AlState::PreOp && to == AlState::SafeOp) {
      return code_;
    }
    return inner_->check_transition(from, to);
  }
  void on_state_change(AlState from, AlState to) override { inner_->on_state_change(from, to); }
  void on_outputs() override { inner_->on_outputs(); }
  void update_inputs() override { inner_->update_inputs(); }
  void tick(Clock::time_point now) override { inner_->tick(now); }
  void apply_safe_outputs() override { inner_->apply_safe_outputs(); }
  void power_on() override { inner_->power_on(); }
  [[nodiscard]] bool outputs_safe() const override { return inner_->outputs_safe(); }

  bool refuse = true;

 private:
  std::unique_ptr<slave::Device> inner_;
  std::uint16_t code_;
};

TEST(State, WalksUpAndDownForTheWholeSegment) {
  Bench b("servo:1,digital-io:2");
  ASSERT_TRUE(b.master->scan().ok());
  for (const auto target : {AlState::PreOp, AlState::SafeOp, AlState::Op, AlState::PreOp, AlState::Init}) {
    auto st = b.master->request_state(target);
    ASSERT_TRUE(st.ok()) << to_string(target) << ": " << st.error().describe();
    for (std::size_t p = 0; p < b.segment->size(); ++p) {
      EXPECT_EQ(b.segment->slave(p).state(), target) << "slave " << p;
      auto s = b.master->read_state(p);
      ASSERT_TRUE(s.ok());
      EXPECT_EQ(s->state(), target);
    }
    EXPECT_EQ(b.master->target_state(), target);
  }
}

TEST(State, OneSlaveAtATime) {
  Bench b("digital-io:3");
  ASSERT_TRUE(b.master->scan().ok());
  ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
  ASSERT_TRUE(b.master->request_state(1, AlState::SafeOp).ok());
  EXPECT_EQ(b.segment->slave(0).state(), AlState::PreOp);
  EXPECT_EQ(b.segment->slave(1).state(), AlState::SafeOp);
  EXPECT_EQ(b.segment->slave(2).state(), AlState::PreOp);
  ASSERT_TRUE(b.master->request_state(1, AlState::Init).ok());
  EXPECT_EQ(b.segment->slave(1).state(), AlState::Init);
}

TEST(State, RefusalReportsSlaveStateAndAlStatusCode) {
  RefusingDevice* refusing = nullptr;
  Bench b([&](slave::Segment& s) {
    s.add(slave::make_device("digital-io").value());
    auto d = std::make_unique<RefusingDevice>(0x001D);  // invalid output configuration
    refusing = d.get();
    s.add(std::move(d));
  });
  ASSERT_TRUE(b.master->scan().ok());
  auto st = b.master->request_state(AlState::Op);
  ASSERT_FALSE(st.ok());
  const auto& msg = st.error().message;
  EXPECT_EQ(st.error().code, Errc::remote);
  EXPECT_NE(msg.find("slave 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("SAFEOP requested"), std::string::npos) << msg;
  EXPECT_NE(msg.find("PREOP + ERROR"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0x001D"), std::string::npos) << msg;
  EXPECT_NE(msg.find("Invalid output configuration"), std::string::npos) << msg;
  EXPECT_EQ(b.master->slave_info(1).al_status_code, 0x001D);

  // Acknowledge, fix the cause, try again.
  ASSERT_TRUE(b.master->acknowledge_error(1).ok());
  auto after = b.master->read_state(1);
  ASSERT_TRUE(after.ok());
  EXPECT_FALSE(after->error);
  refusing->refuse = false;
  auto again = b.master->request_state(AlState::Op);
  ASSERT_TRUE(again.ok()) << again.error().describe();
  EXPECT_EQ(b.segment->slave(1).state(), AlState::Op);
}

TEST(State, RefusedBootstrapNamesTheSlaveAndCode) {
  MasterOptions o = quick_options();
  o.state_timeout = std::chrono::milliseconds{5};
  Bench b("digital-io:1", o);
  ASSERT_TRUE(b.master->scan().ok());
  // INIT → BOOT needs a bootstrap mailbox this device does not have: the
  // ESC refuses, and the master says who and why.
  auto st = b.master->request_state(0, AlState::Bootstrap);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("slave 0"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("BOOT requested"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("0x0013"), std::string::npos) << st.error().message;
}

TEST(State, UnreachableSlaveIsAnErrorNamingItsAddress) {
  MasterOptions o = quick_options();
  o.state_timeout = std::chrono::milliseconds{5};
  Bench b("digital-io:1", o);
  ASSERT_TRUE(b.master->scan().ok());
  b.segment->disconnect(0);  // gone: the state request cannot even be written
  auto st = b.master->request_state(0, AlState::PreOp);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("0x1001"), std::string::npos) << st.error().message;
}

// Swallows every frame that carries process data (an LRW).
class NoProcessDataLink final : public Link {
 public:
  explicit NoProcessDataLink(Link& inner) : inner_(inner) {}
  Status send(ByteSpan frame) override {
    auto f = decode(frame);
    if (f && std::any_of(f->datagrams.begin(), f->datagrams.end(),
                         [](const Datagram& d) { return d.command == Command::LRW; })) {
      return {};
    }
    return inner_.send(frame);
  }
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override {
    return inner_.receive(buf, timeout);
  }
  [[nodiscard]] MacAddress mac() const override { return inner_.mac(); }
  [[nodiscard]] std::string name() const override { return "no-process-data"; }

 private:
  Link& inner_;
};

TEST(State, TimeoutWhenTheSlaveDoesNotFollow) {
  // Without outputs a slave stays in SAFEOP after OP was requested (it
  // would give up only after its own 1 s); the master's 20 ms are up first.
  ManualClock clock;
  auto segment = slave::Segment::create("digital-io:1", clock);
  ASSERT_TRUE(segment.ok());
  slave::SegmentLink inner(**segment);
  NoProcessDataLink link(inner);
  MasterOptions o = quick_options();
  o.state_timeout = std::chrono::milliseconds{20};
  Master master(link, clock, o);
  ASSERT_TRUE(master.scan().ok());
  ASSERT_TRUE(master.request_state(AlState::SafeOp).ok());
  auto st = master.request_state(AlState::Op);
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("timeout after 20 ms"), std::string::npos) << st.error().message;
  EXPECT_NE(st.error().message.find("OP requested, slave is in SAFEOP"), std::string::npos)
      << st.error().message;
  EXPECT_EQ((*segment)->slave(0).state(), AlState::SafeOp);
}

TEST(State, AlStatusCodeText) {
  EXPECT_EQ(describe_al_status_code(0x001B), "0x001B Sync manager watchdog");
  EXPECT_NE(describe_al_status_code(0xBEEF).find("unknown"), std::string::npos);
}

}  // namespace
}  // namespace sf::ethercat::master::test
