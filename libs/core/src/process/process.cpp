// Process: waiting, signalling and reaping the child, its stdin and its piped output (the start
// is in spawn.cpp).
#include "sf/core/process.hpp"
#include "sf/core/text.hpp"

#include <poll.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <system_error>
#include <utility>

#include "sf/core/clock.hpp"

namespace sf {
namespace {

using std::chrono::nanoseconds;
using time_point = Clock::time_point;

time_point now() {
  return SteadyClock::instance().now();
}

// poll(2)'s timeout for the time left until `deadline`, rounded up so that a wait does not spin.
int poll_ms(time_point deadline) {
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - now()).count();
  return static_cast<int>(std::clamp<std::int64_t>(left, 0, INT_MAX));
}

time_point deadline_after(nanoseconds timeout) {
  // Far deadlines (a caller's "forever") must not overflow the clock.
  constexpr auto kForever = std::chrono::hours{24 * 365};
  return now() + std::min<nanoseconds>(timeout, kForever);
}

std::chrono::nanoseconds to_ns(const timeval& t) {
  return std::chrono::seconds{t.tv_sec} + std::chrono::microseconds{t.tv_usec};
}

ExitStatus exit_status_of(int status, const rusage& usage) {
  ExitStatus s;
  if (WIFEXITED(status)) {
    s.code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    s.signal = WTERMSIG(status);
  }
  s.cpu_time = to_ns(usage.ru_utime) + to_ns(usage.ru_stime);
  s.max_rss_kib = usage.ru_maxrss;
  return s;
}

}  // namespace

int ExitStatus::shell_code() const {
  if (code) {
    return *code;
  }
  return signal ? 128 + *signal : -1;
}

std::string ExitStatus::describe() const {
  if (code) {
    return "exit code " + std::to_string(*code);
  }
  if (signal) {
    const char* text = ::sigdescr_np(*signal);
    return "signal " + std::to_string(*signal) + (text != nullptr ? std::string(" (") + text + ")" : "");
  }
  return "unknown exit status";
}

Result<Completed> Process::run(ProcessOptions options, std::chrono::nanoseconds timeout) {
  const auto deadline = deadline_after(timeout);
  if (options.out.kind == Stdio::Kind::inherit) {
    options.out = Stdio::pipe();
  }
  auto p = spawn(std::move(options));
  if (!p) {
    return p.error();
  }
  Completed done;
  const bool ended = p->pump_until([&] { return p->out_.ended() && p->err_.ended(); }, deadline);
  done.out = std::exchange(p->out_.unread, {});
  done.err = std::exchange(p->err_.unread, {});
  auto status = ended ? p->wait(deadline - now()) : Result<ExitStatus>{make_error(Errc::timeout, "")};
  if (!status) {
    p->kill();
    return make_error(Errc::timeout, p->name_ + " did not finish in time; its output: " + done.out);
  }
  done.status = *status;
  return done;
}

Process::Process(Process&& other) noexcept
    : name_(std::move(other.name_)),
      pid_(std::exchange(other.pid_, -1)),
      pidfd_(std::exchange(other.pidfd_, -1)),
      group_(other.group_),
      in_(std::exchange(other.in_, -1)),
      out_(std::exchange(other.out_, {})),
      err_(std::exchange(other.err_, {})),
      exit_status_(other.exit_status_) {}

Process& Process::operator=(Process&& other) noexcept {
  if (this != &other) {
    release();
    name_ = std::move(other.name_);
    pid_ = std::exchange(other.pid_, -1);
    pidfd_ = std::exchange(other.pidfd_, -1);
    group_ = other.group_;
    in_ = std::exchange(other.in_, -1);
    out_ = std::exchange(other.out_, {});
    err_ = std::exchange(other.err_, {});
    exit_status_ = other.exit_status_;
  }
  return *this;
}

Process::~Process() {
  release();
}

void Process::release() {
  close_stdin();  // peers that end on EOF may go before the signal
  if (pid_ > 0) {
    terminate(kDestroyGrace);
  }
  close_all();
}

