// End-to-end latency of the cloud gateway (paper §VI, Fig. 7): S OPC UA servers with V variables each, every
// variable changing every I ms; the gateway subscribes to all of them and writes to the historian.
// For every sample, two latencies from the moment the server changed the value (its source
// timestamp):
//   notification  the gateway has the sample (the OPC UA path alone: sampling, publishing,
//                 encoding, TCP, decoding; measured on the gateway's LiveBus) — the peer
//   committed     the historian's transaction with the sample's row has committed
// Printed side by side with their ratio; the difference is what the historian path adds. Also the
// sustained rate: samples committed per second against samples produced per second.
//
//   bench_cloud_latency [--servers 10] [--variables 1000] [--interval-ms 100] [--seconds 10]
//                       [--db sqlite|postgresql] [--batch 1000] [--flush-ms 200] [--json]
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pg_server.hpp"
#include "sf/bench/percentile.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/server/server.hpp"

namespace {

namespace fs = std::filesystem;
namespace ua = sf::opcua;
using namespace std::chrono_literals;

struct Options {
  std::size_t servers = 10;
  std::size_t variables = 1000;
  int interval_ms = 100;
  int seconds = 10;
  std::string db = "sqlite";
  std::size_t batch = 1000;
  int flush_ms = 200;
  bool json = false;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (arg == "--servers") {
      o.servers = std::stoul(next());
    } else if (arg == "--variables") {
      o.variables = std::stoul(next());
    } else if (arg == "--interval-ms") {
      o.interval_ms = std::stoi(next());
    } else if (arg == "--seconds") {
      o.seconds = std::stoi(next());
    } else if (arg == "--db") {
      o.db = next();
    } else if (arg == "--batch") {
      o.batch = std::stoul(next());
    } else if (arg == "--flush-ms") {
      o.flush_ms = std::stoi(next());
    } else if (arg == "--json") {
      o.json = true;
    } else {
      std::cerr
          << "usage: bench_cloud_latency [--servers N] [--variables N] [--interval-ms MS] [--seconds S] "
             "[--db sqlite|postgresql] [--batch N] [--flush-ms MS] [--json]\n";
      std::exit(arg == "--help" ? 0 : 2);
    }
  }
  return o;
}

std::int64_t now_micros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// A server whose V Double variables under Objects/Plant all take a new value every interval, with
// the moment of the change as source timestamp.
class ChangingServer {
 public:
  ChangingServer(std::size_t variables, std::chrono::milliseconds interval) {
    ua::server::ServerConfig config;
    config.transport.host = "127.0.0.1";
    config.transport.port = 0;
    config.advertised_host = "127.0.0.1";
    server_ = std::make_unique<ua::server::Server>(config);
    server_->with_address_space([&](ua::server::AddressSpace& space) {
      const std::uint16_t ns = space.add_namespace("urn:smartfactory:bench:plant");
      ua::server::ObjectSpec plant;
      plant.node_id = ua::NodeId(ns, ua::String("Plant"));
      plant.browse_name = ua::QualifiedName(ns, "Plant");
      plant.parent = ua::NodeId(0, ua::id::ObjectsFolder);
      plant.reference_type = ua::NodeId(0, ua::id::Organizes);
      (void)space.add_object(plant);
      for (std::size_t i = 0; i < variables; ++i) {
        ua::server::VariableSpec v;
        v.node_id = ua::NodeId(ns, ua::String(fmt::format("Plant.V{}", i)));
        v.browse_name = ua::QualifiedName(ns, ua::String(fmt::format("V{}", i)));
        v.parent = plant.node_id;
        v.data_type = ua::NodeId(0, ua::id::Double);
        v.value = ua::DataValue(ua::Variant(0.0));
        nodes_.push_back(*space.add_variable(v));
      }
    });
    ok_ = server_->start().ok();
    server_->loop().post(
        [this, interval] { timer_ = server_->loop().add_periodic(interval, [this] { step(); }); });
  }
  ~ChangingServer() { server_->stop(); }
  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] std::uint16_t port() const { return server_->port(); }
  [[nodiscard]] std::uint64_t changes() const { return changes_.load(); }

 private:
  void step() {
    ++step_;
    server_->with_address_space([&](ua::server::AddressSpace& space) {
      const ua::DateTime now = ua::DateTime::from_system_clock(std::chrono::system_clock::now());
      for (std::size_t i = 0; i < nodes_.size(); ++i) {
        ua::DataValue value(ua::Variant(static_cast<double>(step_) + static_cast<double>(i) * 1e-6));
        value.source_timestamp = now;
        (void)space.set_value(nodes_[i], std::move(value));
      }
    });
    changes_ += nodes_.size();
  }

  std::unique_ptr<ua::server::Server> server_;
  std::vector<ua::NodeId> nodes_;
  std::uint64_t step_ = 0;
  std::atomic<std::uint64_t> changes_{0};
  sf::net::EventLoop::TimerId timer_ = 0;
  bool ok_ = false;
};

