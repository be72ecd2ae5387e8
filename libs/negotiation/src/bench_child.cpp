#include "bench_child.hpp"

#include <fcntl.h>
#include <sched.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <thread>
#include <utility>

#include <fmt/format.h>

extern char** environ;  // NOLINT: POSIX

namespace sf::negotiation::detail {
namespace {

using namespace std::chrono_literals;

std::chrono::nanoseconds to_ns(const timeval& t) {
  return std::chrono::seconds{t.tv_sec} + std::chrono::microseconds{t.tv_usec};
}

int linux_policy(SchedulingPolicy policy) {
  return policy == SchedulingPolicy::batch ? SCHED_BATCH : SCHED_OTHER;
}

// The program `name` names: itself if it holds a '/', otherwise the first executable of that name
// on PATH (as execvp would find it, looked up before fork so that the child only calls execve).
std::string resolve(const std::string& name) {
  if (name.find('/') != std::string::npos) {
    return name;
  }
  const char* path = std::getenv("PATH");
  std::string_view dirs = path != nullptr ? path : "/usr/local/bin:/usr/bin:/bin";
  while (!dirs.empty()) {
    const auto colon = dirs.find(':');
    const auto dir = dirs.substr(0, colon);
    auto candidate = fmt::format("{}/{}", dir.empty() ? "." : dir, name);
    if (::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    dirs = colon == std::string_view::npos ? std::string_view{} : dirs.substr(colon + 1);
  }
  return name;  // execve fails with ENOENT, reported as such
}

// In the forked child: only async-signal-safe calls until execve. A failure is reported to the
// parent as the errno on `report` (close-on-exec, so a successful execve closes it empty).
[[noreturn]] void exec_child(const std::string& program, char* const* argv, char* const* envp, int output_fd,
                             int report, int policy) {
  const sched_param param{};
  int err = 0;
  if (::sched_setscheduler(0, policy, &param) != 0 || ::dup2(output_fd, 1) < 0 || ::dup2(output_fd, 2) < 0) {
    err = errno;
  } else {
    ::execve(program.c_str(), argv, envp);
    err = errno;
  }
  (void)!::write(report, &err, sizeof err);
  ::_exit(127);
}

}  // namespace

Result<BenchChild> BenchChild::spawn(const std::vector<std::string>& args,
                                     const std::vector<std::string>& extra_env, const std::string& output,
                                     SchedulingPolicy policy) {
  std::vector<char*> argv;
  for (const auto& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));  // NOLINT: execve's signature
  }
  argv.push_back(nullptr);
  std::vector<std::string> env_store = extra_env;
  for (char** e = environ; *e != nullptr; ++e) {
    env_store.emplace_back(*e);
  }
  std::vector<char*> envp;
  for (auto& e : env_store) {
    envp.push_back(e.data());
  }
  envp.push_back(nullptr);
  const auto program = resolve(args.at(0));
  const int output_fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (output_fd < 0) {
    return Error{Errc::io, fmt::format("cannot open {}: {}", output, std::strerror(errno))};
  }
  std::array<int, 2> report{};
  if (::pipe2(report.data(), O_CLOEXEC) != 0) {
    const int err = errno;
    ::close(output_fd);
    return Error{Errc::io, fmt::format("cannot start {}: {}", args[0], std::strerror(err))};
  }
  // posix_spawn cannot set SCHED_BATCH (glibc accepts only SCHED_OTHER, FIFO and RR there), so fork.
  const pid_t pid = ::fork();
  if (pid == 0) {
    exec_child(program, argv.data(), envp.data(), output_fd, report[1], linux_policy(policy));
  }
  const int fork_errno = errno;
  ::close(output_fd);
  ::close(report[1]);
  int child_errno = 0;
  ssize_t got = 0;
  if (pid > 0) {
    do {
      got = ::read(report[0], &child_errno, sizeof child_errno);
    } while (got < 0 && errno == EINTR);
  }
  ::close(report[0]);
  if (pid < 0) {
    return Error{Errc::io, fmt::format("cannot start {}: {}", args[0], std::strerror(fork_errno))};
  }
  if (got == static_cast<ssize_t>(sizeof child_errno)) {
    ::waitpid(pid, nullptr, 0);
    return Error{Errc::io, fmt::format("cannot start {}: {}", args[0], std::strerror(child_errno))};
  }
  return BenchChild{pid};
}

BenchChild::BenchChild(BenchChild&& o) noexcept
    : pid_(std::exchange(o.pid_, 0)), cpu_at_exit_(o.cpu_at_exit_) {}

bool BenchChild::wait(std::chrono::nanoseconds bound) {
  const auto end = std::chrono::steady_clock::now() + bound;
  while (pid_ > 0 && std::chrono::steady_clock::now() < end) {
    rusage usage{};
    if (wait4(pid_, nullptr, WNOHANG, &usage) == pid_) {
      pid_ = 0;
      cpu_at_exit_ = to_ns(usage.ru_utime) + to_ns(usage.ru_stime);
      return true;
    }
    std::this_thread::sleep_for(10ms);
  }
  return pid_ == 0;
}

void BenchChild::stop() {
  if (pid_ <= 0) {
    return;
  }
  kill(pid_, SIGTERM);
  if (!wait(5s)) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = 0;
  }
}

}  // namespace sf::negotiation::detail
