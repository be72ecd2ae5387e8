// Shared by the OPC UA benchmarks (bench_opcua_server, bench_opcua_security): servers as child
// processes (sf::Process), the CPU time of a process, Read throughput with requests kept
// outstanding, and where things are.
#pragma once

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/core/process.hpp"
#include "sf/opcua/client/client.hpp"

namespace opcua_bench {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU time (user + system) process `pid` used so far, in seconds.
inline double cpu_seconds_of(pid_t pid) {
  std::ifstream stat(fmt::format("/proc/{}/stat", pid));
  std::string text;
  std::getline(stat, text);
  // The fields after the command name (in parentheses, may hold spaces): state is field 3,
  // utime 14 and stime 15, in clock ticks.
  const auto close = text.rfind(')');
  if (close == std::string::npos || close + 2 >= text.size()) {
    return 0;
  }
  std::istringstream fields(text.substr(close + 2));
  std::string field;
  double ticks = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i >= 14) {
      ticks += std::stod(field);
    }
  }
  return ticks / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// A server as a child process. Ready once it prints its port on stdout: node_server.mjs prints
// "READY <port>", `smartfactory opcua server` prints "listening on opc.tcp://<host>:<port>".
class ServerProcess {
 public:
  explicit ServerProcess(std::string name) : name_(std::move(name)) {}
  ~ServerProcess() { stop(); }  // our server does not exit on stdin's end, only on SIGTERM
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  bool start(const std::vector<std::string>& args, const std::filesystem::path& cwd, bool verbose,
             std::chrono::seconds timeout) {
    sf::ProcessOptions o;
    o.argv = args;
    o.cwd = cwd;
    o.in = sf::Stdio::pipe();
    o.out = sf::Stdio::pipe();
    o.err = verbose ? sf::Stdio::inherit() : sf::Stdio::null();
    auto started = sf::Process::spawn(std::move(o));
    if (!started) {
      return false;
    }
    process_ = std::move(*started);
    paused_ = false;
    return process_
        .wait_for_line(
            [this](const std::string& line) {
              const auto ready = line.find("READY ");
              const auto listening = line.find("listening on ");
              const auto colon = line.rfind(':');
              if (ready != std::string::npos) {
                port_ = static_cast<std::uint16_t>(std::stoul(line.substr(ready + 6)));
              } else if (listening != std::string::npos && colon != std::string::npos) {
                port_ = static_cast<std::uint16_t>(std::stoul(line.substr(colon + 1)));
              }
              return port_ != 0;
            },
            timeout)
        .ok();
  }

  // Closes stdin (node_server.mjs exits then) and sends SIGTERM; SIGKILL after 10 s.
  void stop() {
    process_.close_stdin();
    process_.terminate(std::chrono::seconds(10));
  }

  // SIGSTOP / SIGCONT: the server takes no CPU while the other one is measured.
  void pause() {
    if (!paused_) {
      (void)process_.signal(SIGSTOP);
      paused_ = true;
    }
  }
  void resume() {
    if (paused_) {
      (void)process_.signal(SIGCONT);
      paused_ = false;
    }
  }

  // VmRSS in bytes (0 when unknown).
  [[nodiscard]] std::uint64_t rss() const {
    std::ifstream status(fmt::format("/proc/{}/status", process_.pid()));
    std::string line;
    while (std::getline(status, line)) {
      if (line.rfind("VmRSS:", 0) == 0) {
        return std::stoull(line.substr(6)) * 1024;
      }
    }
    return 0;
  }

  [[nodiscard]] double cpu_seconds() const { return cpu_seconds_of(process_.pid()); }

  [[nodiscard]] bool running() const { return process_.running(); }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] std::string url() const { return fmt::format("opc.tcp://127.0.0.1:{}", port_); }

 private:
  std::string name_;
  sf::Process process_;
  std::uint16_t port_ = 0;
  bool paused_ = false;
};

struct ReadResult {
  double values_per_s = 0;
  double cpu_percent = 0;         // the server's, of one core
  double client_cpu_percent = 0;  // this process's (the client's loop thread), of one core
  double cpu_us_per_request = 0;  // the server's CPU time over every request it answered meanwhile
  std::uint64_t requests = 0;
  std::uint64_t bad = 0;  // failed requests or values with a Bad status
};

