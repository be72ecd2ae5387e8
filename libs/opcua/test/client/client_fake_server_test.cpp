// The client against a scripted server (fake_server.hpp): request headers, ServiceFaults,
// sequence-number handling of subscriptions (gaps → Republish, duplicates, lost messages) and
// both ways of re-establishing a connection (OPC 10000-4 §6.7).
#include <gtest/gtest.h>

#include <memory>

#include "fake_server.hpp"
#include "node_server.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::opcua {
namespace {

using test::Collector;
using test::FakeServer;

class FakeServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(server_.start());
    ClientConfig config;
    config.endpoint_url = server_.url();
    config.request_timeout = std::chrono::milliseconds(3000);
    config.reconnect_min = std::chrono::milliseconds(50);
    config.reconnect_max = std::chrono::milliseconds(200);
    config.publish_requests = 1;  // one held Publish at a time keeps the script simple
    client_ = std::make_unique<SyncClient>(config);
    client_->set_on_state([this](ClientState state, const Status&) { states_.add(state); });
    const Status connected = client_->connect();
    ASSERT_TRUE(connected.ok()) << connected.error().describe();
  }
  void TearDown() override {
    client_.reset();
    server_.stop();
  }

  // A subscription with one monitored item whose values are collected.
  void subscribe() {
    auto subscription = client_->create_subscription({.publishing_interval_ms = 50});
    ASSERT_TRUE(subscription.ok()) << subscription.error().describe();
    subscription_ = *subscription;
    auto handle = client_->monitor_value(subscription_, value_of(NodeId(1, String("x"))), {},
                                         [this](const DataValue& value) {
                                           if (const auto* d = value.value.get_if<double>()) {
                                             values_.add(*d);
                                           }
                                         });
    ASSERT_TRUE(handle.ok()) << handle.error().describe();
    handle_ = *handle;
    wait_publish();
  }
  // Waits for a held Publish request to answer.
  void wait_publish() {
    ASSERT_TRUE(server_.wait_until([](FakeServer& s) { return s.held_locked() > 0; }));
  }
  void send(std::uint32_t sequence, double value, std::vector<std::uint32_t> available) {
    wait_publish();
    ASSERT_TRUE(server_.publish_data(sequence, handle_, value, std::move(available)));
  }

  FakeServer server_;
  std::unique_ptr<SyncClient> client_;
  Collector<ClientState> states_;
  Collector<double> values_;
  Client::SubscriptionId subscription_ = 0;
  std::uint32_t handle_ = 0;
};

TEST_F(FakeServerTest, FillsTheRequestHeader) {
  ASSERT_TRUE(client_->read_value(NodeId(1, 7)).ok());
  ASSERT_TRUE(client_->read_value(NodeId(1, 8)).ok());
  const auto sessions = server_.requests_of<CreateSessionRequest>();
  ASSERT_EQ(sessions.size(), 1U);
  EXPECT_TRUE(sessions[0].request_header.authentication_token.is_null());
  const auto reads = server_.requests_of<ReadRequest>();
  ASSERT_EQ(reads.size(), 2U);
  for (const auto& read : reads) {
    EXPECT_EQ(read.request_header.authentication_token, NodeId(1, String("token-1")));
    EXPECT_EQ(read.request_header.timeout_hint, 3000U);
    EXPECT_NE(read.request_header.request_handle, 0U);
    const auto age = std::chrono::system_clock::now() - read.request_header.timestamp.to_system_clock();
    EXPECT_LT(std::chrono::abs(age), std::chrono::minutes(1));
  }
  EXPECT_NE(reads[0].request_header.request_handle, reads[1].request_header.request_handle);
  // The anonymous token names the policy id the server offered.
  const auto activations = server_.requests_of<ActivateSessionRequest>();
  ASSERT_EQ(activations.size(), 1U);
  const auto* token = activations[0].user_identity_token.get_if<AnonymousIdentityToken>();
  ASSERT_NE(token, nullptr);
  EXPECT_EQ(token->policy_id, "open-sesame");
}

