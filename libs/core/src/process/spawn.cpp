// Process::spawn: fork + execve with what the child needs prepared before fork, and its failure
// before execve reported over a close-on-exec pipe. The rest of Process is in process.cpp.
#include "sf/core/process.hpp"
#include "sf/core/text.hpp"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdlib>
#include <system_error>
#include <utility>

extern char** environ;  // NOLINT(readability-redundant-declaration): execve's environment

namespace sf {
namespace {

// A file descriptor closed when it goes out of scope.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  Fd(Fd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  Fd& operator=(Fd&& o) noexcept {
    reset(std::exchange(o.fd_, -1));
    return *this;
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }
  void reset(int fd = -1) {
    if (fd_ >= 0) {
      ::close(fd_);
    }
    fd_ = fd;
  }
  [[nodiscard]] int get() const { return fd_; }
  int release() { return std::exchange(fd_, -1); }

 private:
  int fd_ = -1;
};

// What the child gets as fd 0, 1 and 2, and the parent's ends of the pipes.
struct StdioFds {
  std::array<Fd, 3> child;  // -1: inherit (or, for 2, a copy of 1)
  Fd parent_in;
  Fd parent_out;
  Fd parent_err;
  bool err_to_out = false;
};

// Opens what `io` names for child fd `target` (0, 1 or 2); the parent's end of a pipe goes to
// `parent`. Everything is close-on-exec: only the dup2'ed copies reach the program.
Status open_stdio(const Stdio& io, int target, Fd& child, Fd& parent) {
  const bool input = target == STDIN_FILENO;
  switch (io.kind) {
    case Stdio::Kind::inherit:
    case Stdio::Kind::to_stdout:
      return {};
    case Stdio::Kind::null:
      child.reset(::open("/dev/null", (input ? O_RDONLY : O_WRONLY) | O_CLOEXEC));
      break;
    case Stdio::Kind::pipe: {
      std::array<int, 2> p{-1, -1};
      if (::pipe2(p.data(), O_CLOEXEC) != 0) {
        return make_error(Errc::io, "pipe: " + errno_text(errno));
      }
      child.reset(input ? p[0] : p[1]);
      parent.reset(input ? p[1] : p[0]);
      return {};
    }
    case Stdio::Kind::file:
      if (input) {
        return make_error(Errc::invalid_argument, "stdin cannot be a file to write");
      }
      child.reset(
          ::open(io.path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (io.append ? O_APPEND : O_TRUNC), 0644));
      if (child.get() < 0) {
        return make_error(Errc::io, io.path.string() + ": " + errno_text(errno));
      }
      return {};
  }
  return child.get() >= 0 ? Status{} : make_error(Errc::io, "/dev/null: " + errno_text(errno));
}

Result<StdioFds> open_stdio(const ProcessOptions& o) {
  if (o.in.kind == Stdio::Kind::to_stdout || o.out.kind == Stdio::Kind::to_stdout) {
    return make_error(Errc::invalid_argument, "only stderr can go to stdout");
  }
  StdioFds fds;
  SF_TRY(open_stdio(o.in, STDIN_FILENO, fds.child[0], fds.parent_in));
  SF_TRY(open_stdio(o.out, STDOUT_FILENO, fds.child[1], fds.parent_out));
  SF_TRY(open_stdio(o.err, STDERR_FILENO, fds.child[2], fds.parent_err));
  fds.err_to_out = o.err.kind == Stdio::Kind::to_stdout;
  return fds;
}

// This process's environment with `extra` ("NAME=value") added, replacing variables of those names.
std::vector<std::string> merged_environment(const std::vector<std::string>& extra) {
  std::vector<std::string> env = extra;
  const auto overridden = [&](std::string_view entry) {
    const auto name = entry.substr(0, entry.find('=') + 1);
    return std::any_of(extra.begin(), extra.end(), [&](const std::string& e) { return e.starts_with(name); });
  };
  for (char** e = environ; *e != nullptr; ++e) {
    if (!overridden(*e)) {
      env.emplace_back(*e);
    }
  }
  return env;
}

std::vector<char*> c_strings(std::vector<std::string>& strings) {
  std::vector<char*> out;
  out.reserve(strings.size() + 1);
  for (auto& s : strings) {
    out.push_back(s.data());
  }
  out.push_back(nullptr);
  return out;
}

