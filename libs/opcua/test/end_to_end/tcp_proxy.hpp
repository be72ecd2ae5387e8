// A loopback TCP proxy for connection-loss tests: forwards every accepted connection to an
// upstream port, and can cut all current connections and refuse new ones for a while (the
// network between a client and a server going away while both keep running).
#pragma once

#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace sf::opcua::test {

class TcpProxy {
 public:
  explicit TcpProxy(std::uint16_t upstream_port) : upstream_port_(upstream_port) {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address = loopback(0);
    ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), sizeof address);
    ::listen(listen_fd_, 16);
    socklen_t length = sizeof address;
    ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
    port_ = ntohs(address.sin_port);
    thread_ = std::thread([this] { run(); });
  }
  ~TcpProxy() {
    stop_ = true;
    thread_.join();
    close_pairs();
    ::close(listen_fd_);
  }
  TcpProxy(const TcpProxy&) = delete;
  TcpProxy& operator=(const TcpProxy&) = delete;

  [[nodiscard]] std::uint16_t port() const { return port_; }
  // Closes every forwarded connection now; while refusing, new ones are closed on accept.
  void cut_and_refuse() {
    refuse_ = true;
    cut_ = true;
  }
  void accept_again() { refuse_ = false; }

 private:
  static sockaddr_in loopback(std::uint16_t port) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(port);
    return address;
  }

  void run() {
    while (!stop_) {
      if (cut_.exchange(false)) {
        close_pairs();
      }
      std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
      for (const auto& [a, b] : pairs_) {
        fds.push_back({a, POLLIN, 0});
        fds.push_back({b, POLLIN, 0});
      }
      if (::poll(fds.data(), fds.size(), 20) <= 0) {
        continue;
      }
      // Forward before accepting: fds describes the pairs as they were when polled.
      forward(fds);
      if ((fds[0].revents & POLLIN) != 0) {
        accept_one();
      }
    }
  }

  void accept_one() {
    const int client = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) {
      return;
    }
    if (refuse_) {
      ::close(client);
      return;
    }
    const int upstream = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address = loopback(upstream_port_);
    if (::connect(upstream, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      ::close(upstream);
      ::close(client);
      return;
    }
    pairs_.emplace_back(client, upstream);
  }

  // Copies what is readable to the other side; a closed side closes the pair.
  void forward(const std::vector<pollfd>& fds) {
    std::vector<std::pair<int, int>> open;
    for (std::size_t i = 0; i < pairs_.size(); ++i) {
      const auto [a, b] = pairs_[i];
      const bool ok = pump(fds[1 + 2 * i], a, b) && pump(fds[2 + 2 * i], b, a);
      if (ok) {
        open.emplace_back(a, b);
      } else {
        ::close(a);
        ::close(b);
      }
    }
    pairs_ = std::move(open);
  }

  static bool pump(const pollfd& fd, int from, int to) {
    if ((fd.revents & (POLLIN | POLLHUP | POLLERR)) == 0) {
      return true;
    }
    std::array<char, 65536> buffer{};
    const ssize_t n = ::read(from, buffer.data(), buffer.size());
    if (n <= 0) {
      return false;
    }
    for (ssize_t sent = 0; sent < n;) {
      const ssize_t w = ::send(to, buffer.data() + sent, static_cast<std::size_t>(n - sent), MSG_NOSIGNAL);
      if (w <= 0) {
        return false;
      }
      sent += w;
    }
    return true;
  }

  void close_pairs() {
    for (const auto& [a, b] : pairs_) {
      ::close(a);
      ::close(b);
    }
    pairs_.clear();
  }

  std::uint16_t upstream_port_;
  std::uint16_t port_ = 0;
  int listen_fd_ = -1;
  std::vector<std::pair<int, int>> pairs_;  // proxy thread only
  std::atomic<bool> refuse_{false};
  std::atomic<bool> cut_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace sf::opcua::test
