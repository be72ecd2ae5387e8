// Supervisor (supervisor.hpp): the line's processes started in order, watched, restarted with
// back-off and stopped in reverse order.
#include "sf/factory/supervisor.hpp"

#include <csignal>
#include <fstream>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sf/core/log.hpp"

namespace sf::factory {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string_view to_string(ProcessState state) {
  constexpr std::string_view kNames[] = {"stopped", "starting", "up", "restarting", "failed"};
  return kNames[static_cast<std::size_t>(state)];
}

std::string describe_failure(std::string_view name, std::string_view why,
                             const std::deque<std::string>& tail) {
  std::string text = fmt::format("{} {}", name, why);
  if (tail.empty()) {
    return text + "; its log is empty";
  }
  text += "; its last log lines:";
  for (const auto& line : tail) {
    text += "\n  " + line;
  }
  return text;
}

struct Supervisor::Child {
  SupervisedProcess spec;
  fs::path log;
  Process process;
  ProcessState state = ProcessState::stopped;
  unsigned restarts = 0;
  unsigned failures = 0;          // exits in a row without staying up stable_after
  Clock::time_point since{};      // starting: spawned; up: ready; restarting: when to start again
  std::uintmax_t log_offset = 0;  // read this far
  std::string partial;            // a line not ended yet
  std::deque<std::string> tail;   // its last lines
  std::string opcua;
  std::string last_exit;
};

Supervisor::Supervisor(std::vector<SupervisedProcess> processes, SupervisorOptions options, Clock& clock)
    : options_(std::move(options)), clock_(clock) {
  children_.reserve(processes.size());
  for (auto& p : processes) {
    Child c;
    c.log = options_.log_dir / (p.name + ".log");
    c.spec = std::move(p);
    children_.push_back(std::move(c));
  }
}

Supervisor::~Supervisor() {
  stop();
}

Status Supervisor::start(const std::function<bool()>& cancel) {
  SF_TRY(begin());
  while (!all_up()) {
    if (start_error_) {
      stop();
      return *start_error_;
    }
    if (cancel && cancel()) {
      stop();
      return make_error(Errc::state, "the start was cancelled");
    }
    clock_.sleep_until(clock_.now() + options_.tick);
    poll();
  }
  return {};
}

Status Supervisor::begin() {
  std::error_code ec;
  fs::create_directories(options_.log_dir, ec);
  if (ec) {
    return make_error(Errc::io, fmt::format("log folder {}: {}", options_.log_dir.string(), ec.message()));
  }
  starting_ = true;
  start_error_.reset();
  start_next();
  return start_error_ ? Status(*start_error_) : Status{};
}

// The first process not started yet, once every one before it is up.
void Supervisor::start_next() {
  for (auto& c : children_) {
    if (c.state == ProcessState::stopped) {
      spawn(c);
      return;
    }
    if (c.state != ProcessState::up) {
      return;
    }
  }
  starting_ = false;  // all up: from now on exits are restarted
}

void Supervisor::spawn(Child& c) {
  std::error_code ec;
  c.log_offset = fs::exists(c.log, ec) ? fs::file_size(c.log, ec) : 0;
  c.partial.clear();
  note(c, fmt::format("starting {}", fmt::join(c.spec.argv, " ")));
  ProcessOptions o;
  o.argv = c.spec.argv;
  o.in = Stdio::null();
  o.out = Stdio::file(c.log, true);
  o.err = Stdio::to_stdout();
  o.own_process_group = true;
  o.parent_death_signal = SIGTERM;
  auto p = Process::spawn(std::move(o));
  c.since = clock_.now();
  if (!p) {
    on_exit(c, fmt::format("could not be started: {}", p.error().message));
    return;
  }
  c.process = std::move(*p);
  set_state(c, ProcessState::starting);
}

void Supervisor::note(const Child& c, std::string_view text) const {
  std::ofstream out(c.log, std::ios::app);
  out << "--- line: " << text << " ---\n";
}

void Supervisor::poll() {
  for (auto& c : children_) {
    if (c.state == ProcessState::starting || c.state == ProcessState::up) {
      read_log(c);
      if (auto exited = c.process.wait(0ns)) {
        read_log(c);
        on_exit(c, fmt::format("exited ({})", exited->describe()));
      }
    }
    check_deadlines(c);
  }
  if (starting_ && !start_error_) {
    start_next();
  }
}

void Supervisor::read_log(Child& c) {
  std::ifstream in(c.log, std::ios::binary);
  if (!in) {
    return;
  }
  in.seekg(static_cast<std::streamoff>(c.log_offset));
  std::string chunk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  c.log_offset += chunk.size();
  c.partial += chunk;
  std::size_t start = 0;
  for (auto nl = c.partial.find('\n'); nl != std::string::npos; nl = c.partial.find('\n', start)) {
    std::string line = c.partial.substr(start, nl - start);
    start = nl + 1;
    if (line.starts_with("--- line: ")) {
      continue;  // our own notes
    }
    c.tail.push_back(line);
    while (c.tail.size() > options_.log_tail) {
      c.tail.pop_front();
    }
    if (c.state == ProcessState::starting && c.spec.ready) {
      if (auto info = c.spec.ready(line)) {
        on_ready(c, line, std::move(*info));
      }
    }
  }
  c.partial.erase(0, start);
}

void Supervisor::on_ready(Child& c, std::string_view line, ReadyInfo info) {
  c.opcua = std::move(info.opcua);
  if (c.spec.on_ready) {
    if (auto st = c.spec.on_ready(line); !st) {
      if (starting_) {
        fail_start(c, fmt::format("is up, but: {}", st.error().message));
        return;
      }
      sf::log::get("factory")->warn("{}: {}", c.spec.name, st.error().message);
    }
  }
  c.since = clock_.now();
  set_state(c, ProcessState::up);
}

void Supervisor::on_exit(Child& c, std::string why) {
  c.last_exit = std::move(why);
  if (starting_) {
    fail_start(c, c.last_exit);
    return;
  }
  note(c, fmt::format("{} exited: {}", c.spec.name, c.last_exit));
  c.process = Process();
  ++c.failures;
  if (c.failures >= options_.max_failures) {
    sf::log::get("factory")->error("{}", describe_failure(c.spec.name, "given up", c.tail));
    set_state(c, ProcessState::failed);
    return;
  }
  c.since = clock_.now() + backoff(c.failures);
  set_state(c, ProcessState::restarting);
}

void Supervisor::check_deadlines(Child& c) {
  const auto now = clock_.now();
  switch (c.state) {
    case ProcessState::starting:
      if (now - c.since >= options_.ready_timeout) {
        const auto why =
            fmt::format("was not ready within {} s",
                        std::chrono::duration_cast<std::chrono::seconds>(options_.ready_timeout).count());
        c.process.kill();
        on_exit(c, why);
      }
      return;
    case ProcessState::up:
      if (c.failures > 0 && now - c.since >= options_.stable_after) {
        c.failures = 0;  // healthy again: the back-off starts over
      }
      return;
    case ProcessState::restarting:
      if (now >= c.since) {
        ++c.restarts;
        spawn(c);
      }
      return;
    case ProcessState::stopped:
    case ProcessState::failed:
      return;
  }
}

Clock::duration Supervisor::backoff(unsigned failures) const {
  auto delay = options_.backoff_initial;
  for (unsigned i = 1; i < failures && delay < options_.backoff_max; ++i) {
    delay *= 2;
  }
  return std::min(delay, options_.backoff_max);
}

void Supervisor::fail_start(Child& c, std::string_view why) {
  start_error_ = make_error(Errc::state, describe_failure(c.spec.name, why, c.tail));
  set_state(c, ProcessState::failed);
}

void Supervisor::set_state(Child& c, ProcessState state) {
  if (c.state != state) {
    c.state = state;
    ++changes_;
  }
}

void Supervisor::run(const std::function<bool()>& stop_requested, const std::function<void()>& on_poll) {
  while (!stop_requested()) {
    poll();
    if (on_poll) {
      on_poll();
    }
    clock_.sleep_until(clock_.now() + options_.tick);
  }
}

void Supervisor::stop() {
  starting_ = false;
  for (auto it = children_.rbegin(); it != children_.rend(); ++it) {
    Child& c = *it;
    if (c.process.pid() > 0) {
      const auto status = c.process.terminate(options_.stop_grace);
      c.last_exit = status.describe();
      note(c, fmt::format("{} stopped: {}", c.spec.name, c.last_exit));
    }
    c.process = Process();
    if (c.state != ProcessState::failed) {
      set_state(c, ProcessState::stopped);
    }
  }
}

bool Supervisor::all_up() const {
  for (const auto& c : children_) {
    if (c.state != ProcessState::up) {
      return false;
    }
  }
  return true;
}

std::vector<ProcessStatus> Supervisor::status() const {
  std::vector<ProcessStatus> out;
  const auto now = clock_.now();
  for (const auto& c : children_) {
    ProcessStatus s;
    s.name = c.spec.name;
    s.pid = c.process.pid();
    s.state = c.state;
    s.restarts = c.restarts;
    s.uptime = c.state == ProcessState::up ? now - c.since : Clock::duration{0};
    s.opcua = c.opcua;
    s.last_exit = c.last_exit;
    s.log = c.log;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace sf::factory
