// Our OPC UA server next to a node-opcua server, measured in the same run with the same client
// (sf::opcua::Client) and the same model: the demo model plus 1 000 Double variables
// ns=<demo>;s=Demo.Bench.<i> that all change every 100 ms.
//
//   ours:       smartfactory opcua server --demo-model --bench-variables 1000 --max-sessions N
//               --max-channels-per-address N
//   node-opcua: node tests/peers/opcua/node_server.mjs 0 --variables 1000 --max-sessions N
//
// Both run as processes of their own, on 127.0.0.1, SecurityPolicy None (ours with `--security
// none`), anonymous. While one server is measured the other is stopped (SIGSTOP), so neither
// disturbs the other's figures.
// Figures, each as ours, node-opcua, ratio ours / node-opcua:
//   1. Read: values/s with 1 and with 100 values per ReadRequest (Value attribute, both
//      timestamps), one session, `--depth` requests outstanding (8), for `--read-seconds` (3)
//      after a warm-up; with the CPU the server and this process (the client) used meanwhile,
//      and the server's CPU time per request answered.
//   2. Data changes: one subscription (publishing 100 ms) with 1 000 monitored items (sampling
//      100 ms, queue 1) on the Bench variables; notifications/s over `--notify-seconds` (5),
//      the fraction of the 10 000/s the model produces, and the server's CPU.
//   3. Sessions: up to `--sessions` (500) sessions, each on its own TCP connection and secure
//      channel, 16 being opened at a time; how many are held, how long opening them took and
//      the server's RSS with them held. Both servers are configured for exactly that many.
//   4. RSS (VmRSS of /proc/<pid>/status): idle (model loaded, no client) and loaded (the
//      largest sample during the data-change run).
// A readable table on stdout (`--json`: one JSON object), progress on stderr. `--quick` is a
// short smoke run (1 s of reads, 2 s of data changes, 50 sessions); `--only reads|notify|sessions`
// runs one phase and `--read-size 1|100` one size of reads (for profiling one server:
// `--smartfactory` may name a wrapper script, e.g. one that runs it under callgrind).
//
//   build/release/bench/bench_opcua_server [--quick] [--json]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "opcua_bench.hpp"
#include "sf/core/log.hpp"
#include "sf/net/event_loop.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/status_codes.hpp"

