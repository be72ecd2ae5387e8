// Client behaviour that needs no real OPC UA server: requests without a session, connecting to
// nothing or to a server that never answers, misuse of connect, destruction with work pending.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <future>
#include <memory>

#include "node_server.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::opcua {
namespace {

// A TCP listener that completes connections (the kernel does, from the backlog) and never says
// a word: HEL gets no ACK.
class SilentServer {
 public:
  SilentServer() {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0;
    socklen_t length = sizeof address;
    auto* generic = reinterpret_cast<sockaddr*>(&address);
    if (::bind(fd_, generic, length) != 0 || ::listen(fd_, 16) != 0 ||
        ::getsockname(fd_, generic, &length) != 0) {
      ::close(fd_);
      fd_ = -1;
      return;
    }
    port_ = ntohs(address.sin_port);
  }
  ~SilentServer() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  SilentServer(const SilentServer&) = delete;
  SilentServer& operator=(const SilentServer&) = delete;
  [[nodiscard]] bool ok() const { return fd_ >= 0; }
  [[nodiscard]] std::string url() const { return "opc.tcp://127.0.0.1:" + std::to_string(port_); }

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
};

// A port nobody listens on (bound, then closed).
std::uint16_t closed_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  auto* generic = reinterpret_cast<sockaddr*>(&address);
  EXPECT_EQ(::bind(fd, generic, length), 0);
  EXPECT_EQ(::getsockname(fd, generic, &length), 0);
  ::close(fd);
  return ntohs(address.sin_port);
}

ClientConfig quick(std::string url) {
  ClientConfig config;
  config.endpoint_url = std::move(url);
  config.request_timeout = std::chrono::milliseconds(300);
  return config;
}

TEST(ClientBasicTest, RequestsWithoutSessionFailWithBadNotConnected) {
  SyncClient client(quick("opc.tcp://127.0.0.1:1"));
  EXPECT_EQ(client.state(), ClientState::Disconnected);
  auto values = client.read({value_of(NodeId(0, id::Server_ServerStatus_CurrentTime))});
  ASSERT_FALSE(values.ok());
  EXPECT_EQ(status_of(values.error()), status::BadNotConnected);
  auto subscription = client.create_subscription({});
  ASSERT_FALSE(subscription.ok());
  EXPECT_EQ(status_of(subscription.error()), status::BadNotConnected);
  auto deleted = client.delete_subscription(42);
  ASSERT_FALSE(deleted.ok());
  EXPECT_EQ(status_of(deleted.error()), status::BadSubscriptionIdInvalid);
  client.disconnect();  // harmless when not connected
  EXPECT_EQ(client.state(), ClientState::Disconnected);
}

TEST(ClientBasicTest, SilentServerGivesBadTimeout) {
  SilentServer silent;
  ASSERT_TRUE(silent.ok());
  SyncClient client(quick(silent.url()));
  const Status connected = client.connect();
  ASSERT_FALSE(connected.ok());
  EXPECT_EQ(status_of(connected.error()), status::BadTimeout) << connected.error().describe();
  EXPECT_EQ(client.state(), ClientState::Disconnected);
  auto endpoints = client.get_endpoints();
  ASSERT_FALSE(endpoints.ok());
  EXPECT_EQ(status_of(endpoints.error()), status::BadTimeout) << endpoints.error().describe();
}

TEST(ClientBasicTest, NobodyListeningFailsTheConnect) {
  SyncClient client(quick("opc.tcp://127.0.0.1:" + std::to_string(closed_port())));
  test::Collector<ClientState> states;
  client.set_on_state([&](ClientState state, const Status&) { states.add(state); });
  const Status connected = client.connect();
  ASSERT_FALSE(connected.ok());
  EXPECT_TRUE(status_of(connected.error()).is_bad());
  EXPECT_EQ(client.state(), ClientState::Disconnected);
  ASSERT_TRUE(states.wait_for(2));
  EXPECT_EQ(states.values(), (std::vector<ClientState>{ClientState::Connecting, ClientState::Disconnected}));
}

TEST(ClientBasicTest, BadEndpointUrlFails) {
  SyncClient client(quick("http://example.com"));
  const Status connected = client.connect();
  ASSERT_FALSE(connected.ok());
  EXPECT_EQ(status_of(connected.error()), status::BadTcpEndpointUrlInvalid) << connected.error().describe();
}

TEST(ClientBasicTest, SecondConnectWhileConnectingIsInvalidState) {
  SilentServer silent;
  ASSERT_TRUE(silent.ok());
  net::LoopThread thread;
  auto client = std::make_unique<Client>(thread.loop(), quick(silent.url()));
  std::promise<Status> first;
  std::promise<Status> second;
  client->connect([&](Status s) { first.set_value(std::move(s)); });
  client->connect([&](Status s) { second.set_value(std::move(s)); });
  const Status again = second.get_future().get();
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(status_of(again.error()), status::BadInvalidState);
  EXPECT_FALSE(first.get_future().get().ok());  // BadTimeout from the silent server
  client.reset();
}

TEST(ClientBasicTest, DestroyedWithRequestsPendingCallsNothingLater) {
  SilentServer silent;
  ASSERT_TRUE(silent.ok());
  net::LoopThread thread;
  auto called = std::make_shared<std::atomic<int>>(0);
  {
    ClientConfig config = quick(silent.url());
    config.request_timeout = std::chrono::milliseconds(10'000);
    Client client(thread.loop(), config);
    client.connect([called](Status) { ++*called; });
    client.get_endpoints([called](Result<std::vector<EndpointDescription>>) { ++*called; });
  }  // destroyed on this (non-loop) thread while both wait for the silent server
  thread.run_sync([] {});
  EXPECT_EQ(called->load(), 0);
}

TEST(ClientBasicTest, HelpersBuildRequests) {
  const auto browse = browse_children_of(NodeId(0, id::ObjectsFolder));
  EXPECT_EQ(browse.node_id, NodeId(0, id::ObjectsFolder));
  EXPECT_EQ(browse.browse_direction, BrowseDirection::Forward);
  EXPECT_EQ(browse.reference_type_id, NodeId(0, id::HierarchicalReferences));
  EXPECT_TRUE(browse.include_subtypes);
  EXPECT_EQ(browse.result_mask, 63U);
  const auto filter = select_event_fields({"Message", "EnabledState/Id"});
  ASSERT_EQ(filter.select_clauses.size(), 2U);
  EXPECT_EQ(filter.select_clauses[0].type_definition_id, NodeId(0, id::BaseEventType));
  EXPECT_EQ(filter.select_clauses[0].attribute_id, attribute_id::Value);
  ASSERT_EQ(filter.select_clauses[1].browse_path.size(), 2U);
  EXPECT_EQ(filter.select_clauses[1].browse_path[1].name, "Id");
  EXPECT_EQ(to_string(ClientState::Reconnecting), "Reconnecting");
}

}  // namespace
}  // namespace sf::opcua
