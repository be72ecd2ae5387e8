// The plant's PLC request path on arbitrary bytes: Modbus TCP frames into the
// server of each kind of legacy controller (conveyor PLC, uploader PLC,
// legacy robot controller), then a plant step so the controllers' programs
// act on whatever the frames wrote. Every request is answered, refused with
// an exception or closes its connection; the plant keeps running.
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>

#include "sf/core/clock.hpp"
#include "sf/modbus/server.hpp"
#include "sf/plant/plant.hpp"

namespace {

struct Harness {
  sf::ManualClock clock;
  std::unique_ptr<sf::plant::Plant> plant;
  Harness() : plant(std::make_unique<sf::plant::Plant>(*sf::plant::default_layout(), clock)) {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Harness h;
  if (size == 0) {
    return 0;
  }
  // The first byte picks the device: conveyor, uploader or a legacy robot.
  const char* names[] = {"conveyor1", "uploader", "toshiba"};
  auto* device = h.plant->plc(names[data[0] % 3]);
  ++data;
  --size;
  auto server = sf::modbus::Server::listen(*device, sf::modbus::ServerOptions{});
  if (!server) {
    return 0;
  }
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    return 0;
  }
  (void)(*server)->adopt(fds[0]);
  std::size_t sent = 0;
  while (sent < size) {
    const ssize_t n = ::send(fds[1], data + sent, size - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n <= 0) {
      break;
    }
    sent += static_cast<std::size_t>(n);
    (void)(*server)->poll_once(std::chrono::milliseconds{0});
  }
  ::shutdown(fds[1], SHUT_WR);
  for (int i = 0; i < 4; ++i) {
    (void)(*server)->poll_once(std::chrono::milliseconds{0});
  }
  ::close(fds[1]);
  auto lock = h.plant->lock();
  h.plant->advance(std::chrono::milliseconds{1});
  return 0;
}
