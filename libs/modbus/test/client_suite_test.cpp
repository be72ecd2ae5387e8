// The client suite: every behavioural case runs against a TcpClient talking to a Server over
// loopback and against a MemoryClient calling the device directly, so the two cannot drift.
#include <thread>

#include <gtest/gtest.h>

#include "sf/core/clock.hpp"
#include "sf/modbus/memory_client.hpp"
#include "sf/modbus/server.hpp"
#include "sf/modbus/tcp_client.hpp"
#include "test_support.hpp"

namespace sf::modbus::test {
namespace {

using namespace std::chrono_literals;

enum class Kind { tcp, memory };

constexpr auto kResponseTimeout = 200ms;

class ClientSuite : public ::testing::TestWithParam<Kind> {
 protected:
  void SetUp() override {
    if (GetParam() == Kind::tcp) {
      auto server = Server::listen(device_, ServerOptions{});
      ASSERT_TRUE(server.ok()) << server.error().describe();
      server_ = std::move(*server);
      ASSERT_TRUE(server_->start().ok());
    }
    client_ = make_client(kTcpUnitId);
  }

  std::unique_ptr<Client> make_client(std::uint8_t unit_id) {
    if (GetParam() == Kind::memory) {
      return std::make_unique<MemoryClient>(
          device_,
          MemoryClientOptions{.unit_id = unit_id, .clock = &clock_, .response_timeout = kResponseTimeout});
    }
    auto client = TcpClient::create(
        TcpClientOptions{.port = server_->port(), .unit_id = unit_id, .response_timeout = kResponseTimeout});
    EXPECT_TRUE(client.ok());
    return std::move(*client);
  }

  // The server's thread may be serving: touch the device under its lock (device.hpp).
  template <typename F>
  auto locked(F f) {
    const std::lock_guard lock(device_.mutex());
    return f(device_);
  }

