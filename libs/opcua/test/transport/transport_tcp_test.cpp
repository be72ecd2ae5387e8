// ServerTransport and ClientChannel over real TCP on 127.0.0.1.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <map>
#include <optional>
#include <set>

#include "../test_util.hpp"
#include "channel_harness.hpp"
#include "sf/net/tcp.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/transport/client_transport.hpp"
#include "sf/opcua/transport/server_transport.hpp"

namespace sf::opcua::test {
namespace {

using namespace std::chrono_literals;

// Answers ReadRequest with a ReadResponse whose one value is a ByteString of maxAge bytes;
// a negative maxAge means "hold the request and never answer".
class EchoHandler : public ServiceHandler {
 public:
  void on_request(const std::shared_ptr<ServerChannel>& channel, std::uint32_t request_id,
                  Message request) override {
    ++requests;
    last_info = channel->info();
    if (const auto* read = std::get_if<ReadRequest>(&request)) {
      if (read->max_age < 0) {
        held.emplace_back(channel, request_id);
        return;
      }
      channel->send_response(request_id, read_response(read->request_header.request_handle,
                                                       static_cast<std::size_t>(read->max_age)));
    }
  }
  void on_channel_closed(std::uint32_t channel_id) override { closed.push_back(channel_id); }
  [[nodiscard]] bool holds_session(std::uint32_t channel_id) const override {
    return with_session.count(channel_id) != 0;
  }

  int requests = 0;
  std::set<std::uint32_t> with_session;  // channels the test says an activated session uses
  ChannelInfo last_info;
  std::vector<std::pair<std::shared_ptr<ServerChannel>, std::uint32_t>> held;
  std::vector<std::uint32_t> closed;
};

class TransportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    loop_.add_timer(60s, [this] {
      watchdog_ = true;
      loop_.stop();
    });
  }
  void TearDown() override {
    server_.reset();
    EXPECT_FALSE(watchdog_) << "the test timed out";
  }

  void start_server(ServerTransportConfig config = {}) {
    config.host = "127.0.0.1";
    config.port = 0;
    auto server = ServerTransport::start(loop_, std::move(config), handler_);
    ASSERT_TRUE(server.ok()) << server.error().describe();
    server_ = std::move(*server);
  }

  ClientTransportConfig client_config() const {
    ClientTransportConfig c;
    c.endpoint_url = "opc.tcp://127.0.0.1:" + std::to_string(server_->port()) + "/test";
    return c;
  }

  // Runs the loop until pred() holds (checked every millisecond) or the watchdog fires.
  template <typename Pred>
  void run_until(Pred pred) {
    if (pred()) {
      return;
    }
    const auto id = loop_.add_periodic(1ms, [&] {
      if (pred()) {
        loop_.stop();
      }
    });
    loop_.run();
    loop_.cancel_timer(id);
    ASSERT_TRUE(pred()) << "condition not reached";
  }

  Result<std::shared_ptr<ClientChannel>> open(const ClientTransportConfig& config) {
    std::optional<Result<std::shared_ptr<ClientChannel>>> result;
    ClientChannel::open(loop_, config,
                        [&](Result<std::shared_ptr<ClientChannel>> r) { result.emplace(std::move(r)); });
    run_until([&] { return result.has_value(); });
    if (!result) {
      return make_error(Errc::timeout, "open never completed");
    }
    return std::move(*result);
  }

  std::shared_ptr<ClientChannel> open_ok() {
    auto channel = open(client_config());
    EXPECT_TRUE(channel.ok()) << channel.error().describe();
    return channel.ok() ? *channel : nullptr;
  }

  // A TCP connection from `source` that sends only what the test sends; records what the server
  // sends and whether it closed the connection.
  struct RawConnection {
    std::shared_ptr<net::TcpConnection> tcp;
    Bytes received;
    bool closed = false;

