// A peer program for tests and benchmarks (a node-opcua server, our own server) as a child
// process: stdin and stdout on pipes, a wait for the line that says it is ready, and a stop
// that always reaps it (SIGKILL when it does not go in time), also when the object is destroyed.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn needs it

namespace sf::testing {

class ChildProcess {
 public:
  ChildProcess() = default;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ~ChildProcess() { stop(false); }

  // Starts argv[0] (looked up on PATH) in `cwd`; stderr goes to /dev/null unless `show_stderr`.
  bool spawn(const std::vector<std::string>& args, const std::filesystem::path& cwd, bool show_stderr) {
    stop(false);
    int in[2] = {-1, -1};
    int out[2] = {-1, -1};
    if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0) {
      return false;
    }
    std::vector<char*> argv;
    for (const auto& a : args) {
      argv.push_back(const_cast<char*>(a.c_str()));  // NOLINT: posix_spawn's signature
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    if (!show_stderr) {
      posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    }
    posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
    const int rc = ::posix_spawnp(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(in[0]);
    ::close(out[1]);
    stdin_ = in[1];
    stdout_ = out[0];
    if (rc != 0) {
      pid_ = -1;
      close_fds();
      return false;
    }
    return true;
  }

  // Reads stdout line by line until `ready` accepts one (true), the process closes its stdout
  // or the time is up (false). Lines read after the accepted one wait for the next call.
  bool wait_for_line(const std::function<bool(const std::string&)>& ready,
                     std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      for (auto eol = unread_.find('\n'); eol != std::string::npos; eol = unread_.find('\n')) {
        const std::string line = unread_.substr(0, eol);
        unread_.erase(0, eol + 1);
        if (ready(line)) {
          return true;
        }
      }
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) {
        return false;
      }
      pollfd p{stdout_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
        continue;
      }
      char chunk[256];
      const ssize_t n = ::read(stdout_, chunk, sizeof chunk);
      if (n <= 0) {
        return false;  // the process ended before it was ready
      }
      unread_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  // Closes stdin (peers that exit on EOF go then), sends SIGTERM if `terminate`, and SIGKILL
  // if the process is not gone within 10 s.
  void stop(bool terminate) {
    if (pid_ > 0) {
      if (stdin_ >= 0) {
        ::close(stdin_);
        stdin_ = -1;
      }
      if (terminate) {
        ::kill(pid_, SIGCONT);  // a stopped process cannot act on SIGTERM
        ::kill(pid_, SIGTERM);
      }
      if (!wait_exit(std::chrono::seconds(10))) {
        kill();
      }
    }
    close_fds();
  }

  // SIGKILL and reap: the process dies at once.
  void kill() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      wait_exit(std::chrono::seconds(10));
    }
    close_fds();
  }

  void signal(int sig) const {
    if (pid_ > 0) {
      ::kill(pid_, sig);
    }
  }

  [[nodiscard]] pid_t pid() const { return pid_; }
  [[nodiscard]] bool running() const { return pid_ > 0 && ::kill(pid_, 0) == 0; }

 private:
  // Waits for the child with a pidfd (Linux 5.3) instead of polling waitpid.
  bool wait_exit(std::chrono::seconds timeout) {
    if (pid_ <= 0) {
      return true;
    }
    const int fd = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
    if (fd >= 0) {
      pollfd p{fd, POLLIN, 0};
      const int ready = ::poll(&p, 1, static_cast<int>(std::chrono::milliseconds(timeout).count()));
      ::close(fd);
      if (ready <= 0) {
        return false;
      }
    }
    int status = 0;
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    return true;
  }

  void close_fds() {
    unread_.clear();
    for (int* fd : {&stdin_, &stdout_}) {
      if (*fd >= 0) {
        ::close(*fd);
        *fd = -1;
      }
    }
  }

  pid_t pid_ = -1;
  int stdin_ = -1;
  int stdout_ = -1;
  std::string unread_;  // read from stdout, not yet seen by wait_for_line
};

}  // namespace sf::testing
