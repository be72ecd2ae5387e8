// Modbus TCP round trip of our Server serving any Device, next to a bare libmodbus server (the
// select() loop of libmodbus's multi-client example: modbus_receive + modbus_reply over a
// modbus_mapping_t, no hooks) with the same register layout and contents, measured in the same
// run with the same client. bench_modbus uses it with a small device; the plant's PLC devices
// plug in the same way: modbus_bench::compare(device, operations).
#pragma once

#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "sf/bench/percentile.hpp"
#include "sf/modbus/server.hpp"
#include "sf/modbus/tcp_client.hpp"

namespace modbus_bench {

using sf::modbus::BankLayout;
using sf::modbus::Client;
using sf::modbus::Device;
using sf::modbus::RegisterBank;
using sf::modbus::Table;

// The bare libmodbus server on its own thread, on 127.0.0.1 and a free port.
class BareServer {
 public:
  explicit BareServer(RegisterBank& bank) : ctx_(modbus_new_tcp("127.0.0.1", 0)), mapping_(bank.mapping()) {
    listen_ = modbus_tcp_listen(ctx_, 16);
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    ::getsockname(listen_, reinterpret_cast<sockaddr*>(&bound), &length);  // NOLINT
    port_ = ntohs(reinterpret_cast<sockaddr_in*>(&bound)->sin_port);       // NOLINT
    if (::pipe(wake_) != 0) {
      std::perror("pipe");
    }
    thread_ = std::thread([this] { run(); });
  }
  ~BareServer() {
    const char stop = 's';
    (void)!::write(wake_[1], &stop, 1);
    thread_.join();
    ::close(wake_[0]);
    ::close(wake_[1]);
    ::close(listen_);
    modbus_free(ctx_);
  }
  BareServer(const BareServer&) = delete;
  BareServer& operator=(const BareServer&) = delete;

  [[nodiscard]] std::uint16_t port() const { return port_; }

 private:
  // libmodbus's bandwidth-server-many-up.c loop, plus a pipe to stop it.
  void run() {
    std::vector<std::uint8_t> query(MODBUS_TCP_MAX_ADU_LENGTH);
    fd_set refset;
    FD_ZERO(&refset);
    FD_SET(listen_, &refset);
    FD_SET(wake_[0], &refset);
    int fdmax = std::max(listen_, wake_[0]);
    for (;;) {
      fd_set rdset = refset;
      if (::select(fdmax + 1, &rdset, nullptr, nullptr, nullptr) == -1) {
        return;
      }
      if (FD_ISSET(wake_[0], &rdset)) {
        break;
      }
      for (int fd = 0; fd <= fdmax; ++fd) {
        if (!FD_ISSET(fd, &rdset)) {
          continue;
        }
        if (fd == listen_) {
          const int client = ::accept(listen_, nullptr, nullptr);
          if (client >= 0) {
            FD_SET(client, &refset);
            fdmax = std::max(fdmax, client);
          }
          continue;
        }
        modbus_set_socket(ctx_, fd);
        const int rc = modbus_receive(ctx_, query.data());
        if (rc > 0) {
          modbus_reply(ctx_, query.data(), rc, mapping_);
        } else if (rc == -1) {
          ::close(fd);
          FD_CLR(fd, &refset);
        }
      }
    }
    for (int fd = 0; fd <= fdmax; ++fd) {
      if (FD_ISSET(fd, &refset) && fd != listen_ && fd != wake_[0]) {
        ::close(fd);
      }
    }
    modbus_set_socket(ctx_, -1);
  }