    // The status of the ERR the server closed the connection with.
    [[nodiscard]] std::optional<StatusCode> error() const { return error_status(received); }
  };
  std::shared_ptr<RawConnection> raw_connection(const std::string& source = "127.0.0.1") {
    auto s = std::make_shared<RawConnection>();
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in from{};
    from.sin_family = AF_INET;
    ::inet_pton(AF_INET, source.c_str(), &from.sin_addr);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(server_->port());
    ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    // The kernel completes the handshake before the server's loop accepts.
    EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&from), sizeof from), 0);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&to), sizeof to), 0);
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    s->tcp = net::TcpConnection::adopt(loop_, fd, "server");
    RawConnection* raw = s.get();
    s->tcp->set_on_data([raw](ByteSpan b) { raw->received.insert(raw->received.end(), b.begin(), b.end()); });
    s->tcp->set_on_close([raw](const Status&) { raw->closed = true; });
    return s;
  }

  static ReadRequest request(std::uint32_t handle, double size) {
    ReadRequest r = read_request(handle);
    r.max_age = size;
    return r;
  }

  net::EventLoop loop_;
  EchoHandler handler_;
  std::unique_ptr<ServerTransport> server_;
  bool watchdog_ = false;
};

TEST(EndpointUrl, Parses) {
  auto a = parse_endpoint_url("opc.tcp://localhost:4841/UA/Server");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->first, "localhost");
  EXPECT_EQ(a->second, 4841);
  auto b = parse_endpoint_url("OPC.TCP://10.0.0.1");
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(b->first, "10.0.0.1");
  EXPECT_EQ(b->second, 4840);
  auto c = parse_endpoint_url("opc.tcp://[::1]:48400/x");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c->first, "::1");
  EXPECT_EQ(c->second, 48400);
  for (const char* bad : {"http://x:1", "opc.tcp://", "opc.tcp://:4840", "opc.tcp://x:0", "opc.tcp://x:65536",
                          "opc.tcp://x:12a", "opc.tcp://[::1"}) {
    auto r = parse_endpoint_url(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(status_of(r.error()), status::BadTcpEndpointUrlInvalid) << bad;
  }
}

TEST_F(TransportTest, OpensAndReportsTheChannel) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  EXPECT_TRUE(client->is_open());
  EXPECT_NE(client->token().channel_id, 0U);
  EXPECT_EQ(client->token().token_id, 1U);
  EXPECT_EQ(client->negotiated_limits().send_buffer_size, 65535U);
  EXPECT_EQ(server_->channel_count(), 1U);
  bool done = false;
  client->send_request(request(1, 0), 5s, [&](Result<Message> r) {
    ASSERT_TRUE(r.ok()) << r.error().describe();
    done = true;
  });
  run_until([&] { return done; });
  EXPECT_EQ(handler_.last_info.channel_id, client->token().channel_id);
  EXPECT_EQ(handler_.last_info.endpoint_url, client_config().endpoint_url);
  EXPECT_EQ(handler_.last_info.security_policy_uri, kSecurityPolicyNoneUri);
  EXPECT_EQ(handler_.last_info.peer.rfind("127.0.0.1:", 0), 0U);
}

TEST_F(TransportTest, ThousandRequestsInSequence) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  int answered = 0;
  std::function<void(std::uint32_t)> next = [&](std::uint32_t handle) {
    client->send_request(request(handle, 16), 5s, [&, handle](Result<Message> r) {
      ASSERT_TRUE(r.ok()) << r.error().describe();
      const auto& response = std::get<ReadResponse>(*r);
      EXPECT_EQ(response.response_header.request_handle, handle);
      ++answered;
      if (handle < 1000) {
        next(handle + 1);
      }
    });
  };
  next(1);
  run_until([&] { return answered == 1000; });
  EXPECT_EQ(handler_.requests, 1000);
}

TEST_F(TransportTest, PipelinedRequests) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  std::vector<std::uint32_t> order;
  for (std::uint32_t handle = 1; handle <= 300; ++handle) {
    client->send_request(request(handle, 100), 10s, [&order](Result<Message> r) {
      ASSERT_TRUE(r.ok()) << r.error().describe();
      order.push_back(std::get<ReadResponse>(*r).response_header.request_handle);
    });
  }
  EXPECT_EQ(client->pending_requests(), 300U);
  run_until([&] { return order.size() == 300; });
  for (std::uint32_t i = 0; i < 300; ++i) {
    EXPECT_EQ(order[i], i + 1);
  }
}