TEST_F(FakeServerTest, ServiceFaultBecomesAnErrorWithItsStatus) {
  server_.set_read_handler([](const ReadRequest& request) -> std::optional<Message> {
    ServiceFault fault;
    fault.response_header.request_handle = request.request_header.request_handle;
    fault.response_header.service_result = status::BadTooManyOperations;
    return fault;
  });
  auto values = client_->read({value_of(NodeId(1, 7))});
  ASSERT_FALSE(values.ok());
  EXPECT_EQ(status_of(values.error()), status::BadTooManyOperations);
}

TEST_F(FakeServerTest, WrongNumberOfResultsIsRejected) {
  server_.set_read_handler([](const ReadRequest& request) -> std::optional<Message> {
    ReadResponse response;
    response.response_header.request_handle = request.request_header.request_handle;
    return response;  // no results for one node
  });
  auto values = client_->read({value_of(NodeId(1, 7))});
  ASSERT_FALSE(values.ok());
  EXPECT_EQ(status_of(values.error()), status::BadUnknownResponse);
}

TEST_F(FakeServerTest, DeliversInOrderAndRepublishesAGap) {
  subscribe();
  server_.store_for_republish(2, handle_, 2.0);
  send(1, 1.0, {1});
  send(3, 3.0, {2, 3});  // 2 was sent but never arrived
  ASSERT_TRUE(values_.wait_for(3));
  EXPECT_EQ(values_.values(), (std::vector<double>{1.0, 2.0, 3.0}));
  const auto republished = server_.requests_of<RepublishRequest>();
  ASSERT_EQ(republished.size(), 1U);
  EXPECT_EQ(republished[0].retransmit_sequence_number, 2U);
  EXPECT_EQ(republished[0].subscription_id, server_.last_subscription_id());

  // Everything received is acknowledged with the following Publish requests.
  send(4, 4.0, {});
  ASSERT_TRUE(values_.wait_for(4));
  wait_publish();
  std::set<std::uint32_t> acked;
  for (const auto& publish : server_.requests_of<PublishRequest>()) {
    for (const auto& ack : publish.subscription_acknowledgements) {
      acked.insert(ack.sequence_number);
    }
  }
  EXPECT_EQ(acked, (std::set<std::uint32_t>{1, 2, 3, 4}));
}

TEST_F(FakeServerTest, DropsDuplicates) {
  subscribe();
  server_.store_for_republish(2, handle_, 2.0);
  send(1, 1.0, {1});
  send(3, 3.0, {2, 3});
  ASSERT_TRUE(values_.wait_for(3));
  send(2, 2.0, {2});  // the original arrives late: already delivered by Republish
  send(3, 3.0, {3});
  send(4, 4.0, {4});
  ASSERT_TRUE(values_.wait_for(4));
  EXPECT_EQ(values_.values(), (std::vector<double>{1.0, 2.0, 3.0, 4.0}));
}

TEST_F(FakeServerTest, SkipsWhatTheServerNoLongerHas) {
  subscribe();
  send(1, 1.0, {1});
  send(4, 4.0, {4});  // 2 and 3 are gone (not in availableSequenceNumbers)
  send(5, 5.0, {5});
  ASSERT_TRUE(values_.wait_for(3));
  EXPECT_EQ(values_.values(), (std::vector<double>{1.0, 4.0, 5.0}));
  EXPECT_TRUE(server_.requests_of<RepublishRequest>().empty());
}

TEST_F(FakeServerTest, KeepAliveRevealsALostMessage) {
  subscribe();
  server_.store_for_republish(2, handle_, 2.0);
  send(1, 1.0, {1});
  wait_publish();
  ASSERT_TRUE(server_.publish_keep_alive(3, {2}));  // "next is 3": 2 was sent
  ASSERT_TRUE(values_.wait_for(2));
  EXPECT_EQ(values_.values(), (std::vector<double>{1.0, 2.0}));
}

