// Modbus TCP round trip (read 10 holding registers; write 1 register) of our Server with a
// Device whose hooks do a PLC's small amount of work per request (refresh the inputs from a belt
// model before each request, take a new set-point after each write), next to a bare libmodbus
// server over a modbus_mapping_t with no hooks (modbus_bench.hpp), with the same client, in the
// same run. Ratio = our p50 / libmodbus p50 (goal <= 1.2x).
//
// Usage: bench_modbus [REQUESTS]   (default 20000 per server and request kind)
#include <cstdio>
#include <cstdlib>

#include "modbus_bench.hpp"

namespace {

using namespace sf::modbus;

// A conveyor-like device: holding register 0 is the speed set-point, coil 0 runs the motor;
// input registers 0-1 report the belt position (32 bits), discrete inputs 0-3 four photo-eyes.
class BeltDevice final : public Device {
 public:
  BeltDevice()
      : bank_(RegisterBank::create(BankLayout{.coils = {0, 16},
                                              .discrete_inputs = {0, 16},
                                              .holding_registers = {0, 100},
                                              .input_registers = {0, 16}})
                  .value()) {}
  RegisterBank& bank() override { return bank_; }

  std::optional<ExceptionCode> before_request(const Request& /*request*/) override {
    if (bank_.coil(0)) {
      position_ += speed_;
    }
    bank_.set_input_register(0, static_cast<std::uint16_t>(position_ >> 16U));
    bank_.set_input_register(1, static_cast<std::uint16_t>(position_ & 0xFFFFU));
    for (std::uint16_t eye = 0; eye < 4; ++eye) {
      bank_.set_discrete_input(eye, (position_ / 1000U) % 4U == eye);
    }
    return std::nullopt;
  }

  void after_write(const Request& request) override {
    if (request.write->table == Table::holding_registers && request.write->address == 0) {
      speed_ = bank_.holding_register(0);
    }
  }

 private:
  RegisterBank bank_;
  std::uint32_t position_ = 0;
  std::uint32_t speed_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  modbus_bench::Options options;
  if (argc > 1) {
    options.requests = std::strtoul(argv[1], nullptr, 10);
  }
  BeltDevice device;
  std::uint16_t speed = 0;
  const std::vector<modbus_bench::Operation> operations{
      {"read 10 holding registers", [](Client& c) { return c.read_holding_registers(0, 10).ok(); }},
      {"write 1 register", [&speed](Client& c) { return c.write_single_register(0, ++speed).ok(); }},
  };
  std::printf("Modbus TCP round trip on loopback, one client, %zu requests per server and kind\n",
              options.requests);
  const auto rows = modbus_bench::compare(device, operations, options);
  if (rows.empty()) {
    return 1;
  }
  modbus_bench::print(rows);
  return 0;
}