TEST_F(TransportTest, FiveMegabyteResponseIsChunked) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  std::optional<Result<Message>> result;
  client->send_request(request(9, 5'000'000), 30s, [&](Result<Message> r) { result.emplace(std::move(r)); });
  run_until([&] { return result.has_value(); });
  ASSERT_TRUE(result->ok()) << result->error().describe();
  EXPECT_EQ(std::get<ReadResponse>(**result), read_response(9, 5'000'000));
}

TEST_F(TransportTest, ResponseBeyondTheClientsLimitIsAServiceFault) {
  start_server();
  ClientTransportConfig c = client_config();
  c.limits.max_message_size = 100'000;
  auto client = open(c);
  ASSERT_TRUE(client.ok());
  std::optional<Result<Message>> result;
  (*client)->send_request(request(9, 200'000), 5s, [&](Result<Message> r) { result.emplace(std::move(r)); });
  run_until([&] { return result.has_value(); });
  ASSERT_TRUE(result->ok());
  ASSERT_TRUE(std::holds_alternative<ServiceFault>(**result));
  EXPECT_EQ(std::get<ServiceFault>(**result).response_header.service_result, status::BadResponseTooLarge);
  EXPECT_EQ(std::get<ServiceFault>(**result).response_header.request_handle, 9U);
}

TEST_F(TransportTest, UnknownServiceGetsAServiceFaultFromTheTransport) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  std::optional<Result<Message>> result;
  // A response type sent as a request: not a service the server offers.
  client->send_request(read_response(66), 5s, [&](Result<Message> r) { result.emplace(std::move(r)); });
  run_until([&] { return result.has_value(); });
  ASSERT_TRUE(result->ok());
  ASSERT_TRUE(std::holds_alternative<ServiceFault>(**result));
  EXPECT_EQ(std::get<ServiceFault>(**result).response_header.service_result, status::BadServiceUnsupported);
  EXPECT_EQ(handler_.requests, 0);
}

TEST_F(TransportTest, RequestTimesOutAndALateAnswerIsIgnored) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  int calls = 0;
  std::optional<Error> error;
  client->send_request(request(1, -1), 50ms, [&](Result<Message> r) {
    ++calls;
    ASSERT_FALSE(r.ok());
    error = r.error();
  });
  run_until([&] { return calls == 1; });
  EXPECT_EQ(status_of(*error), status::BadTimeout);
  EXPECT_EQ(client->pending_requests(), 0U);
  // The late answer arrives and is dropped; the channel works on.
  ASSERT_EQ(handler_.held.size(), 1U);
  handler_.held[0].first->send_response(handler_.held[0].second, read_response(1));
  bool done = false;
  client->send_request(request(2, 0), 5s, [&](Result<Message> r) {
    EXPECT_TRUE(r.ok());
    done = true;
  });
  run_until([&] { return done; });
  EXPECT_EQ(calls, 1);
  EXPECT_TRUE(client->is_open());
}

TEST_F(TransportTest, ServerStopFailsEveryPendingRequestExactlyOnce) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  int lost = 0;
  std::optional<Status> lost_status;
  client->set_on_closed([&](const Status& st) {
    ++lost;
    lost_status = st;
  });
  std::map<std::uint32_t, int> calls;
  std::vector<StatusCode> codes;
  for (std::uint32_t handle = 1; handle <= 10; ++handle) {
    client->send_request(request(handle, -1), 30s, [&, handle](Result<Message> r) {
      ++calls[handle];
      ASSERT_FALSE(r.ok());
      codes.push_back(status_of(r.error()));
    });
  }
  run_until([&] { return handler_.held.size() == 10; });
  const std::uint32_t channel_id = client->token().channel_id;
  server_->stop();
  EXPECT_EQ(server_->channel_count(), 0U);
  EXPECT_EQ(handler_.closed, std::vector<std::uint32_t>{channel_id});
  run_until([&] { return calls.size() == 10 && lost == 1; });
  // Let anything still queued run; nothing may be reported twice.
  bool settled = false;
  loop_.add_timer(50ms, [&] { settled = true; });
  run_until([&] { return settled; });
  for (const auto& [handle, n] : calls) {
    EXPECT_EQ(n, 1) << handle;
  }
  for (const StatusCode code : codes) {
    EXPECT_TRUE(code == status::BadSecureChannelClosed || code == status::BadConnectionClosed)
        << to_string(code);
  }
  EXPECT_EQ(lost, 1);
  EXPECT_FALSE(client->is_open());
  // New requests fail at once (from the loop, never inside send_request).
  bool failed = false;
  client->send_request(request(99, 0), 1s, [&](Result<Message> r) { failed = !r.ok(); });
  EXPECT_FALSE(failed);
  run_until([&] { return failed; });
}

