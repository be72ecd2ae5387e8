// Live fan-out: CLIENTS WebSocket clients, each subscribed to SERIES topics "series/<n>", while
// the server publishes every series at 10 Hz (SERIES × 10 publishes/s) for SECONDS; the server
// process's CPU time over that window (getrusage: the server's threads and the publisher; the
// clients read in a child process, as fast as they can), the updates published, written and
// dropped (coalesced: sf::web::ServerStats) and the updates the clients received.
// The peer in the same run: the same fan-out from Node.js with the `ws` package
// (bench/web/live_server.mjs), the same JSON messages to the same clients; it has no coalescing
// and skips a client whose socket holds more than 64 KiB unsent (counted as dropped).
// Usage: bench_web_live [SECONDS] [CLIENTS] [SERIES] [THREADS]   (defaults 10, 100, 1000, 1)
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include "sf/core/clock.hpp"
#include "sf/core/process.hpp"
#include "sf/web/server.hpp"

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
using tcp = net::ip::tcp;
using namespace std::chrono_literals;

constexpr int kRate = 10;                     // Hz per series
constexpr std::size_t kSubscribeChunk = 250;  // topics per subscribe message (under 16 KiB)

struct Options {
  int seconds = 10;
  std::size_t clients = 100;
  std::size_t series = 1000;
  int threads = 1;
};

[[noreturn]] void fail(const std::string& what) {
  std::cerr << what << "\n";
  std::exit(1);  // NOLINT(concurrency-mt-unsafe): the benchmark ends here, its threads with it
}

std::string topic(std::size_t n) {
  return fmt::format("series/{}", n);
}

// ---- the clients (child process: bench_web_live --clients PORT CLIENTS SERIES) ----

struct Client {
  explicit Client(net::io_context& context) : ws(context) {}
  beast::websocket::stream<tcp::socket> ws;
  beast::flat_buffer buffer;
  std::uint64_t received = 0;

  // Connects and subscribes to every series, waiting for each acknowledgement.
  void subscribe(std::uint16_t port, std::size_t series) {
    tcp::resolver resolver(ws.get_executor());
    net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
    ws.handshake("127.0.0.1", "/api/live");
    for (std::size_t first = 0; first < series; first += kSubscribeChunk) {
      nlohmann::json topics = nlohmann::json::array();
      for (std::size_t n = first; n < std::min(series, first + kSubscribeChunk); ++n) {
        topics.push_back(topic(n));
      }
      ws.text(true);
      ws.write(net::buffer(nlohmann::json{{"subscribe", topics}}.dump()));
      buffer.clear();
      ws.read(buffer);
      const auto reply = nlohmann::json::parse(beast::buffers_to_string(buffer.data()));
      if (!reply.contains("subscribed") ||
          reply["subscribed"].size() != std::min(series, first + kSubscribeChunk)) {
        fail("subscribe: " + reply.dump());
      }
    }
  }

  // Reads as fast as it can until the server closes the connection.
  void read() {
    buffer.clear();
    ws.async_read(buffer, [this](beast::error_code error, std::size_t) {
      if (!error) {
        ++received;
        read();
      }
    });
  }
};

int run_clients(std::uint16_t port, std::size_t clients, std::size_t series) {
  net::io_context context;
  std::vector<std::unique_ptr<Client>> all;
  for (std::size_t i = 0; i < clients; ++i) {
    all.push_back(std::make_unique<Client>(context));
    all.back()->subscribe(port, series);
  }
  for (auto& c : all) {
    c->read();
  }
  std::cout << "ready" << std::endl;
  std::thread second([&] { context.run(); });
  context.run();
  second.join();
  std::uint64_t received = 0;
  for (const auto& c : all) {
    received += c->received;
  }
  std::cout << "received " << received << std::endl;
  return 0;
}

// ---- the servers ----

struct Figures {
  double cpu_s = 0;
  double wall_s = 0;
  std::uint64_t published = 0;
  std::uint64_t sent = 0;
  std::uint64_t dropped = 0;
  std::uint64_t received = 0;
};

double cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

sf::Process spawn_clients(std::uint16_t port, const Options& o) {
  sf::ProcessOptions po;
  po.argv = {"/proc/self/exe", "--clients", std::to_string(port), std::to_string(o.clients),
             std::to_string(o.series)};
  po.out = sf::Stdio::pipe();
  po.parent_death_signal = SIGKILL;
  auto p = sf::Process::spawn(std::move(po));
  if (!p) {
    fail("clients: " + p.error().describe());
  }
  return std::move(*p);
}

std::uint64_t clients_received(sf::Process& clients) {
  auto line = clients.wait_for_line([](const std::string& l) { return l.starts_with("received "); }, 60s);
  if (!line) {
    fail("clients: " + line.error().describe());
  }
  (void)clients.wait(10s);
  return std::stoull(line->substr(9));
}

