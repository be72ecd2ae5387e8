// The Dispatcher without sockets: sessions (OPC 10000-4 §5.6), discovery, service routing and
// subscriptions over a fake channel, with a ManualClock for timeouts.
#include "sf/opcua/server/dispatcher.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <vector>

#include "sf/examples/opcua_demo.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {
namespace {

using namespace std::chrono_literals;

class FakeChannel final : public ServerChannel {
 public:
  explicit FakeChannel(std::uint32_t id) { info_.channel_id = id; }
  [[nodiscard]] const ChannelInfo& info() const override { return info_; }
  void send_response(std::uint32_t request_id, const Message& response) override {
    responses.emplace_back(request_id, response);
  }
  void close() override { open = false; }
  [[nodiscard]] bool is_open() const override { return open; }

  template <typename T>
  const T& last() const {
    const T* typed = std::get_if<T>(&responses.back().second);
    if (typed == nullptr) {
      ADD_FAILURE() << "last response is " << message_type_name(responses.back().second);
      static const T empty{};
      return empty;
    }
    return *typed;
  }
  [[nodiscard]] StatusCode last_fault() const {
    const auto* fault = std::get_if<ServiceFault>(&responses.back().second);
    return fault != nullptr ? fault->response_header.service_result : StatusCode{};
  }

  ChannelInfo info_;
  std::vector<std::pair<std::uint32_t, Message>> responses;
  bool open = true;
};

class DispatcherTest : public ::testing::Test {
 protected:
  DispatcherTest() {
    EXPECT_TRUE(build_namespace0(space_));
    space_.add_namespace("urn:smartfactory:test");
    EXPECT_TRUE(examples::add_demo_nodes(space_));
    ServerObjectInfo info;
    info.clock = &clock_;
    EXPECT_TRUE(install_server_object_callbacks(space_, std::move(info)));
    SessionLimits sessions;
    sessions.max_sessions = 3;
    sessions.min_session_timeout_ms = 1000;
    sessions.max_session_timeout_ms = 60'000;
    dispatcher_ = std::make_unique<Dispatcher>(space_, clock_, ServerIdentity{}, sessions,
                                               SubscriptionLimits{}, OperationLimits{});
  }

  // CreateSession + ActivateSession on channel; returns the authentication token.
  NodeId open_session(const std::shared_ptr<FakeChannel>& channel, double timeout_ms = 10'000) {
    CreateSessionRequest create;
    create.session_name = "test";
    create.requested_session_timeout = timeout_ms;
    dispatcher_->on_request(channel, next_id_++, create);
    const NodeId token = channel->last<CreateSessionResponse>().authentication_token;
    ActivateSessionRequest activate;
    activate.request_header.authentication_token = token;
    activate.user_identity_token = ExtensionObject::make(AnonymousIdentityToken{"anonymous"});
    dispatcher_->on_request(channel, next_id_++, activate);
    EXPECT_TRUE(std::holds_alternative<ActivateSessionResponse>(channel->responses.back().second));
    return token;
  }

  ReadResponse read_value(const std::shared_ptr<FakeChannel>& channel, const NodeId& token,
                          const NodeId& node) {
    ReadRequest read;
    read.request_header.authentication_token = token;
    read.request_header.request_handle = 77;
    ReadValueId item;
    item.node_id = node;
    item.attribute_id = 13;
    read.nodes_to_read = Array<ReadValueId>{item};
    dispatcher_->on_request(channel, next_id_++, read);
    if (const auto* response = std::get_if<ReadResponse>(&channel->responses.back().second)) {
      return *response;
    }
    return {};
  }

  NodeId counter() const {
    return NodeId(*space_.namespace_index(examples::kDemoNamespaceUri), String("Demo.Counter"));
  }