int linux_policy(SchedulingPolicy policy) {
  switch (policy) {
    case SchedulingPolicy::batch:
      return SCHED_BATCH;
    case SchedulingPolicy::idle:
      return SCHED_IDLE;
    case SchedulingPolicy::normal:
    case SchedulingPolicy::inherit:
      break;
  }
  return SCHED_OTHER;
}

// What the child could not do before execve, sent to the parent over a close-on-exec pipe.
enum class Step : int { group, parent_death, scheduling, stdio, cwd, signals, exec };

struct ChildFailure {
  Step step = Step::exec;
  int err = 0;
};

std::string_view to_string(Step step) {
  switch (step) {
    case Step::group:
      return "setpgid";
    case Step::parent_death:
      return "prctl(PR_SET_PDEATHSIG)";
    case Step::scheduling:
      return "sched_setscheduler";
    case Step::stdio:
      return "dup2";
    case Step::cwd:
      return "chdir";
    case Step::signals:
      return "sigprocmask";
    case Step::exec:
      break;
  }
  return "execve";
}

// Everything the child needs, prepared before fork: after fork, in a process that may have other
// threads, the child may only make async-signal-safe calls until execve.
struct ExecPlan {
  std::string program;
  std::vector<std::string> argv_store;
  std::vector<std::string> env_store;
  std::vector<char*> argv;
  std::vector<char*> envp;
  std::array<int, 3> stdio{-1, -1, -1};
  bool err_to_out = false;
  std::string cwd;
  bool own_group = false;
  int death_signal = 0;
  pid_t parent = 0;
  std::optional<int> policy;
  int report = -1;
};

[[noreturn]] void fail_in_child(int report, Step step) {
  const ChildFailure failure{step, errno};
  (void)!::write(report, &failure, sizeof failure);
  ::_exit(127);
}

// Gives `fd` to the program as `target` (dup2 clears close-on-exec; an fd already in place keeps
// its flag, so clear it).
bool install(int fd, int target) {
  if (fd < 0) {
    return true;
  }
  if (fd == target) {
    return ::fcntl(fd, F_SETFD, 0) == 0;
  }
  return ::dup2(fd, target) == target;
}

[[noreturn]] void exec_child(const ExecPlan& plan) {
  if (plan.own_group && ::setpgid(0, 0) != 0) {
    fail_in_child(plan.report, Step::group);
  }
  if (plan.death_signal != 0) {
    if (::prctl(PR_SET_PDEATHSIG, plan.death_signal) != 0) {
      fail_in_child(plan.report, Step::parent_death);
    }
    if (::getppid() != plan.parent) {
      ::_exit(127);  // the parent died before the signal was set: it will never come
    }
  }
  if (plan.policy) {
    const sched_param param{};
    if (::sched_setscheduler(0, *plan.policy, &param) != 0) {
      fail_in_child(plan.report, Step::scheduling);
    }
  }
  // The stdio fds are all above 2 unless the parent had one of 0-2 closed: install in an order that
  // does not overwrite one still to be installed.
  for (int target = 0; target < 3; ++target) {
    if (!install(plan.stdio.at(static_cast<std::size_t>(target)), target)) {
      fail_in_child(plan.report, Step::stdio);
    }
  }
  if (plan.err_to_out && ::dup2(STDOUT_FILENO, STDERR_FILENO) != STDERR_FILENO) {
    fail_in_child(plan.report, Step::stdio);
  }
  if (!plan.cwd.empty() && ::chdir(plan.cwd.c_str()) != 0) {
    fail_in_child(plan.report, Step::cwd);
  }
  // The program starts with no blocked signals and SIGPIPE at its default, whatever the spawning
  // thread had (signal masks and ignored signals survive execve).
  sigset_t none;
  ::sigemptyset(&none);
  // NOLINTNEXTLINE(concurrency-mt-unsafe): after fork the child has this one thread
  if (::sigprocmask(SIG_SETMASK, &none, nullptr) != 0 || ::signal(SIGPIPE, SIG_DFL) == SIG_ERR) {
    fail_in_child(plan.report, Step::signals);
  }
  ::execve(plan.program.c_str(), plan.argv.data(), plan.envp.data());
  fail_in_child(plan.report, Step::exec);
}

int open_pidfd(pid_t pid) {
  return static_cast<int>(::syscall(SYS_pidfd_open, pid, 0));
}