Figures ours(const Options& o) {
  sf::web::ServerConfig config;
  config.threads = o.threads;
  config.live_topic_limit = o.series;
  config.idle_timeout_seconds = 3600;  // the clients only read
  sf::web::HttpServer server(config, sf::web::Router{});
  auto port = server.start();
  if (!port) {
    fail("server: " + port.error().describe());
  }
  auto clients = spawn_clients(*port, o);
  if (auto ready = clients.wait_for_line([](const std::string& l) { return l == "ready"; }, 300s); !ready) {
    fail("clients: " + ready.error().describe());
  }
  std::vector<std::string> topics;
  for (std::size_t n = 0; n < o.series; ++n) {
    topics.push_back(topic(n));
  }
  auto& clock = sf::SteadyClock::instance();
  Figures f;
  const double cpu0 = cpu_seconds();
  const auto start = clock.now();
  const int ticks = o.seconds * kRate;
  for (int tick = 1; tick <= ticks; ++tick) {
    for (std::size_t n = 0; n < o.series; ++n) {
      server.publish(
          topics[n],
          std::sin(static_cast<double>(static_cast<std::size_t>(tick) * o.series + n) * 1e-3) * 100);
      ++f.published;
    }
    clock.sleep_until(start + tick * std::chrono::milliseconds(1000 / kRate));
  }
  f.cpu_s = cpu_seconds() - cpu0;
  f.wall_s = std::chrono::duration<double>(clock.now() - start).count();
  clock.sleep_until(clock.now() + 1s);  // the last values reach the clients
  for (const auto& c : server.stats().live_clients) {
    f.sent += c.sent;
    f.dropped += c.dropped;
  }
  server.stop();
  f.received = clients_received(clients);
  return f;
}

Figures peer(const Options& o, const std::string& node) {
  sf::ProcessOptions po;
  po.argv = {node,
             std::string(SF_BENCH_SOURCE_DIR) + "/bench/web/live_server.mjs",
             std::to_string(o.clients),
             std::to_string(o.series),
             std::to_string(kRate),
             std::to_string(o.seconds)};
  po.out = sf::Stdio::pipe();
  po.parent_death_signal = SIGKILL;
  auto server = sf::Process::spawn(std::move(po));
  if (!server) {
    fail("node: " + server.error().describe());
  }
  auto port = server->wait_for_line([](const std::string& l) { return l.starts_with("port "); }, 30s);
  if (!port) {
    fail("node: " + port.error().describe());
  }
  auto clients = spawn_clients(static_cast<std::uint16_t>(std::stoi(port->substr(5))), o);
  auto result = server->wait_for_line([](const std::string& l) { return l.starts_with("{"); },
                                      std::chrono::seconds(300 + o.seconds * 10));
  if (!result) {
    fail("node: " + result.error().describe());
  }
  const auto j = nlohmann::json::parse(*result);
  Figures f{j.at("cpu_s"), j.at("wall_s"), j.at("published"), j.at("sent"), j.at("dropped"), 0};
  f.received = clients_received(clients);
  (void)server->wait(10s);
  return f;
}

void print(std::string_view name, const Figures& f) {
  std::cout << fmt::format("{:<12} {:>6.2f} {:>6.2f} {:>5.0f} % {:>9} {:>10} {:>10} {:>10} {:>8.2f}\n", name,
                           f.cpu_s, f.wall_s, 100 * f.cpu_s / f.wall_s, f.published, f.sent, f.dropped,
                           f.received,
                           f.cpu_s * 1e6 / static_cast<double>(std::max<std::uint64_t>(1, f.received)));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 5 && std::string_view(argv[1]) == "--clients") {
    return run_clients(static_cast<std::uint16_t>(std::stoi(argv[2])), std::stoul(argv[3]),
                       std::stoul(argv[4]));
  }
  Options o;
  if (argc > 1) {
    o.seconds = std::stoi(argv[1]);
  }
  if (argc > 2) {
    o.clients = std::stoul(argv[2]);
  }
  if (argc > 3) {
    o.series = std::stoul(argv[3]);
  }
  if (argc > 4) {
    o.threads = std::stoi(argv[4]);
  }
  std::cout << fmt::format("{} clients × {} series at {} Hz ({} publishes/s) for {} s, server threads {}\n",
                           o.clients, o.series, kRate, o.series * kRate, o.seconds, o.threads);
  std::cout << "server        CPU s wall s   CPU  published    written    dropped   received µs CPU/update\n";
  const auto a = ours(o);
  print("sf::web", a);
  const auto node = sf::find_program("node");
  if (!node) {
    std::cout << "ws (Node.js) not run: no node on PATH\n";
    return 0;
  }
  const auto b = peer(o, node->string());
  print("ws (Node.js)", b);
  std::cout << fmt::format(
      "ratio sf::web / ws: CPU {:.2f}, CPU per received update {:.2f}, received {:.2f}\n", a.cpu_s / b.cpu_s,
      (a.cpu_s / static_cast<double>(a.received)) / (b.cpu_s / static_cast<double>(b.received)),
      static_cast<double>(a.received) / static_cast<double>(b.received));
  return 0;
}
