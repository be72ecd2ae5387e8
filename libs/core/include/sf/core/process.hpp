// Process: a child program, started with fork + execve and always reaped. The one place in the
// tree that starts processes: peers of tests (node-opcua, PostgreSQL, DDS peers), the processes of
// benchmarks (contractors, ddsperf, Jena) and the processes a supervisor keeps running.
//
// What it offers over posix_spawn: a Linux scheduling policy for the child (posix_spawn takes only
// SCHED_OTHER, FIFO and RR), a parent-death signal (prctl PR_SET_PDEATHSIG, which posix_spawn has
// no attribute for), its own process group, and a start that fails with the child's errno
// (a close-on-exec pipe reports why execve failed) instead of a child that exits 127.
//
// Waiting uses a pidfd (pidfd_open(2), Linux 5.3): wait(timeout) polls it, so nothing sleeps in a
// loop and a pid is never signalled after it was reaped. Output on pipes is read line by line with
// a timeout; stdout and stderr are drained together, so a child that fills one pipe while we wait
// on the other does not stall.
//
// Concurrency: one thread uses a Process at a time (it is a value, like a file). A Process that is
// destroyed while its child runs terminates it (SIGTERM, SIGKILL after kDestroyGrace) and reaps it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"

namespace sf {

// Where one of the child's standard streams goes (or, for stdin, comes from).
struct Stdio {
  enum class Kind {
    inherit,    // ours
    null,       // /dev/null
    pipe,       // to this process: Process::read_line / write_stdin
    file,       // a file (output streams only), created 0644, truncated unless `append`
    to_stdout,  // stderr only: wherever stdout goes (2>&1)
  };
  Kind kind = Kind::inherit;
  std::filesystem::path path;  // Kind::file
  bool append = false;         // Kind::file

  static Stdio inherit() { return {}; }
  static Stdio null() { return {Kind::null, {}, false}; }
  static Stdio pipe() { return {Kind::pipe, {}, false}; }
  static Stdio file(std::filesystem::path path, bool append = false) {
    return {Kind::file, std::move(path), append};
  }
  static Stdio to_stdout() { return {Kind::to_stdout, {}, false}; }
};

// The Linux scheduling policy the child starts under (sched(7)); its threads inherit it.
enum class SchedulingPolicy {
  inherit,  // ours
  normal,   // SCHED_OTHER
  batch,    // SCHED_BATCH: never preempts on wake-up, for throughput work that must not disturb
  idle,     // SCHED_IDLE: runs only when nothing else wants the CPU
};
// "inherit", "normal", "batch", "idle"
std::string_view to_string(SchedulingPolicy policy);
std::optional<SchedulingPolicy> scheduling_policy_from_string(std::string_view text);

struct ProcessOptions {
  // argv[0] is looked up on PATH unless it holds a '/'.
  std::vector<std::string> argv;
  // "NAME=value" entries added to this process's environment (replacing a variable of that name).
  std::vector<std::string> env;
  std::filesystem::path cwd;  // empty: ours
  Stdio in = Stdio::inherit();
  Stdio out = Stdio::inherit();
  Stdio err = Stdio::inherit();
  SchedulingPolicy scheduling = SchedulingPolicy::inherit;
  // Sent to the child when the *thread* that spawned it ends (prctl PR_SET_PDEATHSIG): spawn from a
  // thread that lives as long as the child should. Not kept across a set-uid execve.
  std::optional<int> parent_death_signal;
  // The child leads a new process group (setpgid): signal() and terminate() reach its descendants.
  bool own_process_group = false;
};

// How a reaped child ended, with what it used (getrusage(2) of the child and the descendants
// it waited for).
struct ExitStatus {
  std::optional<int> code;               // its exit code, when it exited
  std::optional<int> signal;             // the signal that ended it, when one did
  std::chrono::nanoseconds cpu_time{0};  // user + system
  std::int64_t max_rss_kib = 0;          // peak resident set

  [[nodiscard]] bool success() const { return code == 0; }
  // The shell's $?: the exit code, or 128 + the signal.
  [[nodiscard]] int shell_code() const;
  // "exit code 3", "signal 9 (Killed)"
  [[nodiscard]] std::string describe() const;
};

// What Process::run collected.
struct Completed {
  ExitStatus status;
  std::string out;  // stdout, when it was a pipe (with stderr, when that went to stdout)
  std::string err;  // stderr, when it was a pipe
};

enum class Stream { out, err };

// The program `name` names: itself if it holds a '/', otherwise the first executable of that name
// on $PATH (as execvp would find it); nullopt when there is none.
std::optional<std::filesystem::path> find_program(std::string_view name);

class Process {
 public:
  static constexpr std::chrono::seconds kDestroyGrace{10};

