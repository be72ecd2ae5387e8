// Our client against our server while 200 TCP connections that never send a byte are held open
// from four other loopback addresses (a resource exhaustion attempt, OPC 10000-6 §7.1.5): the
// client still connects, reads and subscribes, and its channel survives a further wave of idle
// connections because an activated session uses it.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "../collector.hpp"
#include "../test_util.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/server/server.hpp"
#include "sf/opcua/status_codes.hpp"
#include "variables.hpp"

namespace sf::opcua {
namespace {

using namespace std::chrono_literals;
using test::Collector;

// A connected TCP socket from `source` (any 127.x.y.z is local) that sends nothing.
class IdleConnection {
 public:
  IdleConnection(const std::string& source, std::uint16_t port) : fd_(::socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in from{};
    from.sin_family = AF_INET;
    ::inet_pton(AF_INET, source.c_str(), &from.sin_addr);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    connected_ = fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr*>(&from), sizeof from) == 0 &&
                 ::connect(fd_, reinterpret_cast<sockaddr*>(&to), sizeof to) == 0;
  }
  ~IdleConnection() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  IdleConnection(const IdleConnection&) = delete;
  IdleConnection& operator=(const IdleConnection&) = delete;

  [[nodiscard]] bool connected() const { return connected_; }

  // What the server sent before it closed the connection (waits up to `timeout`).
  Bytes received_until_closed(std::chrono::seconds timeout) const {
    timeval tv{static_cast<time_t>(timeout.count()), 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    Bytes out;
    std::uint8_t buffer[256];
    for (;;) {
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) {
        return out;
      }
      out.insert(out.end(), buffer, buffer + n);
    }
  }

 private:
  int fd_;
  bool connected_ = false;
};

std::vector<std::unique_ptr<IdleConnection>> open_idle(std::size_t count, std::uint16_t port) {
  std::vector<std::unique_ptr<IdleConnection>> out;
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back(std::make_unique<IdleConnection>("127.0.0." + std::to_string(2 + i % 4), port));
    EXPECT_TRUE(out.back()->connected()) << i;
  }
  return out;
}

TEST(IdleConnections, DoNotLockOutAClientThatLogsIn) {
  server::ServerConfig config;  // default limits: 100 channels, 50 per source address
  config.transport.host = "127.0.0.1";
  config.transport.port = 0;
  config.advertised_host = "127.0.0.1";
  server::Server server(config);
  auto counter = std::make_shared<std::atomic<std::int32_t>>(0);
  const NodeId node = test::add_int32_variable(server, "urn:smartfactory:test:idle", "Counter", [counter] {
    return DataValue(Variant(counter->fetch_add(1)));
  });
  ASSERT_TRUE(server.start().ok());

  const auto idle = open_idle(200, server.port());

  ClientConfig client_config;
  client_config.endpoint_url = "opc.tcp://127.0.0.1:" + std::to_string(server.port());
  client_config.request_timeout = 5s;
  client_config.auto_reconnect = false;
  SyncClient client(client_config);
  auto connected = client.connect();
  ASSERT_TRUE(connected.ok()) << connected.error().message;
  auto value = client.read_value(node);
  ASSERT_TRUE(value.ok()) << value.error().message;
  EXPECT_NE(value->value.get_if<std::int32_t>(), nullptr);

  Collector<std::int32_t> values;
  auto subscription = client.create_subscription({.publishing_interval_ms = 50});
  ASSERT_TRUE(subscription.ok()) << subscription.error().message;
  MonitoringParameters parameters;
  parameters.sampling_interval = 10;
  auto handle =
      client.monitor_value(*subscription, value_of(node), parameters, [&values](const DataValue& v) {
        if (const auto* i = v.value.get_if<std::int32_t>()) {
          values.add(*i);
        }
      });
  ASSERT_TRUE(handle.ok()) << handle.error().message;
  EXPECT_TRUE(values.wait_for(3));

  // The oldest idle connection made room and was told why (ERR, OPC 10000-6 §7.1.5).
  EXPECT_EQ(test::error_status(idle.front()->received_until_closed(10s)), status::BadTcpNotEnoughResources);

  // Another wave of idle connections does not take the channel of the activated session: they
  // make room among themselves, oldest first (the 101st of the wave goes when the last arrives).
  const auto more = open_idle(200, server.port());
  (void)more[100]->received_until_closed(10s);
  const std::size_t before = values.size();
  EXPECT_TRUE(values.wait_for(before + 3));
  auto again = client.read_value(node);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(client.state(), ClientState::Connected);
  EXPECT_EQ(server.session_count(), 1U);
}

}  // namespace
}  // namespace sf::opcua
