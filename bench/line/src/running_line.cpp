// RunningLine (running_line.hpp): `smartfactory line --json` as a child process, its ready line
// read from its stdout file.
#include "sf/bench/running_line.hpp"

#include <csignal>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/bench/line.hpp"
#include "sf/core/clock.hpp"

namespace sf::bench {

std::optional<std::vector<LineProcessInfo>> ready_processes(std::string_view line) {
  const auto j = nlohmann::json::parse(line, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("event", "") != "ready" || !j.contains("processes") ||
      !j["processes"].is_array()) {
    return std::nullopt;
  }
  std::vector<LineProcessInfo> out;
  for (const auto& p : j["processes"]) {
    if (p.is_object()) {
      out.push_back({p.value("name", ""), p.value("role", ""), p.value("opcua", ""), p.value("log", "")});
    }
  }
  return out;
}

Result<RunningLine> RunningLine::start(const LineStartOptions& options,
                                       const std::function<void(std::string_view)>& progress) {
  auto report = [&](const std::string& what) {
    if (progress) {
      progress(what);
    }
  };
  RunningLine line;
  Status st = make_error(Errc::invalid_argument, "no attempt to start the line");
  for (int attempt = 1; attempt <= options.attempts; ++attempt) {
    const auto dir = options.run_dir / fmt::format("line-{}", attempt);
    report(fmt::format("starting the line in {}", dir.string()));
    st = line.start_attempt(options, dir);
    if (st) {
      return line;
    }
    report(fmt::format("the line did not start ({}): attempt {} of {}", st.error().describe(), attempt,
                       options.attempts));
    line.stop();
  }
  return st.error();
}

Status RunningLine::start_attempt(const LineStartOptions& options, const std::filesystem::path& dir) {
  ProcessOptions p;
  p.argv = {options.smartfactory.string(), "line", "--run-dir", dir.string(), "--json",
            "--status-interval",           "0"};
  if (!options.orders_file.empty()) {
    p.argv.insert(p.argv.end(), {"--orders", options.orders_file.string()});
  }
  p.argv.insert(p.argv.end(), options.extra_args.begin(), options.extra_args.end());
  const auto out = dir.string() + ".out";
  p.out = Stdio::file(out);
  p.err = Stdio::to_stdout();
  p.parent_death_signal = SIGTERM;  // the line stops with the benchmark, however it ends
  auto spawned = Process::spawn(std::move(p));
  if (!spawned) {
    return spawned.error();
  }
  line_ = std::move(*spawned);
  FileLines lines(out);
  auto& clock = SteadyClock::instance();
  const auto limit = clock.now() + options.ready_limit;
  while (clock.now() < limit) {
    for (const auto& l : lines.read_new()) {
      if (auto ready = ready_processes(l)) {
        processes_ = std::move(*ready);
        return {};
      }
    }
    if (!line_.running()) {
      return make_error(Errc::io, fmt::format("the line ended before it was up: see {}", out));
    }
    clock.sleep_until(clock.now() + std::chrono::milliseconds(100));  // the file is polled
  }
  return make_error(Errc::timeout,
                    fmt::format("the line was not up within {} s", options.ready_limit.count()));
}

const LineProcessInfo* RunningLine::process(std::string_view name) const {
  for (const auto& p : processes_) {
    if (p.name == name) {
      return &p;
    }
  }
  return nullptr;
}

void RunningLine::stop(std::chrono::seconds grace) {
  line_.terminate(grace);
}

}  // namespace sf::bench
