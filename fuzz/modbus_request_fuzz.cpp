// Fuzzes the Modbus TCP server's request path with arbitrary bytes on a connection: MBAP framing
// (MB TCP §3.1.3), PDU decoding (MB AP §6), the device path with its hooks, and libmodbus's
// modbus_reply / modbus_reply_exception writing the answers. The bytes arrive on one end of a
// socketpair the server adopted, in two writes (partial frames are buffered across reads); the
// harness then closes its sending side. The server must answer or close, never crash or hang, and
// everything it sends must be well-formed Modbus TCP responses.
//
// The first byte picks the device's fault (none, unreachable, an exception for every request) and
// whether its before_request hook refuses writes; the second, where the input is split.
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sf/core/log.hpp"
#include "sf/modbus/server.hpp"

namespace {

using namespace sf::modbus;

// A device whose hooks read every value a request carries (so ASan checks Request::data) and
// that refuses writes when told to.
class FuzzDevice final : public Device {
 public:
  FuzzDevice()
      : bank_(RegisterBank::create(BankLayout{.coils = {0, 64},
                                              .discrete_inputs = {0xFFF0, 0x10},
                                              .holding_registers = {100, 125},
                                              .input_registers = {0, 8}})
                  .value()) {}
  RegisterBank& bank() override { return bank_; }
  std::optional<ExceptionCode> before_request(const Request& request) override {
    if (request.writes() && refuse_writes) {
      return ExceptionCode::server_device_busy;
    }
    bank_.set_input_register(0, static_cast<std::uint16_t>(bank_.input_register(0) + 1));
    return std::nullopt;
  }
  void after_write(const Request& request) override {
    std::uint32_t sum = 0;
    for (std::size_t i = 0; i < request.write->count; ++i) {
      sum += request.write->table == Table::coils ? (request.coil_value(i) ? 1U : 0U)
                                                  : request.register_value(i);
    }
    bank_.set_input_register(1, static_cast<std::uint16_t>(sum));
  }
  bool refuse_writes = false;

 private:
  RegisterBank bank_;
};

struct Harness {
  FuzzDevice device;
  std::unique_ptr<Server> server = Server::listen(device, ServerOptions{}).value();
};

Harness& harness() {
  static Harness h;
  return h;
}

Fault fault_for(std::uint8_t mode) {
  static constexpr ExceptionCode kCodes[] = {
      ExceptionCode::illegal_function, ExceptionCode::server_device_failure,
      ExceptionCode::server_device_busy, ExceptionCode::gateway_target_failed_to_respond};
  switch (mode & 3U) {
    case 1:
      return Fault::unreachable();
    case 2:
      return Fault::answer(kCodes[(mode >> 2U) & 3U]);
    default:
      return Fault{};
  }
}

void drain(int fd, std::vector<std::uint8_t>& out) {
  std::uint8_t buffer[4096];
  for (;;) {
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n <= 0) {
      return;
    }
    out.insert(out.end(), buffer, buffer + n);
  }
}

// Every byte the server sent belongs to a response: MBAP protocol id 0, a length that covers the
// unit id, a function code and at least one byte more (an exception code or data).
void check_responses(const std::vector<std::uint8_t>& bytes) {
  std::size_t at = 0;
  while (at < bytes.size()) {
    if (bytes.size() - at < 9) {
      __builtin_trap();
    }
    const unsigned protocol = (static_cast<unsigned>(bytes[at + 2]) << 8U) | bytes[at + 3];
    const std::size_t length = (static_cast<std::size_t>(bytes[at + 4]) << 8U) | bytes[at + 5];
    if (protocol != 0 || length < 3 || length > kMaxPduLength + 1 || bytes.size() - at < 6 + length) {
      __builtin_trap();
    }
    at += 6 + length;
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)sf::log::set_level("off");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  Harness& h = harness();
  h.device.set_fault(fault_for(data[0]));
  h.device.refuse_writes = (data[0] & 0x10U) != 0;
  const std::uint8_t* input = data + 2;
  const std::size_t length = size - 2;
  const std::size_t split = length == 0 ? 0 : data[1] % (length + 1);

  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    return 0;
  }
  const int sender = fds[1];
  if (!h.server->adopt(fds[0]).ok()) {
    __builtin_trap();
  }
  std::vector<std::uint8_t> responses;
  (void)::send(sender, input, split, MSG_NOSIGNAL);
  (void)h.server->poll_once(std::chrono::milliseconds{0});
  drain(sender, responses);
  (void)::send(sender, input + split, length - split, MSG_NOSIGNAL);
  ::shutdown(sender, SHUT_WR);
  // Each step reads at least one byte or the end of the stream, so this bound is never reached
  // by a server that makes progress.
  for (std::size_t step = 0; h.server->counters().clients > 0; ++step) {
    if (step > length + 16) {
      __builtin_trap();
    }
    (void)h.server->poll_once(std::chrono::milliseconds{0});
    drain(sender, responses);
  }
  drain(sender, responses);
  ::close(sender);
  check_responses(responses);
  return 0;
}
