// The smart robot's IPC under load: the EtherCAT cycle's wake-up lateness
// (|wake-up − deadline| of the 1 kHz cycle thread, which then exchanges the
// frame) while its OPC UA server serves 10 subscribed clients (SignAndEncrypt,
// every tag of the machine model monitored at 10 ms) and its DDS agent
// negotiates work that the arm executes, next to the same cycle with nothing
// else running, in the same run.
// Goal: p99 under load ≤ 1.5× p99 alone.
//
// The plant runs in this process in real time (PlantHost: the robot's
// segment on EtherCAT-in-UDP on loopback); the IPC is the MachineProcess the
// `machine` command runs; the load is a product's manager over DDS that
// negotiates "load 1 candy" jobs one after another into a box the plant's hand
// keeps at the robot's station (a new box when one is full).
//   bench_machine [SECONDS_PER_PHASE]
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "sf/core/clock.hpp"
#include "sf/dds/executor.hpp"
#include "sf/factory/machine_model.hpp"
#include "sf/factory/machine_process.hpp"
#include "sf/negotiation/dds_transport.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/client/security_setup.hpp"
#include "sf/plant/host.hpp"
#include "sf/plant/plant.hpp"

namespace {

using namespace std::chrono_literals;
namespace fy = sf::factory;
namespace cnp = sf::negotiation;

constexpr const char* kRobot = "scara-robot-1";

struct Phase {
  std::string name;
  std::uint64_t cycles = 0;
  std::chrono::nanoseconds p50{0}, p99{0}, max{0};
  std::uint64_t jobs = 0;
};

double us(std::chrono::nanoseconds d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

// Keeps a box with a free slot at the robot's station; the next free slot.
class BoxKeeper {
 public:
  explicit BoxKeeper(sf::plant::Plant& plant) : plant_(&plant) {}
  int next_slot() {
    auto lock = plant_->lock();
    auto& world = plant_->world();
    const auto& layout = world.layout();
    const auto at = *sf::line::find_station(layout, layout.robot(kRobot)->stations.front());
    const auto type = *layout.catalog.box_index("small-box");
    if (slot_ >= layout.catalog.box_types[type].capacity() || box_ == 0) {
      if (box_ != 0) {
        (void)world.take_box(at, "bench");
      }
      auto id = world.place_box(type, at, "bench");
      box_ = id ? *id : 0;
      slot_ = 0;
    }
    return slot_++;
  }
  [[nodiscard]] sf::plant::BoxId box() const { return box_; }

 private:
  sf::plant::Plant* plant_;
  sf::plant::BoxId box_ = 0;
  int slot_ = 0;
};

// A product's manager over DDS that keeps one load in negotiation or in work.
class Negotiator {
 public:
  static std::unique_ptr<Negotiator> create(const std::string& partition, sf::plant::Plant& plant) {
    auto n = std::unique_ptr<Negotiator>(new Negotiator(plant));
    auto endpoints = cnp::ProductEndpoints::create(cnp::dds_settings(10, 11, partition, "lo", 1s),
                                                   "bench-product", {"load"}, n->executor_, n->clock_, false);
    if (!endpoints) {
      std::fprintf(stderr, "bench_machine: %s\n", endpoints.error().describe().c_str());
      return nullptr;
    }
    n->endpoints_ = std::move(*endpoints);
    n->manager_ = std::make_unique<cnp::Manager>(*n->endpoints_, n->clock_);
    n->endpoints_->bind(static_cast<cnp::ManagerInbox&>(*n->manager_));
    return n;
  }
  // Runs until `stop`; returns the loads done.
  std::uint64_t run(const std::atomic<bool>& stop) {
    bool busy = false;
    std::uint64_t done = 0;
    const auto& layout = plant_->layout();
    while (!stop.load()) {
      executor_.wait_for(2ms);
      executor_.run_pending();
      if (!busy && endpoints_->bidders("load") > 0) {
        const int slot = keeper_.next_slot();
        cnp::ConversationEvents events;
        events.on_done = [&](const cnp::Conversation&) { busy = false, ++done; };
        events.on_failed = [&](const cnp::Conversation&) { busy = false; };
        busy = manager_
                   ->negotiate({"bench-box",
                                "load",
                                {{"candy", static_cast<double>(*layout.catalog.candy_index("gummy"))},
                                 {"count", 1},
                                 {"box", static_cast<double>(keeper_.box())},
                                 {"slot", static_cast<double>(slot)},
                                 {"box_type", static_cast<double>(*layout.catalog.box_index("small-box"))}},
                                ""},
                               std::move(events))
                   .ok();
      }
      manager_->tick();
      endpoints_->flush_ended();
    }
    return done;
  }

 private:
  explicit Negotiator(sf::plant::Plant& plant) : plant_(&plant), keeper_(plant) {}
  sf::plant::Plant* plant_;
  BoxKeeper keeper_;
  sf::SteadyClock clock_;
  sf::dds::Executor executor_;
  std::unique_ptr<cnp::ProductEndpoints> endpoints_;
  std::unique_ptr<cnp::Manager> manager_;
};

// Clients of the machine's OPC UA server, each with one subscription (publishing 10 ms) monitoring
// every tag of the model and its PackML state (sampling 10 ms).
class UaClients {
 public:
  static std::unique_ptr<UaClients> connect(std::uint16_t port, std::size_t count) {
    auto out = std::make_unique<UaClients>();
    for (std::size_t i = 0; i < count; ++i) {
      sf::opcua::ClientConfig config;
      config.endpoint_url = fmt::format("opc.tcp://localhost:{}", port);
      config.session_name = fmt::format("bench client {}", i);
      if (auto st = sf::opcua::configure_client_security({}, config); !st) {
        std::fprintf(stderr, "bench_machine: %s\n", st.error().describe().c_str());
        return nullptr;
      }
      auto client = std::make_unique<sf::opcua::SyncClient>(config);
      if (auto st = client->connect(); !st) {
        std::fprintf(stderr, "bench_machine: %s\n", st.error().describe().c_str());
        return nullptr;
      }
      if (!out->subscribe(*client)) {
        return nullptr;
      }
      out->clients_.push_back(std::move(client));
    }
    return out;
  }
  [[nodiscard]] std::uint64_t notifications() const { return received_->load(); }
  [[nodiscard]] std::size_t items() const { return items_; }

 private:
  bool subscribe(sf::opcua::SyncClient& client) {
    auto ns = client.namespace_index(std::string(sf::factory::kMachineNamespace));
    sf::opcua::SyncClient::SubscriptionParams params;
    params.publishing_interval_ms = 10;
    auto sub = ns ? client.create_subscription(params) : sf::Result<std::uint32_t>(ns.error());
    if (!sub) {
      std::fprintf(stderr, "bench_machine: %s\n", sub.error().describe().c_str());
      return false;
    }
    sf::opcua::MonitoringParameters monitoring;
    monitoring.sampling_interval = 10;
    monitoring.queue_size = 1;
    for (const auto& name : paths_) {
      auto item = client.monitor_value(
          *sub, sf::opcua::value_of(sf::opcua::NodeId(*ns, sf::opcua::String("ScaraRobot1." + name))),
          monitoring, [received = received_](const sf::opcua::DataValue&) { received->fetch_add(1); });
      items_ += item ? 1U : 0U;
    }
    return true;
  }

  // The PackML state, the job, the tool and every value of the arm's four axes.
  std::vector<std::string> paths_ = [] {
    std::vector<std::string> p{"PackML.Status.StateCurrent", "Job.JobId", "Tags.tool.x", "Tags.tool.y",
                               "Tags.tool.z"};
    for (int a = 1; a <= 4; ++a) {
      for (const char* what : {"position", "setpoint", "state", "statusword"}) {
        p.push_back(fmt::format("Tags.axis{}.{}", a, what));
      }
    }
    return p;
  }();
  std::vector<std::unique_ptr<sf::opcua::SyncClient>> clients_;
  std::shared_ptr<std::atomic<std::uint64_t>> received_ = std::make_shared<std::atomic<std::uint64_t>>(0);
  std::size_t items_ = 0;
};

Phase measure(fy::MachineProcess& machine, const std::string& name, std::chrono::seconds duration,
              Negotiator* load) {
  std::atomic<bool> stop{false};
  std::uint64_t jobs = 0;
  std::thread loader;
  if (load != nullptr) {
    loader = std::thread([&] { jobs = load->run(stop); });
    std::this_thread::sleep_for(1s);  // negotiations under way before the measurement
  }
  machine.controller_thread().reset_lateness();
  std::this_thread::sleep_for(duration);
  const auto lateness = machine.controller_thread().lateness();
  stop = true;
  if (loader.joinable()) {
    loader.join();
  }
  return {name, lateness.count(), lateness.quantile(0.5), lateness.quantile(0.99), lateness.max(), jobs};
}

}  // namespace

int main(int argc, char** argv) {
  const auto seconds = std::chrono::seconds(argc > 1 ? std::max(1, std::atoi(argv[1])) : 10);
  auto layout = sf::line::default_layout();
  if (!layout) {
    std::fprintf(stderr, "bench_machine: %s\n", layout.error().describe().c_str());
    return 1;
  }
  auto& clock = sf::SteadyClock::instance();
  sf::plant::Plant plant(*layout, clock);
  sf::plant::HostOptions host_options;
  host_options.ecat_port = 0;
  auto host = sf::plant::PlantHost::start(plant, clock, host_options);
  if (!host) {
    std::fprintf(stderr, "bench_machine: %s\n", host.error().describe().c_str());
    return 1;
  }
  std::string link;
  for (const auto& e : (*host)->endpoints()) {
    if (e.machine == kRobot && e.protocol == "ethercat-udp") {
      link = "udp:" + e.address;
    }
  }
  const std::string partition = fmt::format("bench-machine-{}", ::getpid());
  auto setup =
      fy::parse_machine_config(fmt::format("machine: {}\nstart: execute\nethercat: {{link: '{}'}}\n"
                                           "dds: {{interface: lo, partition: {}}}\n",
                                           kRobot, link, partition));
  if (!setup) {
    std::fprintf(stderr, "bench_machine: %s\n", setup.error().describe().c_str());
    return 1;
  }
  auto machine = fy::MachineProcess::create(std::move(*setup), clock);
  if (!machine) {
    std::fprintf(stderr, "bench_machine: %s\n", machine.error().describe().c_str());
    return 1;
  }
  std::atomic<bool> stop{false};
  std::thread ipc([&] { (*machine)->run([&] { return stop.load(); }, nullptr, 1s); });
  while ((*machine)->controller_thread().status().packml.state != fy::PackMLState::Execute) {
    std::this_thread::sleep_for(10ms);
  }
  std::printf(
      "SCARA Robot 1's IPC, 1 kHz cycle over EtherCAT-in-UDP on loopback; %s; %lld s per phase\n",
      (*machine)->controller_thread().realtime_active() ? "cycle thread SCHED_FIFO" : "cycle thread normal",
      static_cast<long long>(seconds.count()));
  const Phase alone = measure(**machine, "nothing else running", seconds, nullptr);
  auto negotiator = Negotiator::create(partition, plant);
  auto clients = UaClients::connect((*machine)->opcua_server().port(), 10);
  if (!negotiator || !clients) {
    return 1;
  }
  const auto before = clients->notifications();
  const Phase loaded = measure(**machine, "10 OPC UA clients + DDS + arm loading", seconds, negotiator.get());
  const auto notified = clients->notifications() - before;
  stop = true;
  ipc.join();
  (*host)->stop();

  std::printf("%-38s %8s %10s %10s %10s %6s\n", "phase", "cycles", "p50 us", "p99 us", "max us", "jobs");
  for (const Phase& p : {alone, loaded}) {
    std::printf("%-38s %8llu %10.1f %10.1f %10.1f %6llu\n", p.name.c_str(),
                static_cast<unsigned long long>(p.cycles), us(p.p50), us(p.p99), us(p.max),
                static_cast<unsigned long long>(p.jobs));
  }
  const double ratio = us(loaded.p99) / std::max(1e-3, us(alone.p99));
  std::printf("OPC UA: 10 clients, %zu monitored items, %.0f notifications/s during the loaded phase\n",
              clients->items(), static_cast<double>(notified) / static_cast<double>(seconds.count() + 1));
  std::printf("p99 lateness under load / alone: %.2fx (goal <= 1.5x)\n", ratio);
  return 0;
}
