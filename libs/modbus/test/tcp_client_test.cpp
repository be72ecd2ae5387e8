// The libmodbus client's own behaviour: options, connection failures, reconnection.
#include "sf/modbus/tcp_client.hpp"

#include <gtest/gtest.h>

#include "sf/modbus/server.hpp"
#include "test_support.hpp"

namespace sf::modbus::test {
namespace {

using namespace std::chrono_literals;

std::unique_ptr<Server> serve(Device& device, std::uint16_t port = 0) {
  auto server = Server::listen(device, ServerOptions{.port = port});
  EXPECT_TRUE(server.ok()) << server.error().describe();
  if (!server) {
    return nullptr;
  }
  EXPECT_TRUE((*server)->start().ok());
  return std::move(*server);
}

TEST(TcpClient, RefusesOptionsLibmodbusCannotUse) {
  EXPECT_EQ(TcpClient::create(TcpClientOptions{.unit_id = 250}).error().code, Errc::invalid_argument);
  EXPECT_EQ(TcpClient::create(TcpClientOptions{.response_timeout = 0ms}).error().code,
            Errc::invalid_argument);
  EXPECT_TRUE(TcpClient::create(TcpClientOptions{.unit_id = 247}).ok());
}

TEST(TcpClient, NobodyListeningIsAConnectionError) {
  RecordingDevice device;
  std::uint16_t port = 0;
  {
    auto gone = serve(device);
    ASSERT_TRUE(gone);
    port = gone->port();
  }
  auto client = TcpClient::create(TcpClientOptions{.port = port, .response_timeout = 200ms});
  ASSERT_TRUE(client.ok());
  auto r = (*client)->read_coils(0, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::io) << r.error().describe();
  EXPECT_NE(r.error().message.find(std::to_string(port)), std::string::npos);
  EXPECT_FALSE((*client)->connected());
}

TEST(TcpClient, ConnectsOnDemandAndExplicitly) {
  RecordingDevice device;
  auto server = serve(device);
  auto client = TcpClient::create(TcpClientOptions{.port = server->port()});
  ASSERT_TRUE(client.ok());
  EXPECT_FALSE((*client)->connected());
  ASSERT_TRUE((*client)->connect().ok());
  EXPECT_TRUE((*client)->connected());
  (*client)->close();
  EXPECT_FALSE((*client)->connected());
  EXPECT_TRUE((*client)->read_coils(0, 1).ok());
  EXPECT_TRUE((*client)->connected());
  EXPECT_EQ((*client)->endpoint(), "127.0.0.1:" + std::to_string(server->port()));
}

TEST(TcpClient, ReconnectsAfterTheServerRestarts) {
  RecordingDevice device;
  auto server = serve(device);
  const std::uint16_t port = server->port();
  auto client = TcpClient::create(TcpClientOptions{.port = port, .response_timeout = 500ms});
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE((*client)->write_single_register(1000, 1).ok());

  server.reset();  // closes every connection
  auto down = (*client)->read_holding_registers(1000, 1);
  ASSERT_FALSE(down.ok());
  EXPECT_EQ(down.error().code, Errc::io) << down.error().describe();

  server = serve(device, port);
  ASSERT_TRUE(server);
  auto up = (*client)->read_holding_registers(1000, 1);
  ASSERT_TRUE(up.ok()) << up.error().describe();
  EXPECT_EQ((*up)[0], 1);
}

TEST(TcpClient, AConnectionTheServerClosedIsReplacedBeforeTheNextRequest) {
  RecordingDevice device;
  auto server = serve(device);
  const std::uint16_t port = server->port();
  auto client = TcpClient::create(TcpClientOptions{.port = port});
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE((*client)->read_coils(0, 1).ok());
  server.reset();
  server = serve(device, port);
  ASSERT_TRUE(server);
  // No failed call: the closed connection is noticed before the request goes out.
  EXPECT_TRUE((*client)->read_coils(0, 1).ok());
  EXPECT_EQ(server->counters().connections, 1U);
}

}  // namespace
}  // namespace sf::modbus::test