TEST_F(TransportTest, ClientCloseIsSeenByTheServer) {
  start_server();
  auto client = open_ok();
  ASSERT_TRUE(client);
  bool pending_failed = false;
  client->send_request(request(1, -1), 30s, [&](Result<Message> r) {
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(status_of(r.error()), status::BadSecureChannelClosed);
    pending_failed = true;
  });
  run_until([&] { return handler_.held.size() == 1; });
  bool lost = false;
  client->set_on_closed([&](const Status&) { lost = true; });
  const std::uint32_t id = client->token().channel_id;
  client->close();
  EXPECT_TRUE(pending_failed);
  EXPECT_FALSE(client->is_open());
  run_until([&] { return !handler_.closed.empty(); });
  EXPECT_EQ(handler_.closed, std::vector<std::uint32_t>{id});
  EXPECT_EQ(server_->channel_count(), 0U);
  EXPECT_FALSE(handler_.held[0].first->is_open());
  EXPECT_FALSE(lost);  // close() is not an unexpected loss
}

// OPC 10000-6 §7.1.5: when every place is taken, a new connection takes the place of the oldest
// connection without a secure channel, then of the oldest channel without an activated session;
// only when every channel holds a session is it refused.
TEST_F(TransportTest, NewConnectionsEvictIdleOnesOldestFirst) {
  ServerTransportConfig config;
  config.max_channels = 3;
  start_server(config);
  auto a = open_ok();  // a channel no session uses
  ASSERT_TRUE(a);
  auto first_silent = raw_connection();
  run_until([&] { return server_->channel_count() == 2; });
  auto second_silent = raw_connection();
  run_until([&] { return server_->channel_count() == 3; });

  auto b = open_ok();  // evicts the older silent connection, though `a` is older still
  ASSERT_TRUE(b);
  run_until([&] { return first_silent->closed; });
  EXPECT_EQ(first_silent->error(), status::BadTcpNotEnoughResources);
  EXPECT_FALSE(second_silent->closed);
  EXPECT_TRUE(a->is_open());

  auto c = open_ok();  // the other silent one
  ASSERT_TRUE(c);
  run_until([&] { return second_silent->closed; });
  EXPECT_TRUE(a->is_open());

  auto d = open_ok();  // now the oldest channel without a session: a
  ASSERT_TRUE(d);
  run_until([&] { return !a->is_open(); });
  EXPECT_EQ(server_->channel_count(), 3U);

  // Sessions on b and d: c is the only one that may go.
  handler_.with_session = {b->token().channel_id, d->token().channel_id};
  auto e = open_ok();
  ASSERT_TRUE(e);
  run_until([&] { return !c->is_open(); });
  handler_.with_session.insert(e->token().channel_id);
  auto refused = open(client_config());
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(status_of(refused.error()), status::BadTcpNotEnoughResources) << refused.error().message;
  EXPECT_EQ(server_->channel_count(), 3U);
  // Those that hold sessions are unaffected.
  bool done = false;
  b->send_request(request(1, 0), 5s, [&](Result<Message> r) {
    EXPECT_TRUE(r.ok());
    done = true;
  });
  run_until([&] { return done; });
  EXPECT_TRUE(d->is_open() && e->is_open());
}