  RecordingDevice device_;
  ManualClock clock_;
  std::unique_ptr<Server> server_;
  std::unique_ptr<Client> client_;
};

void expect_exception(const ClientError& error, ExceptionCode code) {
  EXPECT_EQ(error.code, Errc::remote) << error.describe();
  ASSERT_TRUE(error.exception.has_value()) << error.describe();
  EXPECT_EQ(*error.exception, code) << error.describe();
}

TEST_P(ClientSuite, ReadsEachTable) {
  locked([](RecordingDevice& d) {
    d.bank().set_coil(5, true);
    d.bank().set_coil(7, true);
    d.bank().set_discrete_input(115, true);
    d.bank().set_holding_register(1010, 0xCAFE);
    d.bank().set_input_register(2000, 17);
    return 0;
  });

  auto coils = client_->read_coils(4, 4);
  ASSERT_TRUE(coils.ok()) << coils.error().describe();
  EXPECT_EQ(*coils, (std::vector<bool>{false, true, false, true}));
  auto inputs = client_->read_discrete_inputs(114, 2);
  ASSERT_TRUE(inputs.ok()) << inputs.error().describe();
  EXPECT_EQ(*inputs, (std::vector<bool>{false, true}));
  auto holding = client_->read_holding_registers(1009, 3);
  ASSERT_TRUE(holding.ok()) << holding.error().describe();
  EXPECT_EQ(*holding, (std::vector<std::uint16_t>{0, 0xCAFE, 0}));
  auto input_regs = client_->read_input_registers(2000, 1);
  ASSERT_TRUE(input_regs.ok()) << input_regs.error().describe();
  EXPECT_EQ(*input_regs, (std::vector<std::uint16_t>{17}));
}

TEST_P(ClientSuite, ReadsWholeTablesAtTheirLimits) {
  auto coils = client_->read_coils(0, 32);
  ASSERT_TRUE(coils.ok()) << coils.error().describe();
  EXPECT_EQ(coils->size(), 32U);
  auto registers = client_->read_holding_registers(1000, 100);
  ASSERT_TRUE(registers.ok()) << registers.error().describe();
  EXPECT_EQ(registers->size(), 100U);
}

TEST_P(ClientSuite, WritesCoilsAndRegisters) {
  ASSERT_TRUE(client_->write_single_coil(31, true).ok());
  ASSERT_TRUE(
      client_->write_multiple_coils(0, {true, true, false, true, false, false, false, false, true}).ok());
  ASSERT_TRUE(client_->write_single_register(1099, 65535).ok());
  const std::vector<std::uint16_t> values{1, 2, 3, 4};
  ASSERT_TRUE(client_->write_multiple_registers(1000, values).ok());

  locked([&](RecordingDevice& d) {
    EXPECT_TRUE(d.bank().coil(31));
    EXPECT_EQ(d.bank().bits(Table::coils, 0, 9),
              (std::vector<bool>{true, true, false, true, false, false, false, false, true}));
    EXPECT_EQ(d.bank().holding_register(1099), 65535);
    EXPECT_EQ(d.bank().words(Table::holding_registers, 1000, 4), values);
    return 0;
  });
  auto back = client_->read_coils(0, 9);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(*back, (std::vector<bool>{true, true, false, true, false, false, false, false, true}));
}

TEST_P(ClientSuite, AddressesOutsideATableAreIllegalDataAddress) {
  expect_exception(client_->read_holding_registers(999, 1).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->read_holding_registers(1095, 6).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->read_coils(32, 1).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->read_discrete_inputs(0, 1).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->read_input_registers(2019, 2).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->write_single_coil(40, true).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->write_single_register(0, 1).error(), ExceptionCode::illegal_data_address);
  const std::vector<std::uint16_t> two{1, 2};
  expect_exception(client_->write_multiple_registers(1099, two).error(), ExceptionCode::illegal_data_address);
  expect_exception(client_->write_multiple_coils(31, {true, true}).error(),
                   ExceptionCode::illegal_data_address);
  expect_exception(client_->read_holding_registers(0xFFFF, 1).error(), ExceptionCode::illegal_data_address);
}

TEST_P(ClientSuite, QuantitiesOutsideTheLimitsAreRefusedBeforeSending) {
  EXPECT_EQ(client_->read_holding_registers(1000, 0).error().code, Errc::invalid_argument);
  EXPECT_EQ(client_->read_holding_registers(1000, kMaxReadRegisters + 1).error().code,
            Errc::invalid_argument);
  EXPECT_EQ(client_->read_input_registers(2000, kMaxReadRegisters + 1).error().code, Errc::invalid_argument);
  EXPECT_EQ(client_->read_coils(0, kMaxReadBits + 1).error().code, Errc::invalid_argument);
  EXPECT_EQ(client_->read_discrete_inputs(100, 0).error().code, Errc::invalid_argument);
  EXPECT_EQ(client_->write_multiple_coils(0, {}).error().code, Errc::invalid_argument);
  EXPECT_EQ(client_->write_multiple_coils(0, std::vector<bool>(kMaxWriteBits + 1)).error().code,
            Errc::invalid_argument);
  const std::vector<std::uint16_t> many(kMaxWriteRegisters + 1);
  EXPECT_EQ(client_->write_multiple_registers(1000, many).error().code, Errc::invalid_argument);
  locked([](RecordingDevice& d) {
    EXPECT_TRUE(d.before.empty());
    return 0;
  });
}

TEST_P(ClientSuite, HooksSeeEachRequest) {
  auto client = make_client(7);
  ASSERT_TRUE(client->read_holding_registers(1000, 10).ok());
  const std::vector<std::uint16_t> values{11, 12};
  ASSERT_TRUE(client->write_multiple_registers(1020, values).ok());
  ASSERT_TRUE(client->write_single_coil(3, true).ok());

  locked([&](RecordingDevice& d) {
    EXPECT_EQ(d.before.size(), 3U);
    EXPECT_EQ(d.after.size(), 2U);
    if (d.before.size() != 3U || d.after.size() != 2U) {
      return 0;
    }
    EXPECT_EQ(d.before[0].function, FunctionCode::read_holding_registers);
    EXPECT_EQ(d.before[0].unit_id, 7);
    EXPECT_EQ(d.before[0].read, (Range{Table::holding_registers, 1000, 10}));
    EXPECT_FALSE(d.before[0].writes());
    EXPECT_EQ(d.before[1].write, (Range{Table::holding_registers, 1020, 2}));
    EXPECT_EQ(d.after[0].function, FunctionCode::write_multiple_registers);
    EXPECT_EQ(d.after[1].function, FunctionCode::write_single_coil);
    EXPECT_EQ(d.after[1].write, (Range{Table::coils, 3, 1}));
    EXPECT_EQ(d.written_values, (std::vector<std::uint16_t>{1}));
    return 0;
  });
}

TEST_P(ClientSuite, AfterWriteSeesTheValuesWritten) {
  const std::vector<std::uint16_t> values{0x0102, 0xFFFE, 7};
  ASSERT_TRUE(client_->write_multiple_registers(1050, values).ok());
  locked([&](RecordingDevice& d) {
    EXPECT_EQ(d.written_values, (std::vector<std::uint16_t>{0x0102, 0xFFFE, 7}));
    return 0;
  });
  ASSERT_TRUE(client_->write_multiple_coils(8, {false, true, true}).ok());
  locked([&](RecordingDevice& d) {
    EXPECT_EQ(d.written_values, (std::vector<std::uint16_t>{0, 1, 1}));
    return 0;
  });
}

TEST_P(ClientSuite, NoHooksForRequestsThatCannotBeServed) {
  EXPECT_FALSE(client_->read_holding_registers(5000, 1).ok());
  EXPECT_FALSE(client_->write_single_register(5000, 1).ok());
  locked([](RecordingDevice& d) {
    EXPECT_TRUE(d.before.empty());
    EXPECT_TRUE(d.after.empty());
    return 0;
  });
}

TEST_P(ClientSuite, HookRefusalIsATypedExceptionAndChangesNothing) {
  locked([](RecordingDevice& d) {
    d.refuse = ExceptionCode::server_device_busy;
    return 0;
  });
  expect_exception(client_->write_single_register(1001, 5).error(), ExceptionCode::server_device_busy);
  expect_exception(client_->read_input_registers(2000, 1).error(), ExceptionCode::server_device_busy);
  locked([](RecordingDevice& d) {
    EXPECT_EQ(d.bank().holding_register(1001), 0);
    EXPECT_EQ(d.before.size(), 2U);
    EXPECT_TRUE(d.after.empty());
    d.refuse.reset();
    return 0;
  });
  EXPECT_TRUE(client_->write_single_register(1001, 5).ok());
}

TEST_P(ClientSuite, ExceptionFaultAnswersEveryRequestUntilCleared) {
  device_.set_fault(Fault::answer(ExceptionCode::gateway_target_failed_to_respond));
  expect_exception(client_->read_holding_registers(1000, 1).error(),
                   ExceptionCode::gateway_target_failed_to_respond);
  expect_exception(client_->write_single_coil(0, true).error(),
                   ExceptionCode::gateway_target_failed_to_respond);
  expect_exception(client_->read_coils(500, 1).error(), ExceptionCode::gateway_target_failed_to_respond);
  locked([](RecordingDevice& d) {
    EXPECT_FALSE(d.bank().coil(0));
    EXPECT_TRUE(d.before.empty());
    return 0;
  });

  device_.set_fault(Fault{});
  EXPECT_TRUE(client_->write_single_coil(0, true).ok());
}

TEST_P(ClientSuite, UnreachableDeviceTimesOutUntilCleared) {
  ASSERT_TRUE(client_->read_coils(0, 1).ok());  // over TCP: connected before the fault
  device_.set_fault(Fault::unreachable());
  auto r = client_->read_coils(0, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::timeout) << r.error().describe();
  EXPECT_FALSE(r.error().exception.has_value());

  device_.set_fault(Fault{});
  auto again = client_->read_coils(0, 1);
  EXPECT_TRUE(again.ok()) << again.error().describe();
}

TEST_P(ClientSuite, ErrorsConvertToSfResults) {
  Result<std::vector<std::uint16_t>> plain = client_->read_holding_registers(1000, 2);
  EXPECT_TRUE(plain.ok());
  Status status = client_->write_single_register(1, 1);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, Errc::remote);
  EXPECT_NE(status.error().message.find("illegal_data_address"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Clients, ClientSuite, ::testing::Values(Kind::tcp, Kind::memory),
                         [](const ::testing::TestParamInfo<Kind>& param) {
                           return param.param == Kind::tcp ? "tcp" : "memory";
                         });

// --- the in-memory client's own guarantees ---------------------------------------------------

TEST(MemoryClient, UnreachableCostsTheResponseTimeoutOnItsClock) {
  RecordingDevice device;
  ManualClock clock;
  MemoryClient client(device, MemoryClientOptions{.clock = &clock, .response_timeout = 350ms});
  device.set_fault(Fault::unreachable());
  const auto before = clock.now();
  EXPECT_EQ(client.read_coils(0, 1).error().code, Errc::timeout);
  EXPECT_EQ(clock.now() - before, 350ms);
}

TEST(MemoryClient, RunsTheHooksUnderTheDeviceLock) {
  class LockProbe final : public Device {
   public:
    RegisterBank& bank() override { return bank_; }
    std::optional<ExceptionCode> before_request(const Request&) override {
      // Probed from another thread: try_lock on a mutex the caller holds is undefined.
      std::thread probe([this] {
        locked_during_hook = !mutex().try_lock();
        if (!locked_during_hook) {
          mutex().unlock();
        }
      });
      probe.join();
      return std::nullopt;
    }
    bool locked_during_hook = false;

   private:
    RegisterBank bank_ = make_bank();
  };
  LockProbe device;
  MemoryClient client(device);
  ASSERT_TRUE(client.read_coils(0, 1).ok());
  EXPECT_TRUE(device.locked_during_hook);
}

}  // namespace
}  // namespace sf::modbus::test