bool Process::running() const {
  if (pid_ <= 0) {
    return false;
  }
  siginfo_t info{};
  // WNOWAIT: look without reaping, so that wait() still gets the status.
  if (::waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) != 0) {
    return false;
  }
  return info.si_pid == 0;
}

Status Process::signal(int sig) const {
  if (pid_ <= 0) {
    return make_error(Errc::state, "no process to signal");
  }
  int rc = 0;
  if (group_) {
    rc = ::kill(-pid_, sig);
  } else if (pidfd_ >= 0) {
    rc = static_cast<int>(::syscall(SYS_pidfd_send_signal, pidfd_, sig, nullptr, 0));
  } else {
    rc = ::kill(pid_, sig);
  }
  if (rc != 0) {
    return make_error(Errc::io, "signal " + std::to_string(sig) + " to " + name_ + ": " + errno_text(errno));
  }
  return {};
}

Result<ExitStatus> Process::wait(std::chrono::nanoseconds timeout) {
  if (pid_ <= 0) {
    return make_error(Errc::state, "no process to wait for");
  }
  const auto deadline = deadline_after(timeout);
  int flags = 0;
  if (pidfd_ >= 0) {
    pollfd p{pidfd_, POLLIN, 0};
    int ready = 0;
    do {
      ready = ::poll(&p, 1, poll_ms(deadline));
    } while (ready < 0 && errno == EINTR);
    if (ready == 0) {
      return make_error(Errc::timeout, name_ + " still runs");
    }
  } else {
    flags = WNOHANG;  // no pidfd: look every few milliseconds
  }
  while (true) {
    int status = 0;
    rusage usage{};
    const pid_t got = ::wait4(pid_, &status, flags, &usage);
    if (got == pid_ || (got < 0 && errno == ECHILD)) {
      reap(got == pid_ ? exit_status_of(status, usage) : ExitStatus{});
      return *exit_status_;
    }
    if (got < 0 && errno != EINTR) {
      return make_error(Errc::io, "wait for " + name_ + ": " + errno_text(errno));
    }
    if (got == 0) {
      if (now() >= deadline) {
        return make_error(Errc::timeout, name_ + " still runs");
      }
      SteadyClock::instance().sleep_until(std::min(deadline, now() + std::chrono::milliseconds{5}));
    }
  }
}

ExitStatus Process::terminate(std::chrono::nanoseconds grace) {
  if (pid_ > 0) {
    (void)signal(SIGCONT);  // a stopped process cannot act on SIGTERM
    (void)signal(SIGTERM);
    if (auto s = wait(grace); s) {
      return *s;
    }
    return kill();
  }
  return exit_status_.value_or(ExitStatus{});
}

ExitStatus Process::kill() {
  if (pid_ > 0) {
    (void)signal(SIGKILL);
    (void)wait(
        std::chrono::hours{1});  // SIGKILL cannot be caught: only a process stuck in the kernel lingers
  }
  return exit_status_.value_or(ExitStatus{});
}

ExitStatus Process::close_and_wait(std::chrono::nanoseconds grace) {
  close_stdin();
  if (pid_ > 0) {
    if (auto s = wait(grace); s) {
      return *s;
    }
  }
  return kill();
}

void Process::reap(ExitStatus status) {
  exit_status_ = status;
  pid_ = -1;
  if (pidfd_ >= 0) {
    ::close(pidfd_);
    pidfd_ = -1;
  }
}

