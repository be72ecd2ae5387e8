// Device: the server side of Modbus, the "PLC program" behind a register bank. A Server (over
// TCP) and a MemoryClient (in the same process) answer requests from the device's bank with the
// same checks and call the same hooks around each request:
//
//   1. the device's Fault, if one is set (no answer, or an exception for every request);
//   2. the request's own validity against the bank, exactly as libmodbus's modbus_reply checks it
//      (quantity limits -> illegal_data_value, addresses outside a table -> illegal_data_address);
//   3. before_request(): the device refreshes its inputs from its model, or refuses the request
//      with an exception code (fault injection, a value it does not accept);
//   4. the bank answers (reads) or is changed (writes);
//   5. after_write(), for a write that was applied: the device reacts to the new coils/registers.
//
// Thread contract: steps 1-5 run on the thread that serves the request (the Server's thread, or
// the caller of a MemoryClient) with mutex() held from step 1 to step 5, so another thread that
// takes mutex() sees a request entirely or not at all. The owner takes mutex() whenever it reads
// or changes the bank or the model behind it from any other thread (a plant's physics step).
// Hooks must not take mutex() themselves, nor call a client of the same device.
#pragma once

#include <atomic>
#include <mutex>
#include <optional>
#include <utility>

#include "sf/modbus/protocol.hpp"
#include "sf/modbus/register_bank.hpp"
#include "sf/modbus/request.hpp"

namespace sf::modbus {

// A fault the device shows at its Modbus face (fault injection). Cleared by setting Fault{}.
struct Fault {
  enum class Kind : std::uint8_t {
    none,
    // Requests go unanswered (the client times out) and new connections are closed at once.
    unreachable,
    // Every request is answered with `exception`, whatever it asks.
    exception,
  };
  Kind kind = Kind::none;
  ExceptionCode exception = ExceptionCode::server_device_failure;

  static Fault unreachable() { return Fault{Kind::unreachable, ExceptionCode::server_device_failure}; }
  static Fault answer(ExceptionCode code) { return Fault{Kind::exception, code}; }
  friend bool operator==(const Fault&, const Fault&) = default;
};

class Device {
 public:
  Device() { set_fault(Fault{}); }
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;
  virtual ~Device() = default;

  // The tables this device serves (owned by the device or by its model).
  virtual RegisterBank& bank() = 0;

  // Step 3: a valid request is about to be answered. Return an exception code to answer with it
  // instead (the bank is then neither read nor changed).
  virtual std::optional<ExceptionCode> before_request(const Request& request);
  // Step 5: a write request was applied to the bank (over TCP its response is already sent).
  virtual void after_write(const Request& request);

  // The lock held around steps 1-5 (see the thread contract above).
  [[nodiscard]] std::mutex& mutex() const { return mutex_; }

  // Any thread; takes effect from the next request (and, for unreachable, the next connection).
  void set_fault(Fault fault);
  [[nodiscard]] Fault fault() const;

 private:
  mutable std::mutex mutex_;
  std::atomic<std::uint16_t> fault_{0};  // kind << 8 | exception: one lock-free word
};

// A device that is only its register bank: no model, no hooks (tests, benchmarks, fuzzing).
class BankDevice final : public Device {
 public:
  explicit BankDevice(RegisterBank bank) : bank_(std::move(bank)) {}
  RegisterBank& bank() override { return bank_; }

 private:
  RegisterBank bank_;
};

}  // namespace sf::modbus
