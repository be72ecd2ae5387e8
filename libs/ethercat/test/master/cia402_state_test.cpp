#include <gtest/gtest.h>

#include "sf/ethercat/master/cia402.hpp"

namespace sf::ethercat::master::cia402 {
namespace {

TEST(Cia402, StatuswordDecoding) {
  // IEC 61800-7-201 Table 3, with unrelated bits set to show they are masked.
  EXPECT_EQ(state_from_statusword(0x0000), State::NotReadyToSwitchOn);
  EXPECT_EQ(state_from_statusword(0x0250), State::SwitchOnDisabled);
  EXPECT_EQ(state_from_statusword(0x0231), State::ReadyToSwitchOn);
  EXPECT_EQ(state_from_statusword(0x0233), State::SwitchedOn);
  EXPECT_EQ(state_from_statusword(0x1237), State::OperationEnabled);
  EXPECT_EQ(state_from_statusword(0x0217), State::QuickStopActive);
  EXPECT_EQ(state_from_statusword(0x021F), State::FaultReactionActive);
  EXPECT_EQ(state_from_statusword(0x0218), State::Fault);
}

TEST(Cia402, ControlwordWalksUpAndDown) {
  EXPECT_EQ(next_controlword(State::SwitchOnDisabled, true), kShutdown);
  EXPECT_EQ(next_controlword(State::ReadyToSwitchOn, true), kSwitchOn);
  EXPECT_EQ(next_controlword(State::SwitchedOn, true), kEnableOperation);
  EXPECT_EQ(next_controlword(State::OperationEnabled, true), kEnableOperation);
  EXPECT_EQ(next_controlword(State::Fault, true), kDisableVoltage);
  EXPECT_EQ(next_controlword(State::OperationEnabled, false), kDisableVoltage);
}

TEST(Cia402, StateNames) {
  EXPECT_EQ(to_string(State::OperationEnabled), "operation enabled");
  EXPECT_EQ(to_string(State::Fault), "fault");
}

}  // namespace
}  // namespace sf::ethercat::master::cia402
