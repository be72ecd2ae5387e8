// A legacy machine's gateway from PLC to OPC UA: the time from a PLC input
// changing in the plant (a box put on / taken off conveyor 1's upload
// station: its photo-eye, a discrete input) to the data change notification
// at an OPC UA client subscribed to the gateway's model
// (Conveyor1.Tags.plc.station_eye.upload), next to the raw Modbus TCP round
// trip of a read of the same PLC's discrete inputs, in the same run.
//
// The chain a change goes through (docs/shop-floor.md, "Threads"): the plant's
// 1 ms step updates the PLC's registers; the gateway's ControllerThread polls
// the PLC every 20 ms (read of every table) and refreshes its status snapshot
// every 10 ms; MachineHost's timer on the OPC UA loop thread publishes the
// snapshot every 10 ms; the subscription publishes every 10 ms (the server's
// minimum). So the expected latency is about half of each period plus the
// round trips: ~25 ms at the median, ~50 ms at worst.
//
// The plant runs in this process in real time (PlantHost, its PLCs on Modbus
// TCP on loopback); the gateway is the GatewayProcess `smartfactory gateway`
// runs; the client is ours (SignAndEncrypt, the default PKI).
//   bench_gateway [CHANGES]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "sf/bench/percentile.hpp"
#include "sf/core/clock.hpp"
#include "sf/factory/gateway_process.hpp"
#include "sf/factory/machine_model.hpp"
#include "sf/modbus/tcp_client.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/client/security_setup.hpp"
#include "sf/plant/host.hpp"
#include "sf/plant/plant.hpp"

