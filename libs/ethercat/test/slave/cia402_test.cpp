// CiA 402 drive state machine and CSP position following, both on the axis
// model directly and end to end through process data.
#include <gtest/gtest.h>

#include <algorithm>

#include "sf/ethercat/slave/cia402.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

class AxisTest : public ::testing::Test {
 protected:
  AxisTest() : axis(od, 0) {}
  void command(std::uint16_t cw) {
    od.find(0x6040, 0)->set<std::uint16_t>(cw);
    axis.apply_controlword();
    axis.step(0.001);
  }
  std::uint16_t sw() const { return od.find(0x6041, 0)->get<std::uint16_t>(); }
  void enable() {
    command(0x0006);
    command(0x0007);
    command(0x000F);
  }
  ObjectDictionary od;
  Cia402Axis axis;
};

TEST_F(AxisTest, PowerUpToOperationEnabledAndBack) {
  EXPECT_EQ(axis.state(), Cia402State::SwitchOnDisabled);
  EXPECT_EQ(sw() & 0x4F, 0x40);
  command(0x0006);  // shutdown
  EXPECT_EQ(axis.state(), Cia402State::ReadyToSwitchOn);
  EXPECT_EQ(sw() & 0x6F, 0x21);
  command(0x0007);  // switch on
  EXPECT_EQ(axis.state(), Cia402State::SwitchedOn);
  EXPECT_EQ(sw() & 0x6F, 0x23);
  command(0x000F);  // enable operation
  EXPECT_EQ(axis.state(), Cia402State::OperationEnabled);
  EXPECT_EQ(sw() & 0x6F, 0x27);
  command(0x0007);  // disable operation
  EXPECT_EQ(axis.state(), Cia402State::SwitchedOn);
  command(0x0000);  // disable voltage
  EXPECT_EQ(axis.state(), Cia402State::SwitchOnDisabled);
  // Switch on straight from Switch on disabled is not a transition.
  command(0x000F);
  EXPECT_EQ(axis.state(), Cia402State::SwitchOnDisabled);
}