// `depth` ReadRequests of `per_request` values outstanding for `seconds`; values whose response
// arrived within the window count.
inline ReadResult measure_reads(const ServerProcess& server, sf::opcua::Client& client,
                                std::vector<sf::opcua::ReadValueId> items, std::size_t depth,
                                double seconds) {
  struct State {
    sf::opcua::Client* client = nullptr;
    std::vector<sf::opcua::ReadValueId> items;
    std::chrono::steady_clock::time_point end;
    std::uint64_t values = 0;
    std::uint64_t requests = 0;
    std::uint64_t answered = 0;  // also those after the window, while the last ones drain
    std::uint64_t bad = 0;
    std::size_t outstanding = 0;
    std::promise<void> finished;
    std::function<void()> issue;
  };
  auto state = std::make_shared<State>();
  state->client = &client;
  state->items = std::move(items);
  state->issue = [s = state.get()] {
    ++s->outstanding;
    s->client->read(s->items, [s](sf::Result<std::vector<sf::opcua::DataValue>> values) {
      --s->outstanding;
      ++s->answered;
      if (std::chrono::steady_clock::now() <= s->end) {
        ++s->requests;
        if (!values) {
          ++s->bad;
        } else {
          for (const auto& v : *values) {
            (v.status.is_bad() ? s->bad : s->values) += 1;
          }
        }
        s->issue();
      } else if (s->outstanding == 0) {
        s->finished.set_value();
      }
    });
  };
  auto finished = state->finished.get_future();
  const double cpu = server.cpu_seconds();
  const double client_cpu = cpu_seconds_of(::getpid());
  const auto start = std::chrono::steady_clock::now();
  state->end = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double>(seconds));
  for (std::size_t i = 0; i < depth; ++i) {
    state->issue();  // Client::read posts to the client's loop
  }
  finished.wait();
  ReadResult r;
  const double server_cpu = server.cpu_seconds() - cpu;
  r.cpu_percent = 100.0 * server_cpu / seconds_since(start);
  r.cpu_us_per_request = state->answered > 0 ? 1e6 * server_cpu / static_cast<double>(state->answered) : 0;
  r.client_cpu_percent = 100.0 * (cpu_seconds_of(::getpid()) - client_cpu) / seconds_since(start);
  r.values_per_s = static_cast<double>(state->values) / seconds;
  r.requests = state->requests;
  r.bad = state->bad;
  state->issue = nullptr;
  return r;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string node_opcua_version(const std::filesystem::path& source_dir) {
  try {
    const auto j =
        nlohmann::json::parse(read_text(source_dir / "node_modules" / "node-opcua" / "package.json"));
    return j.value("version", "?");
  } catch (const std::exception&) {
    return "?";
  }
}

inline std::filesystem::path self_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::current_path() : exe.parent_path();
}

// `smartfactory opcua server` with the demo model on 127.0.0.1 and a free port, and `extra`.
inline std::vector<std::string> our_server_command(const std::filesystem::path& smartfactory,
                                                   const std::vector<std::string>& extra) {
  std::vector<std::string> args = {smartfactory.string(),
                                   "--log-level",
                                   "warn",
                                   "opcua",
                                   "server",
                                   "--host",
                                   "127.0.0.1",
                                   "--advertised-host",
                                   "127.0.0.1",
                                   "--port",
                                   "0",
                                   "--demo-model",
                                   "--status-interval",
                                   "0"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// tests/peers/opcua/node_server.mjs (the same demo model) on a free port, with `extra`.
inline std::vector<std::string> node_server_command(const std::filesystem::path& source_dir,
                                                    const std::vector<std::string>& extra) {
  std::vector<std::string> args = {
      "node", (source_dir / "tests" / "peers" / "opcua" / "node_server.mjs").string(), "0"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Where the benchmarks find `smartfactory` (next to them in the build tree) and the source tree
// (SF_SOURCE_DIR, else the one the build was configured from), unless told otherwise.
struct Locations {
  std::filesystem::path smartfactory = self_dir() / ".." / "apps" / "smartfactory" / "smartfactory";
  std::filesystem::path source_dir;

  explicit Locations(const char* configured_source_dir) {
    const char* source = std::getenv("SF_SOURCE_DIR");
    source_dir = source != nullptr ? source : configured_source_dir;
  }
};

// What every OPC UA benchmark takes: --quick, --json, --verbose, --smartfactory PATH and
// --source-dir DIR.
struct CommonOptions {
  bool quick = false;
  bool json = false;
  bool verbose = false;  // the servers' stderr goes to ours
  Locations where;

  explicit CommonOptions(const char* configured_source_dir) : where(configured_source_dir) {}
};

using OptionValue = std::function<std::string()>;
// A benchmark's own options: `value()` takes the option's argument; false when `name` is unknown.
using OwnOption = std::function<bool(std::string_view name, const OptionValue& value)>;

// Parses argv into `common` and through `own`; Google Benchmark's --benchmark_* (scripts/bench
// passes its arguments to every benchmark) are ignored. nullopt to go on, or the exit status
// after usage(): 0 for --help, 2 for an unknown option, a missing argument or a bad number.
inline std::optional<int> parse_options(int argc, char** argv, CommonOptions& common, void (*usage)(),
                                        const OwnOption& own) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    const OptionValue value = [&]() -> std::string {
      if (i + 1 >= argc) {
        throw std::invalid_argument("missing argument");
      }
      return argv[++i];
    };
    try {
      if (a == "--quick") {
        common.quick = true;
      } else if (a == "--json") {
        common.json = true;
      } else if (a == "--verbose") {
        common.verbose = true;
      } else if (a == "--smartfactory") {
        common.where.smartfactory = value();
      } else if (a == "--source-dir") {
        common.where.source_dir = value();
      } else if (a.rfind("--benchmark_", 0) != 0 && !own(a, value)) {
        usage();
        return a == "--help" || a == "-h" ? 0 : 2;
      }
    } catch (const std::exception&) {
      usage();
      return 2;
    }
  }
  return std::nullopt;
}

}  // namespace opcua_bench