Status Process::write_stdin(std::string_view bytes) {
  if (in_ < 0) {
    return make_error(Errc::state, name_ + ": stdin is not a pipe (or was closed)");
  }
  // A child that closed its stdin must give EPIPE here, not a SIGPIPE that ends this process:
  // block it for this thread and take a SIGPIPE this write raised before unblocking.
  sigset_t pipe_signal;
  sigset_t old;
  ::sigemptyset(&pipe_signal);
  ::sigaddset(&pipe_signal, SIGPIPE);
  ::pthread_sigmask(SIG_BLOCK, &pipe_signal, &old);
  int err = 0;
  while (!bytes.empty()) {
    const ssize_t n = ::write(in_, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n < 0) {
      err = errno;
      break;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  if (err == EPIPE) {
    const timespec zero{};
    while (::sigtimedwait(&pipe_signal, nullptr, &zero) < 0 && errno == EINTR) {
    }
  }
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
  if (err != 0) {
    return make_error(Errc::io, "write to " + name_ + ": " + errno_text(err));
  }
  return {};
}

void Process::close_stdin() {
  if (in_ >= 0) {
    ::close(in_);
    in_ = -1;
  }
}

bool Process::pump_until(const std::function<bool()>& done, time_point deadline) {
  while (!done()) {
    std::array<pollfd, 2> fds{};
    std::array<Pipe*, 2> pipes{};
    nfds_t n = 0;
    for (Pipe* p : {&out_, &err_}) {
      if (p->fd >= 0) {
        fds.at(n) = pollfd{p->fd, POLLIN, 0};
        pipes.at(n++) = p;
      }
    }
    if (n == 0 || now() >= deadline) {
      return false;  // nothing more will come, or no more time
    }
    const int ready = ::poll(fds.data(), n, poll_ms(deadline));
    if (ready < 0 && errno != EINTR) {
      return false;
    }
    for (nfds_t i = 0; ready > 0 && i < n; ++i) {
      if (fds.at(i).revents != 0) {
        pipes.at(i)->read_some();
      }
    }
  }
  return true;
}

void Process::Pipe::read_some() {
  std::array<char, 4096> chunk{};
  const ssize_t n = ::read(fd, chunk.data(), chunk.size());
  if (n > 0) {
    unread.append(chunk.data(), static_cast<std::size_t>(n));
  } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
    ::close(fd);  // the stream ended (or broke, which ends it too)
    fd = -1;
  }
}

Result<std::string> Process::read_line(std::chrono::nanoseconds timeout, Stream stream) {
  Pipe& p = pipe_of(stream);
  const char* what = stream == Stream::out ? "stdout" : "stderr";
  if (!p.piped) {
    return make_error(Errc::state, name_ + ": " + what + " is not a pipe");
  }
  pump_until([&] { return p.unread.find('\n') != std::string::npos || p.ended(); }, deadline_after(timeout));
  if (const auto eol = p.unread.find('\n'); eol != std::string::npos) {
    std::string line = p.unread.substr(0, eol);
    p.unread.erase(0, eol + 1);
    return line;
  }
  if (!p.ended()) {
    return make_error(Errc::timeout, name_ + ": no line on " + what + " in time");
  }
  if (!p.unread.empty()) {
    return std::exchange(p.unread, {});
  }
  return make_error(Errc::state, name_ + ": " + what + " ended");
}

Result<std::string> Process::wait_for_line(const std::function<bool(const std::string&)>& accept,
                                           std::chrono::nanoseconds timeout, Stream stream) {
  const auto deadline = deadline_after(timeout);
  while (true) {
    auto line = read_line(std::max<nanoseconds>(deadline - now(), nanoseconds{0}), stream);
    if (!line || accept(*line)) {
      return line;
    }
  }
}

Result<std::string> Process::read_to_end(std::chrono::nanoseconds timeout, Stream stream) {
  Pipe& p = pipe_of(stream);
  if (!p.piped) {
    return make_error(Errc::state, name_ + ": not a pipe");
  }
  if (!pump_until([&] { return p.ended(); }, deadline_after(timeout))) {
    return make_error(Errc::timeout, name_ + ": output did not end in time");
  }
  return std::exchange(p.unread, {});
}

void Process::close_all() {
  close_stdin();
  for (Pipe* p : {&out_, &err_}) {
    if (p->fd >= 0) {
      ::close(p->fd);
    }
    *p = Pipe{};
  }
  if (pidfd_ >= 0) {
    ::close(pidfd_);
    pidfd_ = -1;
  }
}

}  // namespace sf