TEST_F(AxisTest, QuickStopDeceleratesThenDisables) {
  enable();
  // Ramp up (1e7 counts/s², within the limit) to 100 counts per ms.
  std::int32_t target = 0;
  for (int i = 1; i <= 30; ++i) {
    target += 10 * std::min(i, 10);
    od.find(0x607A, 0)->set<std::int32_t>(target);
    axis.step(0.001);
  }
  EXPECT_NEAR(axis.velocity(), 100'000.0, 1.0);
  command(0x0002);  // quick stop
  EXPECT_EQ(axis.state(), Cia402State::QuickStopActive);
  EXPECT_EQ(sw() & 0x6F, 0x07);
  for (int i = 0; i < 10 && axis.state() == Cia402State::QuickStopActive; ++i) {
    axis.step(0.001);
  }
  EXPECT_EQ(axis.velocity(), 0.0);
  EXPECT_EQ(axis.state(), Cia402State::SwitchOnDisabled);
}

TEST_F(AxisTest, FollowsASmoothTargetExactly) {
  enable();
  double target = 0;
  double v = 0;
  for (int i = 0; i < 200; ++i) {  // accelerate at 5e6 counts/s², within the 2e7 limit
    v += 5e6 * 0.001;
    target += v * 0.001;
    od.find(0x607A, 0)->set<std::int32_t>(static_cast<std::int32_t>(target));
    axis.step(0.001);
  }
  EXPECT_NEAR(axis.position(), static_cast<std::int32_t>(target), 0.5);
  EXPECT_EQ(od.find(0x6064, 0)->get<std::int32_t>(), static_cast<std::int32_t>(target));
  EXPECT_NEAR(od.find(0x606C, 0)->get<std::int32_t>(), 1'000'000, 1'000);
  EXPECT_EQ(sw() & 0x2000, 0);  // no following error
  EXPECT_NE(sw() & 0x1000, 0);  // follows the command value
}

TEST_F(AxisTest, VelocityLimitCausesFollowingErrorFaultAndResetClearsIt) {
  enable();
  // Demand 2e6 counts/s against a 1e6 limit: the error grows past 10000
  // counts and stays there longer than 10 ms.
  double target = 0;
  for (int i = 0; i < 100 && axis.state() == Cia402State::OperationEnabled; ++i) {
    target += 2000;
    od.find(0x607A, 0)->set<std::int32_t>(static_cast<std::int32_t>(target));
    axis.step(0.001);
    if (i == 5) {
      EXPECT_NE(sw() & 0x0800, 0);  // internal limit active
    }
  }
  EXPECT_EQ(axis.state(), Cia402State::FaultReactionActive);
  EXPECT_EQ(axis.error_code(), kErrorFollowing);
  for (int i = 0; i < 100 && axis.state() != Cia402State::Fault; ++i) {
    axis.step(0.001);
  }
  EXPECT_EQ(axis.state(), Cia402State::Fault);
  EXPECT_EQ(sw() & 0x4F, 0x08);
  EXPECT_NE(sw() & 0x2000, 0);
  command(0x0000);
  command(0x0080);  // rising edge of fault reset
  EXPECT_EQ(axis.state(), Cia402State::SwitchOnDisabled);
  EXPECT_EQ(axis.error_code(), 0);
}

TEST_F(AxisTest, ModeOfOperationAcceptsOnlyCsp) {
  EXPECT_EQ(od.download(0x6060, 0, false, Bytes{8}, AlState::PreOp), 0u);
  EXPECT_NE(od.download(0x6060, 0, false, Bytes{1}, AlState::PreOp), 0u);
  EXPECT_EQ(od.find(0x6061, 0)->get<std::int8_t>(), 8);
}

TEST(Cia402EndToEnd, SmartControllerAxesFollowTargetsOverProcessData) {
  Harness h("smart-controller:1");
  h.assign_stations();
  h.configure_mailbox(0);
  const std::size_t size = h.configure_process_data(0, 0);
  const std::size_t out_bytes = 8 * 6 + 4;
  ASSERT_EQ(size, out_bytes + 8 * 10 + 4);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  ASSERT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  Bytes image(size, 0);
  auto cycle = [&](std::uint16_t cw, std::int32_t target_step, int n) {
    Datagram d;
    for (int c = 0; c < n; ++c) {
      for (std::size_t a = 0; a < 8; ++a) {
        store_le<std::uint16_t>(&image[6 * a], cw);
        const auto t = load_le<std::int32_t>(&image[6 * a + 2]);
        store_le<std::int32_t>(&image[6 * a + 2], t + target_step * static_cast<std::int32_t>(a + 1));
      }
      store_le<std::uint32_t>(&image[48], 0xF0F0A5A5);
      h.clock.advance(std::chrono::milliseconds{1});
      d = h.run(Harness::make(Command::LRW, 0, image));
      EXPECT_EQ(d.wkc, 3);
    }
    return d;
  };
  cycle(0x0000, 0, 1);
  ASSERT_EQ(h.request(0, AlState::Op), AlStatus::of(AlState::Op));
  cycle(0x0006, 0, 2);
  cycle(0x0007, 0, 2);
  auto d = cycle(0x000F, 0, 2);
  for (std::size_t a = 0; a < 8; ++a) {
    EXPECT_EQ(load_le<std::uint16_t>(&d.data[out_bytes + 10 * a]) & 0x6F, 0x27) << a;
  }
  d = cycle(0x000F, 10, 100);
  auto* sc = h.segment->device<SmartController>(0);
  ASSERT_NE(sc, nullptr);
  sc->set_digital_inputs(0x12345678);
  d = cycle(0x000F, 10, 1);
  for (std::size_t a = 0; a < 8; ++a) {
    const auto target = load_le<std::int32_t>(&image[6 * a + 2]);
    EXPECT_EQ(target, 101 * 10 * static_cast<std::int32_t>(a + 1));
    // The actual position lags the target written in the same frame by one cycle.
    const auto actual = load_le<std::int32_t>(&d.data[out_bytes + 10 * a + 2]);
    EXPECT_EQ(actual, target - 10 * static_cast<std::int32_t>(a + 1)) << a;
    EXPECT_EQ(load_le<std::int32_t>(&d.data[out_bytes + 10 * a + 6]),
              10'000 * static_cast<std::int32_t>(a + 1))
        << a;
  }
  EXPECT_EQ(load_le<std::uint32_t>(&d.data[out_bytes + 80]), 0x12345678u);
  EXPECT_EQ(sc->digital_outputs(), 0xF0F0A5A5u);
  // Leaving OP: outputs go safe and enabled axes react to the lost communication.
  ASSERT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  EXPECT_EQ(sc->digital_outputs(), 0u);
  EXPECT_EQ(sc->axis(3).error_code(), kErrorCommunication);
}

}  // namespace
}  // namespace sf::ethercat::slave
