// `smartfactory demo`: the candy factory as processes on this host (`smartfactory line` on the
// default layout with the order service and the cloud writing to SQLite), fed a seeded stream of
// generated orders; progress while it runs, a summary at the end. This file parses options and
// prints; the factory module plans and supervises the line, the order service counts.
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "sf/core/clock.hpp"
#include "sf/factory/line_hosts.hpp"
#include "sf/factory/line_supervisor.hpp"
#include "sf/factory/line_view.hpp"
#include "sf/factory/order.hpp"
#include "sf/line/ontology.hpp"
#include "sf/opcua/security/users.hpp"
#include "sf/opcua/server/session.hpp"

namespace sf::app {
namespace {

namespace fs = std::filesystem;
namespace fy = sf::factory;
using nlohmann::json;

constexpr const char* kDemoHelp =
    "The candy factory as processes on this host: the plant (the line's hardware), SCARA Robot 1's\n"
    "IPC (our EtherCAT master), a gateway per PLC (Modbus), the order service (the products,\n"
    "negotiating over DDS) and the cloud (historian in SQLite), all supervised as by\n"
    "`smartfactory line`. A seeded stream of generated orders (box type, candy types and\n"
    "quantities) goes to the order service; progress is printed while the line makes them and a\n"
    "summary at the end: orders done, failed and lost, lead time p50/p99, throughput, each\n"
    "machine's utilisation (the share of the run it had a job in work). Ends after\n"
    "--orders are finished, after --duration seconds, or on Ctrl-C. The run directory keeps every\n"
    "process's configuration and log and the historian (smartfactory history query --db ...).\n"
    "With --hosts (root), each process runs in a network namespace of its own with an interface\n"
    "per protocol, as `smartfactory line --hosts` (its --help has the networks and addresses).\n"
    "Exit: 0 when every order was done, 1 when one failed or was lost, 2 on bad options.";

struct DemoOptions {
  std::size_t orders = 20;
  double duration_s = 0;
  std::uint64_t seed = 1;
  std::string run_dir;
  bool json = false;
  bool hosts = false;
  int http_port = -1;
  std::string web_users;
  fs::path tls_cert;
  fs::path tls_key;
};

// A users file for the dashboard when none is given: one operator with a random password, said
// on stderr (the demo's own run directory; nothing outside it).
Result<fs::path> demo_users(const fs::path& run_dir) {
  std::string password;
  for (auto b : opcua::server::random_bytes(9)) {
    password += fmt::format("{:02x}", b);
  }
  auto hash = opcua::security::hash_password(password);
  if (!hash) {
    return hash.error();
  }
  opcua::security::UserDatabase users;
  SF_TRY(users.put({"operator", *hash, {}, {"operator"}}));
  const fs::path file = run_dir / "web-users.yaml";
  SF_TRY(users.save(file));
  std::cerr << fmt::format("demo: dashboard user 'operator', password {} ({})\n", password, file.string());
  return file;
}

json utilisation_json(const std::vector<fy::WorkingTime>& working, double seconds) {
  json u = json::object();
  for (const auto& w : working) {
    u[w.machine] = seconds > 0 ? w.seconds / seconds : 0.0;
  }
  return u;
}

json summary_json(const fy::OrderCounts& c, std::size_t orders, double seconds) {
  return {{"event", "summary"},
          {"orders", orders},
          {"done", c.done},
          {"failed", c.failed},
          {"lost", orders - std::min<std::size_t>(orders, c.done + c.failed)},
          {"remade", c.remade},
          {"lead_time_s", {{"p50", c.lead_p50}, {"p99", c.lead_p99}}},
          {"boxes_per_hour", seconds > 0 ? c.done * 3600.0 / seconds : 0.0},
          {"seconds", seconds}};
}

Result<fy::LinePlan> plan(const DemoOptions& o, const fs::path& run_dir) {
  fy::LineOptions line;
  line.run_dir = run_dir;
  std::error_code ec;
  line.program = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    return make_error(Errc::io, fmt::format("cannot find this program: {}", ec.message()));
  }
  line.opcua_base_port = 0;
  line.historian = fmt::format("sqlite:{}", fs::absolute(run_dir / "history.db").string());
  line.orders_file = run_dir / "orders.yaml";
  line.hosts = o.hosts;
  line.http_port = o.http_port;
  line.web_users = o.web_users;
  line.tls_cert = o.tls_cert;
  line.tls_key = o.tls_key;
  if (o.http_port >= 0 && o.web_users.empty()) {
    fs::create_directories(run_dir, ec);
    auto users = demo_users(run_dir);
    if (!users) {
      return users.error();
    }
    line.web_users = *users;
  }
  auto layout = line::default_layout();
  if (!layout) {
    return layout.error();
  }
  fy::OrderGenerator generator(layout->catalog, o.seed, "demo");
  std::vector<fy::Order> orders;
  orders.reserve(o.orders);
  for (std::size_t i = 0; i < o.orders; ++i) {
    orders.push_back(generator.next());
  }
  fs::create_directories(run_dir, ec);
  std::ofstream(line.orders_file) << fy::orders_yaml(orders);
  auto p = fy::plan_line(line);
  if (!p) {
    return p.error();
  }
  SF_TRY(fy::prepare_run_dir(*p));
  return p;
}

int run_demo(const DemoOptions& o) {
  if (o.orders == 0) {
    std::cerr << "demo: --orders must be at least 1\n";
    return kExitUsage;
  }
  if (auto st = o.hosts ? fy::hosts_supported() : Status{}; !st) {
    std::cerr << "demo: " << st.error().message << "\n";
    return kExitUsage;
  }
  fs::path run_dir = o.run_dir;
  if (run_dir.empty()) {
    std::string tmpl = (fs::temp_directory_path() / "smartfactory-demo-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) {
      std::cerr << "demo: cannot make a run directory\n";
      return kExitFailure;
    }
    run_dir = tmpl;
  }
  auto p = plan(o, run_dir);
  if (!p) {
    std::cerr << "demo: " << p.error().message << "\n";
    return kExitUsage;
  }
  std::cerr << fmt::format("demo: {} orders on the line {}; {} processes; run directory {}\n", o.orders,
                           p->layout.line, p->processes.size(), run_dir.string());
  install_stop_signals();
  std::unique_ptr<fy::HostNetworks> networks;  // removed after the supervisor stopped everything
  if (p->hosts) {
    auto made = fy::HostNetworks::create(*p->hosts);
    if (!made) {
      std::cerr << "demo: " << made.error().message << "\n";
      return kExitFailure;
    }
    networks = std::move(*made);
  }
  auto& clock = SteadyClock::instance();
  fy::Supervisor supervisor(fy::supervised_processes(*p), fy::line_supervisor_options(*p), clock);
  if (auto st = supervisor.start(stop_requested); !st) {
    std::cerr << "demo: " << st.error().message << "\n";
    return stop_requested() ? kExitOk : kExitFailure;
  }
  std::cerr << "demo: the line is up; orders go in\n";
  if (o.http_port > 0) {
    std::cerr << fmt::format("demo: dashboard on {}://127.0.0.1:{}/\n", o.tls_cert.empty() ? "http" : "https",
                             o.http_port);
  }
  auto opened = fy::LineView::open(*p);
  if (!opened) {
    std::cerr << "demo: " << opened.error().message << "\n";
    return kExitFailure;
  }
  auto& view = *opened;
  const auto started = clock.now();
  const auto limit =
      o.duration_s > 0
          ? std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.duration_s))
          : Clock::duration::max();
  fy::OrderCounts last{};
  fy::OrderCounts now{};
  auto next_read = started;
  bool finished = false;
  supervisor.run([&] { return stop_requested() || finished || clock.now() - started >= limit; },
                 [&] {
                   if (clock.now() < next_read) {
                     return;
                   }
                   next_read = clock.now() + std::chrono::seconds{1};
                   auto c = view.orders();
                   if (!c) {
                     return;  // the service restarting: asked again in a second
                   }
                   now = *c;
                   finished = now.done + now.failed >= o.orders;
                   if (now == last) {
                     return;
                   }
                   last = now;
                   const double t = std::chrono::duration<double>(clock.now() - started).count();
                   if (o.json) {
                     std::cout << json{{"event", "progress"},    {"t", t},
                                       {"done", now.done},       {"failed", now.failed},
                                       {"in_work", now.in_work}, {"queued", now.queued}}
                                      .dump()
                               << std::endl;
                   } else {
                     std::cout << fmt::format("{:7.1f} s  {} done, {} failed, {} in work, {} queued\n", t,
                                              now.done, now.failed, now.in_work, now.queued)
                               << std::flush;
                   }
                 });
  const double seconds = std::chrono::duration<double>(clock.now() - started).count();
  const auto working = view.working_times();
  supervisor.stop();
  json s = summary_json(now, o.orders, seconds);
  s["utilisation"] = utilisation_json(working, seconds);
  if (o.json) {
    std::cout << s.dump() << std::endl;
  } else {
    std::cout << fmt::format(
        "orders: {} done, {} failed, {} lost of {} ({} boxes remade)\n"
        "lead time: p50 {:.1f} s, p99 {:.1f} s\nthroughput: {:.1f} boxes/hour\n"
        "run directory: {} (logs, configurations; historian {}/history.db)\n",
        now.done, now.failed, s["lost"].get<std::size_t>(), o.orders, now.remade, now.lead_p50, now.lead_p99,
        s["boxes_per_hour"].get<double>(), run_dir.string(), run_dir.string());
    std::cout << "utilisation (time with a job in work):";
    for (const auto& [machine, share] : s["utilisation"].items()) {
      std::cout << fmt::format(" {} {:.0f}%", machine, 100.0 * share.get<double>());
    }
    std::cout << "\n";
  }
  return now.failed == 0 && now.done >= o.orders ? kExitOk : kExitFailure;
}

}  // namespace

void register_demo(CLI::App& app, CommandResult& result) {
  auto o = std::make_shared<DemoOptions>();
  auto* cmd = app.add_subcommand("demo", "The candy factory as processes on this host, fed generated orders");
  cmd->add_option("--orders", o->orders, "Orders to make")->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "Stop after this many seconds (0 = when the orders are made)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seed", o->seed, "Seed of the order stream")->capture_default_str();
  cmd->add_option("--run-dir", o->run_dir,
                  "Where configurations, logs and the historian go (default: a new temp dir)");
  cmd->add_flag("--json", o->json, "Progress and summary as JSON lines");
  cmd->add_flag("--hosts", o->hosts, "Each process in a network namespace of its own (root; see below)");
  cmd->add_option("--http", o->http_port,
                  "The cloud's dashboard on this port (-1 = off); --duration keeps it up after the orders")
      ->capture_default_str();
  cmd->add_option("--web-users", o->web_users,
                  "Users of the dashboard (default: a file with one operator, its password printed)");
  add_tls_options(cmd, o->tls_cert, o->tls_key);
  cmd->footer(kDemoHelp);
  cmd->callback([o, &result] { result.exit_code = run_demo(*o); });
}

}  // namespace sf::app