namespace {

using namespace opcua_bench;
namespace ua = sf::opcua;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr std::string_view kDemoNamespace = "urn:smartfactory:demo";

struct Options : CommonOptions {
  Options() : CommonOptions(SF_BENCH_SOURCE_DIR) {}
  std::string only;  // one phase (reads, notify, sessions), e.g. for profiling
  std::size_t variables = 1000;
  std::size_t sessions = 500;
  std::size_t depth = 8;
  std::size_t read_with_items = 0;  // monitored items on another session during the reads
  std::size_t read_size = 0;        // 1 or 100: only reads of that many values (0: both)
  double read_seconds = 3;
  double notify_seconds = 5;
};

void progress(const std::string& text) {
  std::fprintf(stderr, "bench_opcua_server: %s\n", text.c_str());
}

// --- measurements -------------------------------------------------------------------

ua::ClientConfig client_config(const std::string& url, const std::string& name) {
  ua::ClientConfig config;
  config.endpoint_url = url;
  config.session_name = name;
  config.auto_reconnect = false;
  config.request_timeout = 20s;
  return config;
}

std::vector<ua::ReadValueId> bench_values(std::uint16_t ns, std::size_t first, std::size_t count) {
  std::vector<ua::ReadValueId> items;
  for (std::size_t i = first; i < first + count; ++i) {
    items.push_back(ua::value_of(ua::NodeId(ns, ua::String(fmt::format("Demo.Bench.{}", i)))));
  }
  return items;
}

// A connected client with the index of the demo namespace.
struct Connection {
  std::unique_ptr<ua::SyncClient> client;
  std::uint16_t ns = 0;
};

std::optional<Connection> connect(const ServerProcess& server, const std::string& name) {
  Connection c;
  c.client = std::make_unique<ua::SyncClient>(client_config(server.url(), name));
  if (auto st = c.client->connect(); !st) {
    progress(fmt::format("{}: cannot connect: {}", server.name(), st.error().message));
    return std::nullopt;
  }
  auto ns = c.client->namespace_index(kDemoNamespace);
  if (!ns) {
    progress(fmt::format("{}: no demo namespace: {}", server.name(), ns.error().message));
    return std::nullopt;
  }
  c.ns = *ns;
  return c;
}

struct NotifyResult {
  double per_s = 0;
  std::size_t items = 0;  // monitored items created
  std::uint64_t loaded_rss = 0;
  double cpu_percent = 0;  // the server's, of one core
};

// One subscription with `variables` monitored items; notifications/s after a 1.5 s warm-up.
// One subscription (publishing 100 ms) with a monitored item (sampling 100 ms, queue 1) on each
// of the first `variables` Bench variables, counting the notifications that arrive.
struct Subscribed {
  std::optional<ua::SyncClient::SubscriptionId> id;
  std::size_t items = 0;  // monitored items created
  std::shared_ptr<std::atomic<std::uint64_t>> received = std::make_shared<std::atomic<std::uint64_t>>(0);
};

Subscribed subscribe(Connection& c, const ServerProcess& server, std::size_t variables) {
  Subscribed s;
  ua::SyncClient::SubscriptionParams params;
  params.publishing_interval_ms = 100;
  params.max_keep_alive_count = 10;
  params.lifetime_count = 100;
  auto sub = c.client->create_subscription(params);
  if (!sub) {
    progress(fmt::format("{}: CreateSubscription: {}", server.name(), sub.error().message));
    return s;
  }
  s.id = *sub;
  ua::MonitoringParameters parameters;
  parameters.sampling_interval = 100;
  parameters.queue_size = 1;
  parameters.discard_oldest = true;
  // Created 50 at a time (one item per CreateMonitoredItems request, as the client sends them).
  std::atomic<std::size_t> created{0};
  std::atomic<std::size_t> answered{0};
  const auto items = bench_values(c.ns, 0, variables);
  ua::Client& client = c.client->client();
  std::size_t next = 0;
  while (next < items.size()) {
    const std::size_t batch_end = std::min(items.size(), next + 50);
    for (; next < batch_end; ++next) {
      client.monitor_value(
          *sub, items[next], parameters,
          [received = s.received](const ua::DataValue&) { received->fetch_add(1); },
          [&](const sf::Result<std::uint32_t>& handle) {
            if (handle) {
              created.fetch_add(1);
            }
            answered.fetch_add(1);
          });
    }
    while (answered.load() < next) {
      std::this_thread::sleep_for(1ms);
    }
  }
  s.items = created.load();
  return s;
}

// Notifications/s of one subscription with `variables` items, after a 1.5 s warm-up.
NotifyResult measure_notifications(Connection& c, const ServerProcess& server, std::size_t variables,
                                   double seconds) {
  NotifyResult r;
  const Subscribed sub = subscribe(c, server, variables);
  if (!sub.id) {
    return r;
  }
  const auto& received = sub.received;
  r.items = sub.items;
  std::this_thread::sleep_for(1500ms);
  const std::uint64_t first = received->load();
  const double cpu = server.cpu_seconds();
  const auto start = Clock::now();
  while (seconds_since(start) < seconds) {
    std::this_thread::sleep_for(100ms);
    r.loaded_rss = std::max(r.loaded_rss, server.rss());
  }
  const double elapsed = seconds_since(start);
  r.cpu_percent = 100.0 * (server.cpu_seconds() - cpu) / elapsed;
  r.per_s = static_cast<double>(received->load() - first) / elapsed;
  (void)c.client->delete_subscription(*sub.id);
  return r;
}

struct SessionsResult {
  std::size_t held = 0;
  double open_seconds = 0;
  std::uint64_t rss = 0;
  std::string first_error;
};

// Opens up to `cap` clients (each its own connection, channel and session), `window` at a time,
// on one loop; counts the ones still connected a second after the last one opened.
SessionsResult measure_sessions(const ServerProcess& server, std::size_t cap, std::size_t window) {
  SessionsResult r;
  sf::net::LoopThread thread;
  std::vector<std::unique_ptr<ua::Client>> clients;
  std::promise<void> all_tried;
  auto tried = all_tried.get_future();
  std::size_t started = 0;
  std::size_t done = 0;
  std::function<void()> open_next;
  open_next = [&] {
    if (started == cap) {
      return;
    }
    auto& client = clients.emplace_back(std::make_unique<ua::Client>(
        thread.loop(), client_config(server.url(), fmt::format("bench session {}", started))));
    ++started;
    client->connect([&](const sf::Status& st) {
      if (!st && r.first_error.empty()) {
        r.first_error = st.error().message;
      }
      if (++done == cap) {
        all_tried.set_value();
      } else {
        open_next();
      }
    });
  };
  const auto start = Clock::now();
  thread.run_sync([&] {
    clients.reserve(cap);
    for (std::size_t i = 0; i < std::min(window, cap); ++i) {
      open_next();
    }
  });
  tried.wait();
  r.open_seconds = seconds_since(start);
  std::this_thread::sleep_for(1s);
  thread.run_sync([&] {
    r.held = static_cast<std::size_t>(std::count_if(clients.begin(), clients.end(), [](const auto& c) {
      return c->state() == ua::ClientState::Connected;
    }));
  });
  r.rss = server.rss();
  // CloseSession on every one, then the clients go (on the loop thread).
  std::promise<void> all_closed;
  auto closed = all_closed.get_future();
  std::size_t closing = clients.size();
  thread.run_sync([&] {
    for (auto& client : clients) {
      client->disconnect([&] {
        if (--closing == 0) {
          all_closed.set_value();
        }
      });
    }
  });
  closed.wait_for(30s);
  thread.run_sync([&] { clients.clear(); });
  return r;
}

// --- the run ------------------------------------------------------------------------

struct Metric {
  std::string key;
  std::string label;
  std::string unit;
  bool higher_is_better = true;
  double ours = 0;
  double node = 0;
};

struct Figures {
  ReadResult read1;
  ReadResult read100;
  NotifyResult notify;
  SessionsResult sessions;
  std::uint64_t idle_rss = 0;
};

// Every measurement against one server, the other one stopped meanwhile.
struct Pair {
  ServerProcess* ours;
  ServerProcess* node;
  template <typename F>
  void each(F&& measure) {
    node->pause();
    measure(*ours, true);
    node->resume();
    ours->pause();
    measure(*node, false);
    ours->resume();
  }
};

std::string format_value(double v, const std::string& unit) {
  if (unit == "MiB") {
    return fmt::format("{:.1f}", v);
  }
  if (unit == "s") {
    return fmt::format("{:.2f}", v);
  }
  if (unit == "%" || unit == "% core" || unit == "us") {
    return fmt::format("{:.1f}", v);
  }
  return fmt::format("{:.0f}", v);
}

int run(const Options& o) {
  const std::string node_version = node_opcua_version(o.where.source_dir);
  ServerProcess ours("ours");
  ServerProcess node("node-opcua");
  progress(fmt::format("starting our server ({})", o.where.smartfactory.string()));
  const std::string vars = std::to_string(o.variables);
  const std::string sessions = std::to_string(o.sessions);
  if (!ours.start(our_server_command(o.where.smartfactory,
                                     {"--bench-variables", vars, "--max-sessions", sessions,
                                      "--max-channels-per-address", sessions, "--security", "none"}),
                  o.where.source_dir, o.verbose, 30s)) {
    progress("our server did not start");
    return 1;
  }
  progress(fmt::format("starting node-opcua {}", node_version));
  if (!node.start(node_server_command(o.where.source_dir, {"--variables", vars, "--max-sessions", sessions}),
                  o.where.source_dir, o.verbose, 120s)) {
    progress("the node-opcua server did not start (node on PATH? npm ci?)");
    return 1;
  }
  std::this_thread::sleep_for(2s);  // both settle: model loaded, timers running

  Figures f_ours;
  Figures f_node;
  Pair pair{&ours, &node};
  auto figures = [&](bool is_ours) -> Figures& { return is_ours ? f_ours : f_node; };

  // Idle RSS, each with the other one stopped.
  pair.each([&](ServerProcess& server, bool is_ours) {
    std::this_thread::sleep_for(500ms);
    figures(is_ours).idle_rss = server.rss();
  });

  const auto phase = [&o](std::string_view name) { return o.only.empty() || o.only == name; };
  const double read_s = o.quick ? 1.0 : o.read_seconds;
  if (phase("reads")) {
    pair.each([&](ServerProcess& server, bool is_ours) {
      progress(fmt::format("{}: reads, {} s per size, {} outstanding", server.name(), read_s, o.depth));
      auto c = connect(server, "bench reads");
      if (!c) {
        return;
      }
      // Optionally, a subscription on another session keeps the server busy meanwhile.
      std::optional<Connection> other;
      if (o.read_with_items > 0 && (other = connect(server, "bench background subscription"))) {
        progress(fmt::format("{}: {} items monitored during the reads: {}", server.name(), o.read_with_items,
                             subscribe(*other, server, o.read_with_items).items));
      }
      // A warm-up of each size (node's JIT, both servers' buffers), then the measured runs.
      auto& client = c->client->client();
      for (const std::size_t n : {std::size_t{1}, std::size_t{100}}) {
        if (o.read_size == 0 || o.read_size == n) {
          (void)measure_reads(server, client, bench_values(c->ns, 0, n), o.depth, 0.5);
        }
      }
      if (o.read_size != 100) {
        figures(is_ours).read1 = measure_reads(server, client, bench_values(c->ns, 0, 1), o.depth, read_s);
      }
      if (o.read_size != 1) {
        figures(is_ours).read100 =
            measure_reads(server, client, bench_values(c->ns, 0, 100), o.depth, read_s);
      }
      c->client->disconnect();
      if (other) {
        other->client->disconnect();
      }
    });
  }

  const double notify_s = o.quick ? 2.0 : o.notify_seconds;
  if (phase("notify")) {
    pair.each([&](ServerProcess& server, bool is_ours) {
      progress(fmt::format("{}: data changes of {} items for {} s", server.name(), o.variables, notify_s));
      auto c = connect(server, "bench data changes");
      if (!c) {
        return;
      }
      figures(is_ours).notify = measure_notifications(*c, server, o.variables, notify_s);
      c->client->disconnect();
    });
  }

  const std::size_t cap = o.quick ? std::min<std::size_t>(o.sessions, 50) : o.sessions;
  if (phase("sessions")) {
    pair.each([&](ServerProcess& server, bool is_ours) {
      progress(fmt::format("{}: opening {} sessions", server.name(), cap));
      figures(is_ours).sessions = measure_sessions(server, cap, 16);
      if (!figures(is_ours).sessions.first_error.empty()) {
        progress(fmt::format("{}: first failed session: {}", server.name(),
                             figures(is_ours).sessions.first_error));
      }
    });
  }
  const bool both_alive = ours.running() && node.running();
  ours.stop();
  node.stop();

  constexpr double kMiB = 1024.0 * 1024.0;
  const double theoretical = static_cast<double>(o.variables) * 10.0;  // a change every 100 ms
  std::vector<Metric> metrics = {
      {"read_1_values_per_s", "Read, 1 value per request", "values/s", true, f_ours.read1.values_per_s,
       f_node.read1.values_per_s},
      {"read_1_cpu_percent", "  server CPU", "% core", false, f_ours.read1.cpu_percent,
       f_node.read1.cpu_percent},
      {"read_1_cpu_us_per_request", "  server CPU per request", "us", false, f_ours.read1.cpu_us_per_request,
       f_node.read1.cpu_us_per_request},
      {"read_1_client_cpu_percent", "  client CPU (this process)", "% core", false,
       f_ours.read1.client_cpu_percent, f_node.read1.client_cpu_percent},
      {"read_100_values_per_s", "Read, 100 values per request", "values/s", true, f_ours.read100.values_per_s,
       f_node.read100.values_per_s},
      {"read_100_cpu_percent", "  server CPU", "% core", false, f_ours.read100.cpu_percent,
       f_node.read100.cpu_percent},
      {"read_100_cpu_us_per_request", "  server CPU per request", "us", false,
       f_ours.read100.cpu_us_per_request, f_node.read100.cpu_us_per_request},
      {"read_100_client_cpu_percent", "  client CPU (this process)", "% core", false,
       f_ours.read100.client_cpu_percent, f_node.read100.client_cpu_percent},
      {"notifications_per_s", fmt::format("Data changes, {} items at 100 ms", o.variables), "notif./s", true,
       f_ours.notify.per_s, f_node.notify.per_s},
      {"notifications_percent", fmt::format("  of the {:.0f}/s produced", theoretical), "%", true,
       100.0 * f_ours.notify.per_s / theoretical, 100.0 * f_node.notify.per_s / theoretical},
      {"notifications_cpu_percent", "  server CPU", "% core", false, f_ours.notify.cpu_percent,
       f_node.notify.cpu_percent},
      {"sessions_held", fmt::format("Sessions held (of {})", cap), "sessions", true,
       static_cast<double>(f_ours.sessions.held), static_cast<double>(f_node.sessions.held)},
      {"sessions_open_s", "  time to open them", "s", false, f_ours.sessions.open_seconds,
       f_node.sessions.open_seconds},
      {"rss_idle_mib", "RSS idle", "MiB", false, static_cast<double>(f_ours.idle_rss) / kMiB,
       static_cast<double>(f_node.idle_rss) / kMiB},
      {"rss_notifications_mib", "RSS loaded (data changes)", "MiB", false,
       static_cast<double>(f_ours.notify.loaded_rss) / kMiB,
       static_cast<double>(f_node.notify.loaded_rss) / kMiB},
      {"rss_sessions_mib", "RSS with the sessions held", "MiB", false,
       static_cast<double>(f_ours.sessions.rss) / kMiB, static_cast<double>(f_node.sessions.rss) / kMiB},
  };
  // Phases left out with --only have nothing to show.
  std::erase_if(metrics, [](const Metric& m) { return m.ours == 0 && m.node == 0; });
  // No ratio when node-opcua's figure is 0 (e.g. CPU below the clock tick).
  auto ratio = [](const Metric& m) {
    return m.node > 0 ? std::optional<double>(m.ours / m.node) : std::nullopt;
  };

  std::string load;
  std::getline(std::ifstream("/proc/loadavg") >> std::ws, load);
  const unsigned cores = std::thread::hardware_concurrency();
  if (o.json) {
    nlohmann::json out;
    out["peer"] = "node-opcua " + node_version;
    out["cores"] = cores;
    out["loadavg"] = load;
    out["quick"] = o.quick;
    out["settings"] = {{"variables", o.variables},      {"read_with_monitored_items", o.read_with_items},
                       {"read_seconds", read_s},        {"read_outstanding", o.depth},
                       {"notify_seconds", notify_s},    {"sessions_cap", cap},
                       {"sessions_opened_at_once", 16}, {"publishing_interval_ms", 100},
                       {"sampling_interval_ms", 100}};
    for (const auto& m : metrics) {
      out["metrics"][m.key] = {{"unit", m.unit},
                               {"ours", m.ours},
                               {"node_opcua", m.node},
                               {"ratio", ratio(m) ? nlohmann::json(*ratio(m)) : nlohmann::json()},
                               {"higher_is_better", m.higher_is_better}};
    }
    out["read_requests"] = {{"ours", f_ours.read1.requests + f_ours.read100.requests},
                            {"node_opcua", f_node.read1.requests + f_node.read100.requests}};
    out["bad_reads"] = {{"ours", f_ours.read1.bad + f_ours.read100.bad},
                        {"node_opcua", f_node.read1.bad + f_node.read100.bad}};
    out["monitored_items_created"] = {{"ours", f_ours.notify.items}, {"node_opcua", f_node.notify.items}};
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("OPC UA server: ours (smartfactory opcua server) vs node-opcua %s, same run, same client\n",
                node_version.c_str());
    std::printf(
        "%u cores, load average %s; reads %.0f s with %zu outstanding (%zu items monitored meanwhile); "
        "data changes %.0f s\n",
        cores, load.c_str(), read_s, o.depth, o.read_with_items, notify_s);
    std::printf("%-36s %-9s %12s %12s %8s\n", "metric", "unit", "ours", "node-opcua", "ratio");
    for (const auto& m : metrics) {
      const auto r = ratio(m);
      std::printf("%-36s %-9s %12s %12s %8s%s\n", m.label.c_str(), m.unit.c_str(),
                  format_value(m.ours, m.unit).c_str(), format_value(m.node, m.unit).c_str(),
                  r ? fmt::format("{:.2f}x", *r).c_str() : "-",
                  m.higher_is_better ? "" : " (lower is better)");
    }
    fmt::print("monitored items created: ours {}, node-opcua {}; bad reads: ours {}, node-opcua {}\n",
               f_ours.notify.items, f_node.notify.items, f_ours.read1.bad + f_ours.read100.bad,
               f_node.read1.bad + f_node.read100.bad);
  }
  if (!both_alive) {
    progress("a server died during the run");
    return 1;
  }
  return 0;
}

void usage() {
  std::fprintf(stderr,
               "usage: bench_opcua_server [--quick] [--json] [--verbose] [--sessions N] [--variables N]\n"
               "                          [--depth N] [--read-seconds S] [--notify-seconds S]\n"
               "                          [--read-with-items N] [--read-size 1|100]\n"
               "                          [--only reads|notify|sessions] [--smartfactory PATH]\n"
               "                          [--source-dir DIR]\n"
               "Our OPC UA server next to node-opcua in the same run (see the top of the source).\n");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const auto own = [&o](std::string_view a, const OptionValue& value) {
    if (a == "--sessions") {
      o.sessions = std::stoul(value());
    } else if (a == "--variables") {
      o.variables = std::stoul(value());
    } else if (a == "--depth") {
      o.depth = std::max<std::size_t>(1, std::stoul(value()));
    } else if (a == "--read-seconds") {
      o.read_seconds = std::stod(value());
    } else if (a == "--notify-seconds") {
      o.notify_seconds = std::stod(value());
    } else if (a == "--read-with-items") {
      o.read_with_items = std::stoul(value());
    } else if (a == "--read-size") {
      o.read_size = std::stoul(value());
    } else if (a == "--only") {
      o.only = value();
    } else {
      return false;
    }
    return true;
  };
  if (const auto exit_status = parse_options(argc, argv, o, usage, own)) {
    return *exit_status;
  }
  if (o.read_size != 0 && o.read_size != 1 && o.read_size != 100) {
    std::fprintf(stderr, "bench_opcua_server: --read-size is 1 or 100\n");
    return 2;
  }
  if (o.read_with_items > o.variables) {
    std::fprintf(stderr, "bench_opcua_server: --read-with-items must not exceed --variables\n");
    return 2;
  }
  if (o.variables < 100) {
    std::fprintf(stderr, "bench_opcua_server: --variables must be at least 100 (a read of 100 values)\n");
    return 2;
  }
  (void)sf::log::set_level("warn");
  ::signal(SIGPIPE, SIG_IGN);
  return run(o);
}