  // Starts the program. Errors (Errc::io, naming argv[0]): no such program, not executable, a
  // cwd or file that cannot be opened, a policy the system refuses.
  static Result<Process> spawn(ProcessOptions options);
  // Runs the program to its end with stdout on a pipe (unless options.out says otherwise) and
  // returns what it wrote there (and on stderr, when that is a pipe or goes to stdout).
  // Errc::timeout when it is still running after `timeout`: then it is killed.
  static Result<Completed> run(ProcessOptions options, std::chrono::nanoseconds timeout);

  Process() = default;  // no process
  Process(Process&& other) noexcept;
  Process& operator=(Process&& other) noexcept;
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;
  ~Process();

  // The child's pid while it has not been reaped, else -1.
  [[nodiscard]] pid_t pid() const { return pid_; }
  // Started and not yet exited (an exited child that was not waited for is not running).
  [[nodiscard]] bool running() const;
  [[nodiscard]] const std::string& name() const { return name_; }

  // Sends `sig` to the child (its group with own_process_group); ignored once reaped.
  Status signal(int sig) const;
  // Waits up to `timeout` for the child to exit and reaps it. Errc::timeout when it still runs;
  // Errc::state when there is no child.
  Result<ExitStatus> wait(std::chrono::nanoseconds timeout);
  // SIGCONT + SIGTERM (a stopped process cannot act on SIGTERM), SIGKILL when it is still there
  // after `grace`, and reaps it. Without a child: the status it was reaped with, if any.
  ExitStatus terminate(std::chrono::nanoseconds grace);
  // SIGKILL and reap: the child dies at once.
  ExitStatus kill();
  // Closes stdin and waits up to `grace` for the child to end by itself (peers that end on EOF),
  // SIGKILL after that; reaps it.
  ExitStatus close_and_wait(std::chrono::nanoseconds grace);
  // The status of the last wait that reaped the child.
  [[nodiscard]] const std::optional<ExitStatus>& exit_status() const { return exit_status_; }

  // stdin on a pipe: writes all of `bytes` (blocking), or closes it (peers that exit on EOF go).
  Status write_stdin(std::string_view bytes);
  void close_stdin();

  // The next line (without its '\n') of a piped stream, waiting up to `timeout`. Errc::timeout
  // when no full line came in time; Errc::state when the stream ended (a last line without
  // '\n' is still returned first).
  Result<std::string> read_line(std::chrono::nanoseconds timeout, Stream stream = Stream::out);
  // Reads lines until `accept` takes one (returned), the stream ends or `timeout` passes (errors as
  // read_line). Lines after the accepted one wait for the next read.
  Result<std::string> wait_for_line(const std::function<bool(const std::string&)>& accept,
                                    std::chrono::nanoseconds timeout, Stream stream = Stream::out);
  // Everything left on a piped stream until it ends (Errc::timeout if it does not in time).
  Result<std::string> read_to_end(std::chrono::nanoseconds timeout, Stream stream = Stream::out);

 private:
  struct Pipe {
    int fd = -1;         // -1 once the stream ended
    bool piped = false;  // the stream is a pipe to us
    std::string unread;  // read, not yet returned
    [[nodiscard]] bool ended() const { return fd < 0; }
    void read_some();
  };

  Pipe& pipe_of(Stream stream) { return stream == Stream::out ? out_ : err_; }
  // Reads what the piped streams have until `done` holds; false when `deadline` passes or the
  // streams end first.
  bool pump_until(const std::function<bool()>& done, std::chrono::steady_clock::time_point deadline);
  void reap(ExitStatus status);
  // Terminates a child still running and closes every descriptor.
  void release();
  void close_all();

  std::string name_;  // argv[0], for messages
  pid_t pid_ = -1;
  int pidfd_ = -1;
  bool group_ = false;
  int in_ = -1;
  Pipe out_;
  Pipe err_;
  std::optional<ExitStatus> exit_status_;
};

}  // namespace sf