  ManualClock clock_;
  AddressSpace space_;
  std::unique_ptr<Dispatcher> dispatcher_;
  std::uint32_t next_id_ = 1;
};

TEST_F(DispatcherTest, SessionLifecycleAndRead) {
  auto channel = std::make_shared<FakeChannel>(1);
  const NodeId token = open_session(channel);
  EXPECT_EQ(dispatcher_->session_count(), 1U);
  const auto response = read_value(channel, token, NodeId(0, id::Server_NamespaceArray));
  EXPECT_EQ(response.response_header.request_handle, 77U);
  ASSERT_EQ(response.results.size(), 1U);
  const auto* namespaces = response.results[0].value.array_if<String>();
  ASSERT_NE(namespaces, nullptr);
  ASSERT_GE(namespaces->size(), 3U);
  EXPECT_EQ((*namespaces)[0], "http://opcfoundation.org/UA/");
  EXPECT_EQ((*namespaces)[2], "urn:smartfactory:demo");

  CloseSessionRequest close;
  close.request_header.authentication_token = token;
  dispatcher_->on_request(channel, next_id_++, close);
  EXPECT_TRUE(std::holds_alternative<CloseSessionResponse>(channel->responses.back().second));
  EXPECT_EQ(dispatcher_->session_count(), 0U);
  read_value(channel, token, NodeId(0, id::Server_NamespaceArray));
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadSessionIdInvalid));
}

TEST_F(DispatcherTest, RequestsWithoutAValidSessionGetFaults) {
  auto channel = std::make_shared<FakeChannel>(1);
  read_value(channel, NodeId(1, ByteString({1, 2, 3})), counter());
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadSessionIdInvalid));

  CreateSessionRequest create;
  dispatcher_->on_request(channel, next_id_++, create);
  const NodeId token = channel->last<CreateSessionResponse>().authentication_token;
  read_value(channel, token, counter());
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadSessionNotActivated));

  // The first activation must come over the creating channel.
  auto other = std::make_shared<FakeChannel>(2);
  ActivateSessionRequest activate;
  activate.request_header.authentication_token = token;
  dispatcher_->on_request(other, next_id_++, activate);
  EXPECT_EQ(other->last_fault(), StatusCode(status::BadSecureChannelIdInvalid));
}

TEST_F(DispatcherTest, ActivatedSessionMovesToANewChannel) {
  auto first = std::make_shared<FakeChannel>(1);
  const NodeId token = open_session(first);
  auto second = std::make_shared<FakeChannel>(2);
  read_value(second, token, counter());
  EXPECT_EQ(second->last_fault(), StatusCode(status::BadSecureChannelIdInvalid));

  dispatcher_->on_channel_closed(1);
  ActivateSessionRequest activate;
  activate.request_header.authentication_token = token;
  dispatcher_->on_request(second, next_id_++, activate);
  ASSERT_TRUE(std::holds_alternative<ActivateSessionResponse>(second->responses.back().second));
  EXPECT_TRUE(read_value(second, token, counter()).results.at(0).status.is_good());
  read_value(first, token, counter());
  EXPECT_EQ(first->last_fault(), StatusCode(status::BadSecureChannelIdInvalid));
}

TEST_F(DispatcherTest, UnsupportedIdentityTokensAreRejected) {
  auto channel = std::make_shared<FakeChannel>(1);
  CreateSessionRequest create;
  dispatcher_->on_request(channel, next_id_++, create);
  ActivateSessionRequest activate;
  activate.request_header.authentication_token = channel->last<CreateSessionResponse>().authentication_token;
  UserNameIdentityToken user;
  user.user_name = "operator";
  activate.user_identity_token = ExtensionObject::make(user);
  dispatcher_->on_request(channel, next_id_++, activate);
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadIdentityTokenRejected));
}

TEST_F(DispatcherTest, TooManySessions) {
  auto channel = std::make_shared<FakeChannel>(1);
  for (int i = 0; i < 3; ++i) {
    open_session(channel);
  }
  CreateSessionRequest create;
  dispatcher_->on_request(channel, next_id_++, create);
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadTooManySessions));
  EXPECT_EQ(dispatcher_->session_count(), 3U);
}

TEST_F(DispatcherTest, SessionTimesOutWithoutRequests) {
  auto channel = std::make_shared<FakeChannel>(1);
  const NodeId token = open_session(channel, 2000);
  clock_.advance(1500ms);
  EXPECT_TRUE(read_value(channel, token, counter()).results.at(0).status.is_good());  // refreshes
  clock_.advance(1500ms);
  dispatcher_->tick();
  EXPECT_EQ(dispatcher_->session_count(), 1U);
  clock_.advance(600ms);
  dispatcher_->tick();
  EXPECT_EQ(dispatcher_->session_count(), 0U);
  read_value(channel, token, counter());
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadSessionIdInvalid));
}

