// Test helpers for the OPC UA client: the node-opcua test server
// (tests/peers/opcua/node_server.mjs) as a child process, and a thread-safe collector for
// values that callbacks deliver on the loop thread.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "../collector.hpp"

extern char** environ;  // NOLINT(readability-redundant-declaration): posix_spawn needs it

namespace sf::opcua::test {

// The repository: $SF_SOURCE_DIR (set for every unit test by sf_unit_test).
inline std::filesystem::path source_dir() {
  const char* env = std::getenv("SF_SOURCE_DIR");
  return env != nullptr ? std::filesystem::path(env) : std::filesystem::current_path();
}

inline std::optional<std::filesystem::path> find_node() {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "/usr/bin:/usr/local/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const auto end = dirs.find(':', start);
    const std::filesystem::path candidate =
        std::filesystem::path(
            dirs.substr(start, end == std::string::npos ? std::string::npos : end - start)) /
        "node";
    if (::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    if (end == std::string::npos) {
      break;
    }
    start = end + 1;
  }
  return std::nullopt;
}

// Why node-opcua tests cannot run here, or nullopt if they can.
inline std::optional<std::string> node_unavailable() {
  if (!find_node()) {
    return "node is not on PATH";
  }
  if (!std::filesystem::exists(source_dir() / "node_modules" / "node-opcua")) {
    return "node_modules/node-opcua is missing (npm ci)";
  }
  return std::nullopt;
}

// One node-opcua server process. It exits when its stdin closes (stop) or on SIGKILL (kill).
class NodeServer {
 public:
  NodeServer() = default;
  NodeServer(const NodeServer&) = delete;
  NodeServer& operator=(const NodeServer&) = delete;
  ~NodeServer() { stop(); }

  // Starts the server on port (0 = a free one) and waits for "READY <port>".
  bool start(std::uint16_t port = 0, std::chrono::seconds timeout = std::chrono::seconds(90)) {
    stop();
    const auto node = find_node();
    if (!node) {
      return false;
    }
    int in[2] = {-1, -1};
    int out[2] = {-1, -1};
    if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0) {
      return false;
    }
    const std::string script = (source_dir() / "tests" / "peers" / "opcua" / "node_server.mjs").string();
    const std::string port_text = std::to_string(port);
    const std::string node_text = node->string();
    std::vector<char*> argv = {const_cast<char*>(node_text.c_str()), const_cast<char*>(script.c_str()),
                               const_cast<char*>(port_text.c_str()), nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    if (std::getenv("SF_NODE_SERVER_LOG") == nullptr) {
      posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    }
    posix_spawn_file_actions_addchdir_np(&actions, source_dir().c_str());
    const int rc = ::posix_spawn(&pid_, node_text.c_str(), &actions, nullptr, argv.data(), environ);
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
    return wait_ready(timeout);
  }

  // Closes stdin (an orderly shutdown); SIGKILL if it is not gone within a few seconds.
  void stop() {
    if (pid_ <= 0) {
      close_fds();
      return;
    }
    if (stdin_ >= 0) {
      ::close(stdin_);
      stdin_ = -1;
    }
    if (!wait_exit(std::chrono::seconds(10))) {
      ::kill(pid_, SIGKILL);
      wait_exit(std::chrono::seconds(10));
    }
    close_fds();
  }

  // The server dies at once (no CloseSession, no CLO): the connection just drops.
  void kill() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      wait_exit(std::chrono::seconds(10));
    }
    close_fds();
  }

  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] std::string url() const { return "opc.tcp://127.0.0.1:" + std::to_string(port_); }

 private:
  bool wait_ready(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::string buffer;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{stdout_, POLLIN, 0};
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (::poll(&p, 1, static_cast<int>(std::max<std::int64_t>(left.count(), 1))) <= 0) {
        continue;
      }
      char chunk[256];
      const ssize_t n = ::read(stdout_, chunk, sizeof chunk);
      if (n <= 0) {
        return false;  // the process ended before it was ready
      }
      buffer.append(chunk, static_cast<std::size_t>(n));
      const auto at = buffer.find("READY ");
      const auto eol = at == std::string::npos ? std::string::npos : buffer.find('\n', at);
      if (eol != std::string::npos) {
        port_ = static_cast<std::uint16_t>(std::stoul(buffer.substr(at + 6, eol - at - 6)));
        return true;
      }
    }
    return false;
  }

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
  std::uint16_t port_ = 0;
};

}  // namespace sf::opcua::test