// Latencies in microseconds, collected from several threads while `recording` is set.
class Latencies {
 public:
  void add(std::int64_t micros) {
    std::lock_guard lock(mutex_);
    values_.push_back(micros);
  }
  std::vector<std::int64_t> take() {
    std::lock_guard lock(mutex_);
    std::sort(values_.begin(), values_.end());
    return std::move(values_);
  }

 private:
  std::mutex mutex_;
  std::vector<std::int64_t> values_;
};

double percentile_ms(const std::vector<std::int64_t>& sorted, double p) {
  return static_cast<double>(sf::bench::percentile_of_sorted(std::span<const std::int64_t>(sorted), p)) /
         1000.0;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  (void)sf::log::set_level("warn");
  const fs::path dir = fs::temp_directory_path() / fmt::format("sf-bench-cloud-{}", ::getpid());
  fs::create_directories(dir);
  std::unique_ptr<sf::historian::testing::PgServer> pg;
  std::string url = "sqlite:" + (dir / "history.db").string();
  if (o.db == "postgresql") {
    auto started = sf::historian::testing::PgServer::start({.durable = true});
    if (!started) {
      std::cerr << "PostgreSQL: " << started.error().describe() << "\n";
      return 1;
    }
    pg = std::move(*started);
    url = pg->url();
  }

  std::cerr << fmt::format("starting {} servers × {} variables, a change every {} ms ...\n", o.servers,
                           o.variables, o.interval_ms);
  std::vector<std::unique_ptr<ChangingServer>> servers;
  sf::cloud::GatewayConfig config;
  config.historian.url = url;
  config.historian.buffer = dir / "buffer";
  config.historian.batch = o.batch;
  config.historian.flush_interval = std::chrono::milliseconds(o.flush_ms);
  for (std::size_t s = 0; s < o.servers; ++s) {
    servers.push_back(
        std::make_unique<ChangingServer>(o.variables, std::chrono::milliseconds(o.interval_ms)));
    if (!servers.back()->ok()) {
      std::cerr << "a server did not start\n";
      return 1;
    }
    sf::cloud::ServerConfig server;
    server.name = fmt::format("cell-{}", s);
    server.url = fmt::format("opc.tcp://127.0.0.1:{}", servers.back()->port());
    server.publishing_interval_ms = o.interval_ms;
    server.sampling_interval_ms = o.interval_ms / 2.0;
    server.queue_size = 4;
    sf::cloud::SubscribeRule rule;
    rule.browse_path = "/Objects/Plant";
    rule.depth = 1;
    server.subscribe.push_back(rule);
    config.servers.push_back(server);
  }

  std::atomic<bool> recording{false};
  std::atomic<std::uint64_t> committed{0};
  Latencies notified_latency;
  Latencies committed_latency;
  sf::cloud::GatewayOptions options;
  options.on_commit = [&](std::span<const sf::historian::Sample> batch) {
    committed += batch.size();
    if (!recording) {
      return;
    }
    const std::int64_t now = now_micros();
    for (const auto& sample : batch) {
      committed_latency.add(now - sample.source_time.time_since_epoch().count());
    }
  };
  auto gateway = sf::cloud::Gateway::create(config, options);
  if (!gateway) {
    std::cerr << gateway.error().describe() << "\n";
    return 1;
  }
  auto live = (*gateway)->live().subscribe([&](const sf::cloud::LiveUpdate& u) {
    if (recording) {
      notified_latency.add(now_micros() - u.sample.source_time.time_since_epoch().count());
    }
  });
  if (auto st = (*gateway)->start(); !st) {
    std::cerr << st.error().describe() << "\n";
    return 1;
  }
  const std::size_t series = o.servers * o.variables;
  for (int waited = 0;; ++waited) {
    std::size_t subscribed = 0;
    for (const auto& s : (*gateway)->status().servers) {
      subscribed += s.phase == "subscribed" ? s.series : 0;
    }
    if (subscribed == series) {
      break;
    }
    if (waited == 600) {
      std::cerr << "the gateway did not subscribe to every variable within 60 s\n";
      return 1;
    }
    std::this_thread::sleep_for(100ms);
  }
  std::cerr << "subscribed to " << series << " variables; warming up 3 s, then measuring " << o.seconds
            << " s\n";
  std::this_thread::sleep_for(3s);
  auto changes_now = [&] {
    std::uint64_t n = 0;
    for (const auto& s : servers) {
      n += s->changes();
    }
    return n;
  };
  const std::uint64_t changes0 = changes_now();
  const std::uint64_t committed0 = committed.load();
  recording = true;
  const auto started = std::chrono::steady_clock::now();
  for (int s = 0; s < o.seconds; ++s) {
    std::this_thread::sleep_for(1s);
    const auto status = (*gateway)->status();
    std::cerr << fmt::format("  {:>3} s: {} written, {} queued, {} buffered\n", s + 1, status.samples_written,
                             status.queued, status.buffer.buffered_records);
  }
  recording = false;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double produced = static_cast<double>(changes_now() - changes0) / elapsed;
  const double written = static_cast<double>(committed.load() - committed0) / elapsed;
  (*gateway)->stop();
  servers.clear();
  const auto notified = notified_latency.take();
  const auto stored = committed_latency.take();
  fs::remove_all(dir);

  const double n50 = percentile_ms(notified, 0.50);
  const double n99 = percentile_ms(notified, 0.99);
  const double c50 = percentile_ms(stored, 0.50);
  const double c99 = percentile_ms(stored, 0.99);
  if (o.json) {
    std::cout << fmt::format(
        R"({{"servers":{},"variables":{},"interval_ms":{},"db":"{}","produced_per_s":{:.0f},"committed_per_s":{:.0f},)"
        R"("notification_ms":{{"p50":{:.1f},"p99":{:.1f}}},"committed_ms":{{"p50":{:.1f},"p99":{:.1f}}},)"
        R"("ratio_p50":{:.2f},"ratio_p99":{:.2f}}})"
        "\n",
        o.servers, o.variables, o.interval_ms, o.db, produced, written, n50, n99, c50, c99, c50 / n50,
        c99 / n99);
    return 0;
  }
  std::cout << fmt::format(
      "{} servers × {} variables, a change every {} ms, sampling {} ms, publishing {} ms, {} (batch {}, "
      "flush {} ms)\n",
      o.servers, o.variables, o.interval_ms, o.interval_ms / 2.0, o.interval_ms, o.db, o.batch, o.flush_ms);
  std::cout << fmt::format("  produced {:.0f} values/s, committed {:.0f} rows/s ({} samples measured)\n",
                           produced, written, stored.size());
  std::cout << fmt::format("  {:<40} {:>9} {:>9}\n", "latency from the value change", "p50 ms", "p99 ms");
  std::cout << fmt::format("  {:<40} {:>9.1f} {:>9.1f}\n", "committed row (gateway → historian)", c50, c99);
  std::cout << fmt::format("  {:<40} {:>9.1f} {:>9.1f}\n", "notification at the gateway (peer)", n50, n99);
  std::cout << fmt::format("  ratio committed / notification: p50 {:.2f}×, p99 {:.2f}×\n", c50 / n50,
                           c99 / n99);
  return 0;
}