TEST_F(DispatcherTest, RevisesTheSessionTimeoutIntoItsRange) {
  auto channel = std::make_shared<FakeChannel>(1);
  CreateSessionRequest create;
  create.requested_session_timeout = 1;
  dispatcher_->on_request(channel, next_id_++, create);
  EXPECT_EQ(channel->last<CreateSessionResponse>().revised_session_timeout, 1000.0);
  create.requested_session_timeout = 1e9;
  dispatcher_->on_request(channel, next_id_++, create);
  EXPECT_EQ(channel->last<CreateSessionResponse>().revised_session_timeout, 60'000.0);
}

TEST_F(DispatcherTest, HistoryWithoutADatabaseAndResponsesAsRequests) {
  auto channel = std::make_shared<FakeChannel>(1);
  const NodeId token = open_session(channel);
  HistoryReadRequest history;
  history.request_header.authentication_token = token;
  history.request_header.request_handle = 9;
  ReadRawModifiedDetails details;
  details.start_time = DateTime::from_unix_seconds(1);
  details.end_time = DateTime::from_unix_seconds(2);
  history.history_read_details = ExtensionObject::make(details);
  history.timestamps_to_return = TimestampsToReturn::Both;
  HistoryReadValueId item;
  item.node_id = counter();
  history.nodes_to_read = Array<HistoryReadValueId>{item};
  dispatcher_->on_request(channel, next_id_++, history);
  const auto& response = channel->last<HistoryReadResponse>();
  EXPECT_EQ(response.response_header.request_handle, 9U);
  ASSERT_EQ(response.results.size(), 1U);
  EXPECT_EQ(response.results[0].status_code, StatusCode(status::BadHistoryOperationUnsupported));
  dispatcher_->on_request(channel, next_id_++, ReadResponse{});
  EXPECT_EQ(channel->last_fault(), StatusCode(status::BadServiceUnsupported));
}

TEST_F(DispatcherTest, GetEndpointsEchoesTheUrlAndFiltersProfiles) {
  auto channel = std::make_shared<FakeChannel>(1);
  GetEndpointsRequest request;
  request.endpoint_url = "opc.tcp://plc7:4841";
  dispatcher_->on_request(channel, next_id_++, request);
  const auto& response = channel->last<GetEndpointsResponse>();
  ASSERT_EQ(response.endpoints.size(), 1U);
  EXPECT_EQ(response.endpoints[0].endpoint_url, "opc.tcp://plc7:4841");
  EXPECT_EQ(response.endpoints[0].security_mode, MessageSecurityMode::None);
  EXPECT_EQ(response.endpoints[0].user_identity_tokens.at(0).token_type, UserTokenType::Anonymous);
  EXPECT_EQ(response.endpoints[0].server.application_type, ApplicationType::Server);

  request.profile_uris =
      Array<String>{String("http://opcfoundation.org/UA-Profile/Transport/https-uabinary")};
  dispatcher_->on_request(channel, next_id_++, request);
  EXPECT_TRUE(channel->last<GetEndpointsResponse>().endpoints.empty());

  FindServersRequest find;
  dispatcher_->on_request(channel, next_id_++, find);
  ASSERT_EQ(channel->last<FindServersResponse>().servers.size(), 1U);
  EXPECT_EQ(channel->last<FindServersResponse>().servers[0].application_uri,
            ServerIdentity{}.application_uri);
}

TEST_F(DispatcherTest, WriteThenSubscribeDeliversTheValueThroughPublish) {
  auto channel = std::make_shared<FakeChannel>(1);
  const NodeId token = open_session(channel);
  WriteRequest write;
  write.request_header.authentication_token = token;
  WriteValue item;
  item.node_id = counter();
  item.attribute_id = 13;
  item.value = DataValue(Variant(std::int32_t{41}));
  write.nodes_to_write = Array<WriteValue>{item};
  dispatcher_->on_request(channel, next_id_++, write);
  ASSERT_EQ(channel->last<WriteResponse>().results.at(0), StatusCode{});

  CreateSubscriptionRequest create;
  create.request_header.authentication_token = token;
  create.requested_publishing_interval = 100;
  create.requested_lifetime_count = 30;
  create.requested_max_keep_alive_count = 10;
  create.publishing_enabled = true;
  dispatcher_->on_request(channel, next_id_++, create);
  const std::uint32_t subscription = channel->last<CreateSubscriptionResponse>().subscription_id;

  CreateMonitoredItemsRequest items;
  items.request_header.authentication_token = token;
  items.subscription_id = subscription;
  items.timestamps_to_return = TimestampsToReturn::Both;
  MonitoredItemCreateRequest monitored;
  monitored.item_to_monitor.node_id = counter();
  monitored.item_to_monitor.attribute_id = 13;
  monitored.monitoring_mode = MonitoringMode::Reporting;
  monitored.requested_parameters.client_handle = 5;
  monitored.requested_parameters.sampling_interval = 100;
  monitored.requested_parameters.queue_size = 1;
  items.items_to_create = Array<MonitoredItemCreateRequest>{monitored};
  dispatcher_->on_request(channel, next_id_++, items);
  ASSERT_TRUE(channel->last<CreateMonitoredItemsResponse>().results.at(0).status_code.is_good());

  PublishRequest publish;
  publish.request_header.authentication_token = token;
  publish.request_header.request_handle = 1234;
  const std::uint32_t publish_id = next_id_++;
  dispatcher_->on_request(channel, publish_id, publish);
  for (int i = 0; i < 5 && channel->responses.back().first != publish_id; ++i) {
    clock_.advance(100ms);
    dispatcher_->tick();
  }
  ASSERT_EQ(channel->responses.back().first, publish_id);
  const auto& response = channel->last<PublishResponse>();
  EXPECT_EQ(response.response_header.request_handle, 1234U);
  EXPECT_EQ(response.subscription_id, subscription);
  ASSERT_EQ(response.notification_message.notification_data.size(), 1U);
  const auto* change = response.notification_message.notification_data[0].get_if<DataChangeNotification>();
  ASSERT_NE(change, nullptr);
  ASSERT_EQ(change->monitored_items.size(), 1U);
  EXPECT_EQ(change->monitored_items[0].client_handle, 5U);
  EXPECT_EQ(change->monitored_items[0].value.value, Variant(std::int32_t{41}));

  // Closing the session with deleteSubscriptions removes them.
  CloseSessionRequest close;
  close.request_header.authentication_token = token;
  close.delete_subscriptions = true;
  dispatcher_->on_request(channel, next_id_++, close);
  EXPECT_EQ(dispatcher_->subscriptions().subscription_count(), 0U);
}

// The server re-arms its timer after requests that may make something due earlier (a new
// session's expiry, a subscription's cycle, a monitored item's sampling, a Publish deadline),
// and not after attribute and view services, which would only cost it a pass over every
// monitored item per request.
TEST_F(DispatcherTest, OnlyRequestsThatMayMoveTheScheduleAskForATick) {
  int reschedules = 0;
  dispatcher_->set_on_schedule_changed([&reschedules] { ++reschedules; });
  auto channel = std::make_shared<FakeChannel>(1);
  const NodeId token = open_session(channel);
  EXPECT_EQ(reschedules, 2);  // CreateSession, ActivateSession

  read_value(channel, token, counter());
  WriteRequest write;
  write.request_header.authentication_token = token;
  WriteValue item;
  item.node_id = counter();
  item.attribute_id = 13;
  item.value = DataValue(Variant(std::int32_t{7}));
  write.nodes_to_write = Array<WriteValue>{item};
  dispatcher_->on_request(channel, next_id_++, write);
  BrowseRequest browse;
  browse.request_header.authentication_token = token;
  browse.nodes_to_browse = Array<BrowseDescription>{BrowseDescription{}};
  browse.nodes_to_browse[0].node_id = NodeId(0, id::ObjectsFolder);
  dispatcher_->on_request(channel, next_id_++, browse);
  dispatcher_->on_request(channel, next_id_++, GetEndpointsRequest{});
  EXPECT_EQ(reschedules, 2);

  CreateSubscriptionRequest create;
  create.request_header.authentication_token = token;
  create.requested_publishing_interval = 100;
  create.publishing_enabled = true;
  dispatcher_->on_request(channel, next_id_++, create);
  EXPECT_EQ(reschedules, 3);
  PublishRequest publish;
  publish.request_header.authentication_token = token;
  dispatcher_->on_request(channel, next_id_++, publish);
  EXPECT_EQ(reschedules, 4);
}

}  // namespace
}  // namespace sf::opcua::server
