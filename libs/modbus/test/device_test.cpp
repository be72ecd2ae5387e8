#include "sf/modbus/device.hpp"

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::modbus::test {
namespace {

TEST(Device, StartsWithoutAFault) {
  BankDevice device(make_bank());
  EXPECT_EQ(device.fault(), Fault{});
}

TEST(Device, KeepsEveryFaultItIsGiven) {
  BankDevice device(make_bank());
  device.set_fault(Fault::unreachable());
  EXPECT_EQ(device.fault().kind, Fault::Kind::unreachable);
  for (auto code : {ExceptionCode::illegal_function, ExceptionCode::server_device_busy,
                    ExceptionCode::gateway_target_failed_to_respond}) {
    device.set_fault(Fault::answer(code));
    EXPECT_EQ(device.fault(), Fault::answer(code));
  }
  device.set_fault(Fault{});
  EXPECT_EQ(device.fault(), Fault{});
}

}  // namespace
}  // namespace sf::modbus::test