// OPC 10000-4 §6.7: the connection drops but the server keeps the session: the client
// reactivates it on a new channel, fetches what it missed with Republish, and creates nothing.
TEST_F(FakeServerTest, ReconnectReactivatesTheSession) {
  subscribe();
  send(1, 1.0, {1});
  ASSERT_TRUE(values_.wait_for(1));
  const std::uint16_t port = server_.port();
  server_.stop();
  ASSERT_TRUE(states_.wait_until(
      [](const std::vector<ClientState>& s) { return !s.empty() && s.back() == ClientState::Reconnecting; }));
  server_.store_for_republish(2, handle_, 2.0);  // sent while the connection was down
  ASSERT_TRUE(server_.start(port));
  ASSERT_TRUE(states_.wait_until(
      [](const std::vector<ClientState>& s) { return s.back() == ClientState::Connected; }));
  send(3, 3.0, {2, 3});
  ASSERT_TRUE(values_.wait_for(3));
  EXPECT_EQ(values_.values(), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(server_.requests_of<CreateSessionRequest>().size(), 1U);
  EXPECT_EQ(server_.requests_of<ActivateSessionRequest>().size(), 2U);
  EXPECT_EQ(server_.requests_of<CreateSubscriptionRequest>().size(), 1U);
  EXPECT_EQ(server_.requests_of<CreateMonitoredItemsRequest>().size(), 1U);
}

// The server restarted and forgot the session: a new session, the subscription and its item are
// re-created with the same client handle, and numbering starts again at 1.
TEST_F(FakeServerTest, ReconnectRecreatesWhenTheSessionIsGone) {
  subscribe();
  send(1, 1.0, {1});
  send(2, 2.0, {1, 2});
  ASSERT_TRUE(values_.wait_for(2));
  const std::uint16_t port = server_.port();
  server_.stop(/*forget_sessions=*/true);
  ASSERT_TRUE(states_.wait_until(
      [](const std::vector<ClientState>& s) { return !s.empty() && s.back() == ClientState::Reconnecting; }));
  ASSERT_TRUE(server_.start(port));
  ASSERT_TRUE(states_.wait_until(
      [](const std::vector<ClientState>& s) { return s.back() == ClientState::Connected; }));
  EXPECT_EQ(server_.requests_of<CreateSessionRequest>().size(), 2U);
  const auto items = server_.requests_of<CreateMonitoredItemsRequest>();
  ASSERT_EQ(items.size(), 2U);
  ASSERT_EQ(items[1].items_to_create.size(), 1U);
  EXPECT_EQ(items[1].items_to_create[0].requested_parameters.client_handle, handle_);
  EXPECT_EQ(items[1].subscription_id, server_.last_subscription_id());
  send(1, 10.0, {1});  // the initial value again, numbered from 1
  send(2, 11.0, {2});
  ASSERT_TRUE(values_.wait_for(4));
  EXPECT_EQ(values_.values(), (std::vector<double>{1.0, 2.0, 10.0, 11.0}));
}

// A session error on an ordinary request (the server lost the session) recovers like a lost
// connection.
TEST_F(FakeServerTest, SessionErrorStartsRecovery) {
  subscribe();
  server_.forget_sessions();
  auto failed = client_->read_value(NodeId(1, 7));
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(status_of(failed.error()), status::BadSessionIdInvalid);
  ASSERT_TRUE(states_.wait_until([](const std::vector<ClientState>& s) {
    return s.size() >= 4 &&
           s.back() == ClientState::Connected;  // Connecting, Connected, Reconnecting, Connected
  }));
  EXPECT_EQ(server_.requests_of<CreateSessionRequest>().size(), 2U);
  EXPECT_EQ(server_.requests_of<CreateSubscriptionRequest>().size(), 2U);
  auto value = client_->read_value(NodeId(1, 7));
  ASSERT_TRUE(value.ok()) << value.error().describe();
}

TEST_F(FakeServerTest, DisconnectClosesTheSession) {
  subscribe();
  client_->disconnect();
  EXPECT_EQ(client_->state(), ClientState::Disconnected);
  const auto closes = server_.requests_of<CloseSessionRequest>();
  ASSERT_EQ(closes.size(), 1U);
  EXPECT_TRUE(closes[0].delete_subscriptions);
  auto after = client_->read_value(NodeId(1, 7));
  ASSERT_FALSE(after.ok());
  EXPECT_EQ(status_of(after.error()), status::BadNotConnected);
  // And it can connect again.
  ASSERT_TRUE(client_->connect().ok());
  EXPECT_TRUE(client_->read_value(NodeId(1, 7)).ok());
}

}  // namespace
}  // namespace sf::opcua