// One source address gets at most max_channels_per_address places; beyond, its own oldest idle
// connection gives way, not another address's.
TEST_F(TransportTest, ConnectionsPerSourceAddress) {
  ServerTransportConfig config;
  config.max_channels = 10;
  config.max_channels_per_address = 2;
  start_server(config);
  auto other = raw_connection("127.0.0.2");
  run_until([&] { return server_->channel_count() == 1; });
  auto s1 = raw_connection();
  auto s2 = raw_connection();
  run_until([&] { return server_->channel_count() == 3; });
  auto s3 = raw_connection();
  run_until([&] { return s1->closed; });
  EXPECT_EQ(s1->error(), status::BadTcpNotEnoughResources);
  auto client = open_ok();  // from 127.0.0.1 too: takes s2's place
  ASSERT_TRUE(client);
  run_until([&] { return s2->closed; });
  EXPECT_FALSE(other->closed);
  EXPECT_FALSE(s3->closed);
  EXPECT_EQ(server_->channel_count(), 3U);
  // With the address's channels all holding sessions, it is refused; others still get in.
  handler_.with_session.insert(client->token().channel_id);
  auto second = open_ok();  // takes s3's place
  ASSERT_TRUE(second);
  handler_.with_session.insert(second->token().channel_id);
  auto refused = open(client_config());
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(status_of(refused.error()), status::BadTcpNotEnoughResources);
  auto from_elsewhere = raw_connection("127.0.0.3");
  run_until([&] { return server_->channel_count() == 4; });
  EXPECT_FALSE(other->closed);
}

TEST_F(TransportTest, ConnectionRefused) {
  start_server();
  ClientTransportConfig c = client_config();
  server_.reset();  // nothing listens on that port any more
  auto channel = open(c);
  ASSERT_FALSE(channel.ok());
  EXPECT_EQ(status_of(channel.error()), status::BadConnectionRejected);
  EXPECT_NE(channel.error().message.find("refused"), std::string::npos) << channel.error().message;
}

TEST_F(TransportTest, BadEndpointUrl) {
  ClientTransportConfig c;
  c.endpoint_url = "http://localhost:4840";
  auto channel = open(c);
  ASSERT_FALSE(channel.ok());
  EXPECT_EQ(status_of(channel.error()), status::BadTcpEndpointUrlInvalid);
}

TEST_F(TransportTest, SilentConnectionIsClosedAfterTheHelloTimeout) {
  ServerTransportConfig config;
  config.hello_timeout = 100ms;
  start_server(config);
  auto raw = raw_connection();
  run_until([&] { return raw->closed; });
  EXPECT_EQ(raw->error(), status::BadTimeout);
  EXPECT_EQ(server_->channel_count(), 0U);
}

TEST_F(TransportTest, GarbageGetsAnErrAndTheServerKeepsServing) {
  start_server();
  auto raw = raw_connection();
  const std::string junk = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";
  raw->tcp->send(ByteSpan(reinterpret_cast<const std::uint8_t*>(junk.data()), junk.size()));
  run_until([&] { return raw->closed; });
  EXPECT_EQ(raw->error(), status::BadTcpMessageTypeInvalid);
  auto client = open_ok();
  EXPECT_TRUE(client && client->is_open());
}

TEST_F(TransportTest, TokensAreRenewedOnTheirOwn) {
  ServerTransportConfig config;
  config.min_token_lifetime_ms = 300;
  start_server(config);
  ClientTransportConfig c = client_config();
  c.requested_lifetime_ms = 300;  // renewal every 225 ms
  auto client = open(c);
  ASSERT_TRUE(client.ok());
  auto channel = *client;
  EXPECT_EQ(channel->token().revised_lifetime, 300U);
  int answered = 0;
  bool failed = false;
  // Keep requests flowing while the token is renewed three times.
  std::function<void()> next = [&] {
    channel->send_request(request(1, 10), 5s, [&](Result<Message> r) {
      if (!r.ok()) {
        failed = true;
        return;
      }
      ++answered;
      if (channel->token().token_id < 4) {
        loop_.add_timer(5ms, next);
      }
    });
  };
  next();
  run_until([&] { return failed || channel->token().token_id >= 4; });
  EXPECT_FALSE(failed);
  EXPECT_TRUE(channel->is_open());
  EXPECT_GT(answered, 3);
  EXPECT_EQ(server_->channel_count(), 1U);
}

}  // namespace
}  // namespace sf::opcua::test