// Waits for the child's report: empty when execve succeeded (the pipe closed on exec).
std::optional<ChildFailure> read_report(int fd) {
  ChildFailure failure;
  ssize_t got = 0;
  do {
    got = ::read(fd, &failure, sizeof failure);
  } while (got < 0 && errno == EINTR);
  return got == static_cast<ssize_t>(sizeof failure) ? std::optional{failure} : std::nullopt;
}

}  // namespace

std::string_view to_string(SchedulingPolicy policy) {
  switch (policy) {
    case SchedulingPolicy::inherit:
      return "inherit";
    case SchedulingPolicy::normal:
      return "normal";
    case SchedulingPolicy::batch:
      return "batch";
    case SchedulingPolicy::idle:
      return "idle";
  }
  return "?";
}

std::optional<SchedulingPolicy> scheduling_policy_from_string(std::string_view text) {
  for (auto p : {SchedulingPolicy::inherit, SchedulingPolicy::normal, SchedulingPolicy::batch,
                 SchedulingPolicy::idle}) {
    if (to_string(p) == text) {
      return p;
    }
  }
  return std::nullopt;
}

std::optional<std::filesystem::path> find_program(std::string_view name) {
  if (name.empty()) {
    return std::nullopt;
  }
  if (name.find('/') != std::string_view::npos) {
    return std::filesystem::path(name);
  }
  const char* path = std::getenv("PATH");  // NOLINT(concurrency-mt-unsafe): nobody sets it
  std::string_view dirs = path != nullptr ? path : "/usr/local/bin:/usr/bin:/bin";
  while (true) {
    const auto colon = dirs.find(':');
    const auto dir = dirs.substr(0, colon);
    auto candidate = std::filesystem::path(dir.empty() ? "." : dir) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    if (colon == std::string_view::npos) {
      return std::nullopt;
    }
    dirs = dirs.substr(colon + 1);
  }
}

Result<Process> Process::spawn(ProcessOptions options) {
  if (options.argv.empty()) {
    return make_error(Errc::invalid_argument, "no program to start (empty argv)");
  }
  const std::string name = options.argv.front();
  const auto cannot = [&](const std::string& why) {
    return make_error(Errc::io, "cannot start " + name + ": " + why);
  };
  const auto program = find_program(name);
  if (!program) {
    return cannot("not found on PATH");
  }
  auto fds = open_stdio(options);
  if (!fds) {
    return cannot(fds.error().message);
  }
  ExecPlan plan;
  plan.program = program->string();
  plan.argv_store = std::move(options.argv);
  plan.env_store = merged_environment(options.env);
  plan.argv = c_strings(plan.argv_store);
  plan.envp = c_strings(plan.env_store);
  for (std::size_t i = 0; i < 3; ++i) {
    plan.stdio.at(i) = fds->child.at(i).get();
  }
  plan.err_to_out = fds->err_to_out;
  plan.cwd = options.cwd.string();
  plan.own_group = options.own_process_group;
  plan.death_signal = options.parent_death_signal.value_or(0);
  plan.parent = ::getpid();
  if (options.scheduling != SchedulingPolicy::inherit) {
    plan.policy = linux_policy(options.scheduling);
  }
  std::array<int, 2> report{-1, -1};
  if (::pipe2(report.data(), O_CLOEXEC) != 0) {
    return cannot("pipe: " + errno_text(errno));
  }
  Fd report_read{report[0]};
  Fd report_write{report[1]};
  plan.report = report[1];
  const pid_t pid = ::fork();
  if (pid == 0) {
    exec_child(plan);
  }
  if (pid < 0) {
    return cannot("fork: " + errno_text(errno));
  }
  report_write.reset();
  for (auto& fd : fds->child) {
    fd.reset();
  }
  if (const auto failure = read_report(report_read.get())) {
    ::waitpid(pid, nullptr, 0);
    return cannot(std::string(to_string(failure->step)) + ": " + errno_text(failure->err));
  }
  Process p;
  p.name_ = name;
  p.pid_ = pid;
  p.pidfd_ = open_pidfd(pid);  // -1 before Linux 5.3: wait() then polls waitpid
  p.group_ = options.own_process_group;
  p.in_ = fds->parent_in.release();
  p.out_.fd = fds->parent_out.release();
  p.out_.piped = p.out_.fd >= 0;
  p.err_.fd = fds->parent_err.release();
  p.err_.piped = p.err_.fd >= 0;
  return p;
}

}  // namespace sf
