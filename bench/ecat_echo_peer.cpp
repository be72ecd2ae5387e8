// The wire floor for the EtherCAT benchmarks: the same raw-socket Link over
// the same veth pair, with a peer that only reflects frames (no ESC work).
// bench/ecat_veth.sh runs it next to `ecat sim` + `ecat run`, so the ratio
// "our segment / plain echo" shows what the EtherCAT processing costs.
//
//   ecat_echo_peer serve IF                      reflect every EtherCAT frame until SIGTERM
//   ecat_echo_peer ping IF SIZE RATE_HZ SECONDS  send frames of SIZE bytes at RATE_HZ
//                                                  (0 = back to back), print JSON statistics
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/ethercat/master/statistics.hpp"

namespace ecat = sf::ethercat;
using namespace std::chrono_literals;

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int /*sig*/) {
  g_stop = 1;
}

int serve(ecat::Link& link) {
  std::array<std::uint8_t, ecat::kMaxFrameSize + 4> buf{};
  while (g_stop == 0) {
    auto n = link.receive(buf, 100ms);
    if (!n) {
      std::fprintf(stderr, "receive: %s\n", n.error().describe().c_str());
      return 1;
    }
    if (*n == 0) {
      continue;
    }
    buf[6] |= 0x02;  // like an ESC: mark the source MAC locally administered
    if (auto st = link.send(sf::ByteSpan{buf.data(), *n}); !st) {
      std::fprintf(stderr, "send: %s\n", st.error().describe().c_str());
    }
  }
  return 0;
}

double us(std::chrono::nanoseconds d) {
  return static_cast<double>(d.count()) / 1000.0;
}

int ping(ecat::Link& link, std::size_t size, double rate_hz, double seconds) {
  ecat::Frame frame;
  frame.source = link.mac();
  const std::size_t data = size > 28 ? size - 28 : 1;  // Ethernet + EtherCAT + datagram overhead
  frame.datagrams.push_back({ecat::Command::NOP, 0, 0, 0, false, sf::Bytes(data), 0});
  auto bytes = ecat::encode(frame);
  if (!bytes) {
    std::fprintf(stderr, "encode: %s\n", bytes.error().describe().c_str());
    return 1;
  }
  auto& clock = sf::SteadyClock::instance();
  ecat::master::DurationHistogram rtt;
  std::uint64_t sent = 0;
  std::uint64_t lost = 0;
  std::array<std::uint8_t, ecat::kMaxFrameSize + 4> buf{};
  const auto start = clock.now();
  const auto end =
      start + std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>{seconds});
  const auto period = rate_hz > 0 ? std::chrono::nanoseconds{static_cast<std::int64_t>(1e9 / rate_hz)} : 0ns;
  auto next = start;
  while (clock.now() < end && g_stop == 0) {
    if (period > 0ns) {
      clock.sleep_until(next);
      next += period;
    }
    (*bytes)[ecat::kEthernetHeaderSize + ecat::kEcatHeaderSize + 1] = static_cast<std::uint8_t>(sent);
    const auto t0 = clock.now();
    if (!link.send(*bytes)) {
      return 1;
    }
    ++sent;
    bool back = false;
    while (!back) {
      auto n = link.receive(buf, 2ms);
      if (!n || *n == 0) {
        break;
      }
      back =
          buf[ecat::kEthernetHeaderSize + ecat::kEcatHeaderSize + 1] == static_cast<std::uint8_t>(sent - 1);
    }
    if (back) {
      rtt.record(clock.now() - t0);
    } else {
      ++lost;
    }
  }
  const double elapsed = std::chrono::duration<double>(clock.now() - start).count();
  std::printf(
      "{\"frames\": %llu, \"lost\": %llu, \"frames_per_s\": %.1f, \"round_trip_us\": {\"min\": %.2f, "
      "\"median\": %.2f, "
      "\"p99\": %.2f, \"max\": %.2f}}\n",
      static_cast<unsigned long long>(sent), static_cast<unsigned long long>(lost),
      static_cast<double>(sent) / elapsed, us(rtt.min()), us(rtt.median()), us(rtt.quantile(0.99)),
      us(rtt.max()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s serve IF | ping IF SIZE RATE_HZ SECONDS\n", argv[0]);
    return 2;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  auto link = ecat::RawSocketLink::open(argv[2]);
  if (!link) {
    std::fprintf(stderr, "%s\n", link.error().describe().c_str());
    return 1;
  }
  if (std::strcmp(argv[1], "serve") == 0) {
    return serve(**link);
  }
  if (std::strcmp(argv[1], "ping") == 0 && argc == 6) {
    return ping(**link, std::strtoul(argv[3], nullptr, 10), std::strtod(argv[4], nullptr),
                std::strtod(argv[5], nullptr));
  }
  std::fprintf(stderr, "usage: %s serve IF | ping IF SIZE RATE_HZ SECONDS\n", argv[0]);
  return 2;
}