namespace {

using namespace std::chrono_literals;
namespace fy = sf::factory;
using Nanos = std::chrono::nanoseconds;

constexpr const char* kBelt = "conveyor1";
constexpr const char* kStation = "conveyor1/upload";
constexpr const char* kTag = "Conveyor1.Tags.plc.station_eye.upload";

double ms(Nanos d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

// Ends the benchmark at once: threads of the plant, the gateway and the client may still run, so
// no exit handlers or destructors (std::_Exit); stderr is unbuffered.
[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "bench_gateway: %s\n", what.c_str());
  std::_Exit(1);
}

// The latest value of the monitored photo-eye and when it arrived.
class EyeWatch {
 public:
  void seen(bool value) {
    const auto now = sf::SteadyClock::instance().now();
    std::lock_guard lock(mutex_);
    value_ = value;
    at_ = now;
    changed_.notify_all();
  }
  // When the value became `want` (nullopt after `timeout`).
  std::optional<sf::Clock::time_point> wait_for(bool want, std::chrono::milliseconds timeout) {
    std::unique_lock lock(mutex_);
    if (!changed_.wait_for(lock, timeout, [&] { return value_ == want; })) {
      return std::nullopt;
    }
    return at_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<bool> value_;
  sf::Clock::time_point at_{};
};

std::unique_ptr<sf::opcua::SyncClient> subscribe(std::uint16_t port, EyeWatch& watch) {
  sf::opcua::ClientConfig config;
  config.endpoint_url = fmt::format("opc.tcp://localhost:{}", port);
  config.session_name = "bench_gateway";
  if (auto st = sf::opcua::configure_client_security({}, config); !st) {
    fail(st.error().describe());
  }
  auto client = std::make_unique<sf::opcua::SyncClient>(config);
  if (auto st = client->connect(); !st) {
    fail(st.error().describe());
  }
  auto ns = client->namespace_index(std::string(fy::kMachineNamespace));
  sf::opcua::SyncClient::SubscriptionParams params;
  params.publishing_interval_ms = 10;
  auto sub = ns ? client->create_subscription(params) : sf::Result<std::uint32_t>(ns.error());
  if (!sub) {
    fail(sub.error().describe());
  }
  sf::opcua::MonitoringParameters monitoring;
  monitoring.sampling_interval = 0;  // every change the server writes
  monitoring.queue_size = 4;
  auto item = client->monitor_value(
      *sub, sf::opcua::value_of(sf::opcua::NodeId(*ns, sf::opcua::String(kTag))), monitoring,
      [&watch](const sf::opcua::DataValue& v) {
        if (const auto* b = v.value.get_if<bool>(); b != nullptr && v.status.is_good()) {
          watch.seen(*b);
        }
      });
  if (!item) {
    fail(item.error().describe());
  }
  return client;
}

// Puts a box on the station (true) or takes it off (false); when.
sf::Clock::time_point toggle(sf::plant::Plant& plant, bool box) {
  auto lock = plant.lock();
  auto& world = plant.world();
  const auto& layout = world.layout();
  const auto at = *sf::line::find_station(layout, kStation);
  const auto when = sf::SteadyClock::instance().now();
  if (box) {
    if (auto id = world.place_box(*layout.catalog.box_index("small-box"), at, "bench"); !id) {
      fail(id.error().describe());
    }
  } else if (auto taken = world.take_box(at, "bench"); !taken) {
    fail(taken.error().describe());
  }
  return when;
}

std::vector<Nanos> modbus_round_trips(std::uint16_t port, int count) {
  sf::modbus::TcpClientOptions options;
  options.port = port;
  auto client = sf::modbus::TcpClient::create(options);
  if (!client) {
    fail(client.error().describe());
  }
  std::vector<Nanos> out;
  for (int i = 0; i < count; ++i) {
    const auto start = sf::SteadyClock::instance().now();
    if (auto r = (*client)->read_discrete_inputs(0, 16); !r) {
      fail("Modbus read failed");
    }
    out.push_back(sf::SteadyClock::instance().now() - start);
  }
  return out;
}

void print(const char* what, const std::vector<Nanos>& samples) {
  std::printf("%-52s %6zu %9.3f %9.3f %9.3f\n", what, samples.size(), ms(sf::bench::percentile(samples, 0.5)),
              ms(sf::bench::percentile(samples, 0.99)),
              ms(*std::max_element(samples.begin(), samples.end())));
}

}  // namespace

int main(int argc, char** argv) {
  const int changes = argc > 1 ? std::max(10, std::atoi(argv[1])) : 200;
  auto layout = sf::line::default_layout();
  if (!layout) {
    fail(layout.error().describe());
  }
  auto& clock = sf::SteadyClock::instance();
  sf::plant::Plant plant(*layout, clock);
  auto host = sf::plant::PlantHost::start(plant, clock, {});
  if (!host) {
    fail(host.error().describe());
  }
  std::uint16_t plc_port = 0;
  for (const auto& e : (*host)->endpoints()) {
    if (e.machine == kBelt && e.protocol == "modbus-tcp") {
      plc_port = static_cast<std::uint16_t>(std::stoi(e.address.substr(e.address.rfind(':') + 1)));
    }
  }
  auto setup = fy::parse_gateway_config(
      fmt::format("machine: {}\nkind: conveyor\nstart: execute\nmodbus: {{port: {}, poll_period_ms: 20}}\n"
                  "opcua: {{port: 0}}\ndds: {{interface: lo, partition: bench-gateway-{}}}\n",
                  kBelt, plc_port, ::getpid()));
  if (!setup) {
    fail(setup.error().describe());
  }
  auto gateway = fy::GatewayProcess::create(std::move(*setup), clock);
  if (!gateway) {
    fail(gateway.error().describe());
  }
  std::atomic<bool> stop{false};
  std::thread process([&] { (*gateway)->run([&] { return stop.load(); }, nullptr, 0s); });
  EyeWatch watch;
  auto client = subscribe((*gateway)->opcua_server().port(), watch);
  if (!watch.wait_for(false, 5s)) {
    fail("the photo-eye never showed Good over OPC UA");
  }

  // De-phased from the poll period: a random pause before each change.
  std::mt19937 random(7);
  std::uniform_int_distribution<int> pause_us(0, 40000);
  std::vector<Nanos> latency;
  for (int i = 0; i < changes; ++i) {
    std::this_thread::sleep_for(std::chrono::microseconds(pause_us(random)));
    const bool box = i % 2 == 0;
    const auto changed = toggle(plant, box);
    const auto seen = watch.wait_for(box, 2s);
    if (!seen) {
      fail(fmt::format("change {} not notified within 2 s", i));
    }
    latency.push_back(*seen - changed);
  }
  const auto round_trips = modbus_round_trips(plc_port, 2000);
  stop = true;
  process.join();
  client.reset();
  (*host)->stop();

  std::printf("conveyor 1's gateway: PLC poll every 20 ms, OPC UA subscription publishing every 10 ms\n");
  std::printf("%-52s %6s %9s %9s %9s\n", "", "n", "p50 ms", "p99 ms", "max ms");
  print("photo-eye change in the plant -> OPC UA notification", latency);
  print("raw Modbus TCP round trip (read 16 inputs)", round_trips);
  std::printf(
      "notification p50 / Modbus round trip p50: %.0fx\n",
      ms(sf::bench::percentile(latency, 0.5)) / std::max(1e-6, ms(sf::bench::percentile(round_trips, 0.5))));
  return 0;
}
