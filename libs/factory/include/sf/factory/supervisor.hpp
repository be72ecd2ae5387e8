// Supervisor: keeps a list of processes running, the way `smartfactory line` keeps the line's
// processes (plant, controllers, order service, cloud) running. Processes start in the order of
// the list, each once the one before has printed its ready line (the plant's endpoints before the
// controllers that need them). Each one's stdout and stderr go to a log file of its own, which the
// supervisor reads for the ready line and keeps the last lines of for error messages.
//
// After the start, a process that exits (or, restarted, does not get ready in time) is started
// again after a back-off that doubles from backoff_initial up to backoff_max; one that stayed up
// stable_after counts as healthy again (back-off and failure count start over). After
// max_failures exits in a row it is given up (failed) and the others keep running. stop() ends
// them in reverse order: SIGTERM, SIGKILL after stop_grace (sf::Process::terminate).
//
// Concurrency: one thread uses a Supervisor. poll() never blocks; deadlines (ready timeouts,
// back-offs, stable_after) are read from the Clock, so a ManualClock drives them in tests.
// Children lead their own process group (signals reach what they start) and get SIGTERM when the
// thread that spawned them ends.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/process.hpp"
#include "sf/core/result.hpp"

namespace sf::factory {

enum class ProcessState : std::uint8_t {
  stopped,     // not started yet, or stopped on request
  starting,    // running, its ready line not seen yet
  up,          // its ready line seen
  restarting,  // exited; started again when its back-off ends
  failed,      // given up: it did not come up at the start, or exited max_failures times in a row
};
// "stopped", "starting", "up", "restarting", "failed"
std::string_view to_string(ProcessState state);

// What a process's ready line says about it.
struct ReadyInfo {
  std::string opcua;  // its OPC UA endpoint URL, when it has one
};

struct SupervisedProcess {
  std::string name;  // also its log file's name: <log_dir>/<name>.log
  std::vector<std::string> argv;
  // Takes a line of its output; the ready information when it is the ready line.
  std::function<std::optional<ReadyInfo>(std::string_view line)> ready;
  // Runs on every ready line before the next process starts (e.g. writes the configuration files
  // of the processes that need its addresses). An error during the start ends the start.
  std::function<Status(std::string_view line)> on_ready;
};

struct SupervisorOptions {
  std::filesystem::path log_dir;
  Clock::duration ready_timeout = std::chrono::seconds{30};
  Clock::duration backoff_initial = std::chrono::milliseconds{500};
  Clock::duration backoff_max = std::chrono::seconds{10};
  Clock::duration stable_after = std::chrono::seconds{10};
  unsigned max_failures = 10;
  std::chrono::nanoseconds stop_grace = std::chrono::seconds{5};  // real time (Process::terminate)
  Clock::duration tick = std::chrono::milliseconds{50};           // start() and run() poll this often
  std::size_t log_tail = 10;                                      // lines kept for error messages
};

struct ProcessStatus {
  std::string name;
  pid_t pid = -1;
  ProcessState state = ProcessState::stopped;
  unsigned restarts = 0;
  Clock::duration uptime{0};  // since its ready line (0 unless up)
  std::string opcua;          // from its last ready line
  std::string last_exit;      // "exited (exit code 3)", "was not ready within 30 s"; empty before
  std::filesystem::path log;
};

class Supervisor {
 public:
  Supervisor(std::vector<SupervisedProcess> processes, SupervisorOptions options, Clock& clock);
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;

  // Starts the processes in order and returns once all are up. Errors, after everything started
  // was stopped: a process that could not be spawned, exited or was not ready within
  // ready_timeout (the message names it and quotes its last log lines); Errc::state when
  // `cancel` returned true first.
  Status start(const std::function<bool()>& cancel = {});
  // The non-blocking start: spawns the first process; poll() starts the others in turn.
  Status begin();
  // One round: reads the logs, notices exits and ready lines, kills a process past its ready
  // timeout, starts what is due. Never blocks.
  void poll();
  // poll() every tick until `stop` returns true, calling `on_poll` after each round.
  void run(const std::function<bool()>& stop, const std::function<void()>& on_poll);
  // SIGTERM in reverse order, SIGKILL after stop_grace; every process ends stopped (or failed).
  void stop();

  // The error that ended the start (begin() + poll()), if one did.
  [[nodiscard]] const std::optional<Error>& start_error() const { return start_error_; }
  [[nodiscard]] bool all_up() const;
  [[nodiscard]] std::vector<ProcessStatus> status() const;
  // Counts state changes: a caller prints the status when it moved.
  [[nodiscard]] std::uint64_t changes() const { return changes_; }

 private:
  struct Child;

  void spawn(Child& c);
  void read_log(Child& c);
  void on_exit(Child& c, std::string why);
  void on_ready(Child& c, std::string_view line, ReadyInfo info);
  void check_deadlines(Child& c);
  void start_next();
  void fail_start(Child& c, std::string_view why);
  void set_state(Child& c, ProcessState state);
  void note(const Child& c, std::string_view text) const;
  [[nodiscard]] Clock::duration backoff(unsigned failures) const;

  std::vector<Child> children_;
  SupervisorOptions options_;
  Clock& clock_;
  bool starting_ = false;  // in the start: the processes come up one by one, none is restarted
  std::optional<Error> start_error_;
  std::uint64_t changes_ = 0;
};

// The process's state and the last lines of its log, for errors: "conveyor1 (exit code 2); its
// last log lines:\n  ...".
std::string describe_failure(std::string_view name, std::string_view why,
                             const std::deque<std::string>& tail);

}  // namespace sf::factory