  modbus_t* ctx_;
  modbus_mapping_t* mapping_;
  int listen_ = -1;
  int wake_[2] = {-1, -1};
  std::uint16_t port_ = 0;
  std::thread thread_;
};

struct Figures {
  double p50_us = 0;
  double p99_us = 0;
  double per_s = 0;
};

// One kind of request, repeated: returns false when a request failed.
struct Operation {
  std::string name;
  std::function<bool(Client&)> run;
};

struct Row {
  std::string name;
  Figures ours;
  Figures bare;
  [[nodiscard]] double ratio() const { return ours.p50_us / bare.p50_us; }
};

struct Options {
  std::size_t requests = 20000;  // per server and operation, over all rounds
  std::size_t rounds = 5;        // ours and bare alternate, so load changes hit both
  std::size_t warm_up = 500;
};

inline Figures figures(std::vector<double>& latencies_us, double seconds) {
  std::sort(latencies_us.begin(), latencies_us.end());
  Figures f;
  if (latencies_us.empty()) {
    return f;
  }
  f.p50_us = sf::bench::percentile_of_sorted(std::span<const double>(latencies_us), 0.50);
  f.p99_us = sf::bench::percentile_of_sorted(std::span<const double>(latencies_us), 0.99);
  f.per_s = static_cast<double>(latencies_us.size()) / seconds;
  return f;
}

// Times `count` runs of an operation, appending each round trip in microseconds.
inline bool time_requests(Client& client, const Operation& op, std::size_t count, std::vector<double>& out,
                          double& seconds) {
  using clock = std::chrono::steady_clock;
  const auto begin = clock::now();
  for (std::size_t i = 0; i < count; ++i) {
    const auto start = clock::now();
    if (!op.run(client)) {
      return false;
    }
    out.push_back(std::chrono::duration<double, std::micro>(clock::now() - start).count());
  }
  seconds += std::chrono::duration<double>(clock::now() - begin).count();
  return true;
}

inline std::unique_ptr<sf::modbus::TcpClient> connect(std::uint16_t port) {
  auto client = sf::modbus::TcpClient::create(sf::modbus::TcpClientOptions{.port = port});
  if (!client || !(*client)->connect()) {
    return nullptr;
  }
  return std::move(*client);
}

// Our Server serving `device` next to the bare server over a copy of its bank, for each
// operation. Empty on a failure (printed to stderr).
inline std::vector<Row> compare(Device& device, const std::vector<Operation>& operations,
                                const Options& options = {}) {
  auto server = sf::modbus::Server::listen(device, sf::modbus::ServerOptions{});
  if (!server || !(*server)->start()) {
    std::fprintf(stderr, "modbus bench: our server did not start\n");
    return {};
  }
  auto bare_bank = RegisterBank::create(device.bank().layout());
  if (!bare_bank) {
    return {};
  }
  {
    const std::lock_guard lock(device.mutex());
    const BankLayout& l = device.bank().layout();
    for (Table t : {Table::coils, Table::discrete_inputs}) {
      bare_bank->set_bits(t, l[t].start, device.bank().bits(t, l[t].start, l[t].count));
    }
    for (Table t : {Table::holding_registers, Table::input_registers}) {
      bare_bank->set_words(t, l[t].start, device.bank().words(t, l[t].start, l[t].count));
    }
  }
  BareServer bare(*bare_bank);
  auto ours_client = connect((*server)->port());
  auto bare_client = connect(bare.port());
  if (!ours_client || !bare_client) {
    std::fprintf(stderr, "modbus bench: cannot connect\n");
    return {};
  }
  std::vector<Row> rows;
  const std::size_t per_round = std::max<std::size_t>(1, options.requests / options.rounds);
  for (const Operation& op : operations) {
    std::vector<double> ours_us;
    std::vector<double> bare_us;
    double ours_s = 0;
    double bare_s = 0;
    std::vector<double> ignored;
    double ignored_s = 0;
    bool ok = time_requests(*ours_client, op, options.warm_up, ignored, ignored_s) &&
              time_requests(*bare_client, op, options.warm_up, ignored, ignored_s);
    for (std::size_t round = 0; ok && round < options.rounds; ++round) {
      ok = time_requests(*ours_client, op, per_round, ours_us, ours_s) &&
           time_requests(*bare_client, op, per_round, bare_us, bare_s);
    }
    if (!ok) {
      std::fprintf(stderr, "modbus bench: %s failed\n", op.name.c_str());
      return {};
    }
    rows.push_back(Row{op.name, figures(ours_us, ours_s), figures(bare_us, bare_s)});
  }
  return rows;
}

inline void print(const std::vector<Row>& rows) {
  std::printf("%-28s %-10s %9s %9s %12s %8s\n", "request", "server", "p50 us", "p99 us", "requests/s",
              "ratio");
  for (const Row& r : rows) {
    std::printf("%-28s %-10s %9.1f %9.1f %12.0f %7.2fx\n", r.name.c_str(), "ours", r.ours.p50_us,
                r.ours.p99_us, r.ours.per_s, r.ratio());
    std::printf("%-28s %-10s %9.1f %9.1f %12.0f\n", "", "libmodbus", r.bare.p50_us, r.bare.p99_us,
                r.bare.per_s);
  }
}

}  // namespace modbus_bench
