// `smartfactory line` as a benchmark's child process (bench_line, bench_dashboard): started with
// --json, up once its ready line came (a start that fails on a loaded host is tried again in a
// fresh run directory), with the processes that ready line lists, stopped with SIGTERM.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/process.hpp"
#include "sf/core/result.hpp"

namespace sf::bench {

// One process of the line as its ready line lists it.
struct LineProcessInfo {
  std::string name;   // the machine's name; "plant", "orders"
  std::string role;   // plant, machine, gateway, cloud, orders (factory::LineRole)
  std::string opcua;  // its OPC UA endpoint; empty for the plant
  std::filesystem::path log;
};

// The processes of a `{"event":"ready",...}` line of `smartfactory line --json`; nullopt for any
// other line.
std::optional<std::vector<LineProcessInfo>> ready_processes(std::string_view line);

struct LineStartOptions {
  std::filesystem::path smartfactory;     // the binary
  std::filesystem::path run_dir;          // attempt N runs in run_dir/line-N (stdout: line-N.out)
  std::filesystem::path orders_file;      // the order service's orders at its start; optional
  std::vector<std::string> extra_args;    // more options of `smartfactory line`
  std::chrono::seconds ready_limit{180};  // the whole line up: plant, controllers, order service
  int attempts = 3;
};

class RunningLine {
 public:
  // The line, up. Errors: it did not come up in any attempt (the last one's reason).
  static Result<RunningLine> start(const LineStartOptions& options,
                                   const std::function<void(std::string_view)>& progress = {});

  [[nodiscard]] const std::vector<LineProcessInfo>& processes() const { return processes_; }
  // The process named `name`; nullptr when the line has none.
  [[nodiscard]] const LineProcessInfo* process(std::string_view name) const;
  [[nodiscard]] bool running() const { return line_.running(); }
  // SIGTERM (the supervisor stops every process in reverse order), SIGKILL after `grace`.
  void stop(std::chrono::seconds grace = std::chrono::seconds{120});

 private:
  Status start_attempt(const LineStartOptions& options, const std::filesystem::path& dir);

  Process line_;
  std::vector<LineProcessInfo> processes_;
};

}  // namespace sf::bench
