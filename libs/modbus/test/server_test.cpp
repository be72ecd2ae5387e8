// The TCP server on the bytes no client would send, its bounds, its fault modes at the socket,
// and the two ways to run it (own thread, poll_once).
#include "sf/modbus/server.hpp"

#include <sys/socket.h>

#include <atomic>
#include <thread>

#include <gtest/gtest.h>

#include "sf/core/clock.hpp"
#include "sf/modbus/tcp_client.hpp"
#include "test_support.hpp"

namespace sf::modbus::test {
namespace {

using namespace std::chrono_literals;

class ServerTest : public ::testing::Test {
 protected:
  void start(const ServerOptions& options = {}) {
    auto server = Server::listen(device_, options);
    ASSERT_TRUE(server.ok()) << server.error().describe();
    server_ = std::move(*server);
    ASSERT_TRUE(server_->start().ok());
  }

  // A read of holding register 1000 with the given transaction id.
  static std::vector<std::uint8_t> good_request(std::uint16_t transaction) {
    return adu(transaction, 1, pdu(0x03, {1000, 1}));
  }

  static void expect_answer(RawConnection& c, std::uint16_t transaction) {
    const auto r = c.read_response();
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->transaction, transaction);
    EXPECT_EQ(r->function, 0x03);
    EXPECT_FALSE(r->is_exception());
  }

  static void expect_exception(RawConnection& c, std::uint8_t function, std::uint8_t code) {
    const auto r = c.read_response();
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->function, function | 0x80U);
    EXPECT_EQ(r->exception_code(), code);
  }

  RecordingDevice device_;
  std::unique_ptr<Server> server_;
};

TEST_F(ServerTest, ReportsTheEphemeralPortItBound) {
  start();
  EXPECT_NE(server_->port(), 0);
  EXPECT_EQ(server_->endpoint(), "127.0.0.1:" + std::to_string(server_->port()));
}

TEST_F(ServerTest, UnknownFunctionIsIllegalFunctionAndTheConnectionStays) {
  start();
  RawConnection c(server_->port());
  ASSERT_TRUE(c.send(adu(1, 1, pdu(0x41, {0, 1}))));
  expect_exception(c, 0x41, 0x01);
  ASSERT_TRUE(c.send(adu(2, 1, std::vector<std::uint8_t>{0x2B, 0x0E, 0x01, 0x00})));  // device identification
  expect_exception(c, 0x2B, 0x01);
  ASSERT_TRUE(c.send(good_request(3)));
  expect_answer(c, 3);
}

TEST_F(ServerTest, QuantityOutsideTheLimitsIsIllegalDataValue) {
  start();
  RawConnection c(server_->port());
  ASSERT_TRUE(c.send(adu(1, 1, pdu(0x03, {1000, 0}))));
  expect_exception(c, 0x03, 0x03);
  ASSERT_TRUE(c.send(adu(2, 1, pdu(0x03, {1000, 126}))));
  expect_exception(c, 0x03, 0x03);
  ASSERT_TRUE(c.send(adu(3, 1, pdu(0x01, {0, 2001}))));
  expect_exception(c, 0x01, 0x03);
  ASSERT_TRUE(c.send(adu(4, 1, pdu(0x05, {0, 0x1234}))));  // a coil is 0xFF00 or 0x0000
  expect_exception(c, 0x05, 0x03);
  ASSERT_TRUE(c.send(adu(5, 1, pdu(0x03, {5000, 1}))));
  expect_exception(c, 0x03, 0x02);
  EXPECT_EQ(server_->counters().exceptions, 5U);
}

TEST_F(ServerTest, PduThatDoesNotFitItsFunctionIsIllegalDataValue) {
  start();
  RawConnection c(server_->port());
  ASSERT_TRUE(c.send(adu(1, 1, pdu(0x03, {1000, 1, 7}))));  // two bytes too many
  expect_exception(c, 0x03, 0x03);
  auto short_write = pdu(0x10, {1000, 2});
  short_write.insert(short_write.end(), {4, 0, 1});  // byte count 4, three bytes
  ASSERT_TRUE(c.send(adu(2, 1, short_write)));
  expect_exception(c, 0x10, 0x03);
  ASSERT_TRUE(c.send(adu(3, 1, std::vector<std::uint8_t>{0x03})));  // function code alone
  expect_exception(c, 0x03, 0x03);
  ASSERT_TRUE(c.send(good_request(4)));
  expect_answer(c, 4);
  EXPECT_EQ(server_->counters().malformed, 3U);
  EXPECT_EQ(device_.bank().holding_register(1000), 0);
}

TEST_F(ServerTest, BrokenMbapHeaderClosesOnlyThatConnection) {
  start();
  RawConnection good(server_->port());
  ASSERT_TRUE(good.send(good_request(1)));
  expect_answer(good, 1);

  const std::vector<std::vector<std::uint8_t>> broken{
      adu(1, 1, pdu(0x03, {1000, 1}), std::nullopt, /*protocol=*/1),
      adu(1, 1, pdu(0x03, {1000, 1}), /*length=*/0),
      adu(1, 1, pdu(0x03, {1000, 1}), /*length=*/1),
      adu(1, 1, pdu(0x03, {1000, 1}), /*length=*/300),
      {'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P', '/', '1', '.', '1', '\r', '\n'},
  };
  for (const auto& bytes : broken) {
    RawConnection bad(server_->port());
    ASSERT_TRUE(bad.send(bytes));
    EXPECT_TRUE(bad.closed_by_peer());
  }
  EXPECT_EQ(server_->counters().malformed, broken.size());

  ASSERT_TRUE(good.send(good_request(2)));
  expect_answer(good, 2);
  RawConnection next(server_->port());
  ASSERT_TRUE(next.send(good_request(3)));
  expect_answer(next, 3);
}

TEST_F(ServerTest, AHalfSentRequestDoesNotHoldUpOtherClients) {
  start();
  RawConnection slow(server_->port());
  const auto request = good_request(7);
  ASSERT_TRUE(slow.send({request.begin(), request.begin() + 5}));
  RawConnection other(server_->port());
  ASSERT_TRUE(other.send(good_request(8)));
  expect_answer(other, 8);
  ASSERT_TRUE(slow.send({request.begin() + 5, request.end()}));
  expect_answer(slow, 7);
}

TEST_F(ServerTest, PipelinedRequestsAreAnsweredInOrder) {
  start();
  RawConnection c(server_->port());
  auto both = good_request(1);
  const auto second = adu(2, 1, pdu(0x06, {1001, 99}));
  both.insert(both.end(), second.begin(), second.end());
  ASSERT_TRUE(c.send(both));
  expect_answer(c, 1);
  const auto r = c.read_response();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->transaction, 2);
  EXPECT_EQ(r->function, 0x06);
}

TEST_F(ServerTest, ServesManyClientsAtOnce) {
  start(ServerOptions{.max_clients = 16});
  constexpr int kClients = 12;
  constexpr int kRounds = 40;
  std::atomic<int> failures{0};
  std::vector<std::thread> threads;
  threads.reserve(kClients);
  for (int i = 0; i < kClients; ++i) {
    threads.emplace_back([&, i] {
      auto client = TcpClient::create(TcpClientOptions{.port = server_->port()});
      if (!client) {
        ++failures;
        return;
      }
      const auto address = static_cast<std::uint16_t>(1000 + i);
      for (int round = 0; round < kRounds; ++round) {
        const auto value = static_cast<std::uint16_t>(round * 100 + i);
        if (!(*client)->write_single_register(address, value).ok()) {
          ++failures;
        }
        auto back = (*client)->read_holding_registers(address, 1);
        if (!back.ok() || (*back)[0] != value) {
          ++failures;
        }
      }
    });
  }
  for (auto& t : threads) {
    t.join();
  }
  EXPECT_EQ(failures, 0);
  const ServerCounters counters = server_->counters();
  EXPECT_EQ(counters.requests, std::uint64_t{kClients} * kRounds * 2);
  EXPECT_EQ(counters.connections, std::uint64_t{kClients});
  EXPECT_EQ(counters.evicted, 0U);
}

TEST_F(ServerTest, AFullServerEvictsTheIdlestConnection) {
  ManualClock clock;
  auto server = Server::listen(device_, ServerOptions{.max_clients = 2, .clock = &clock});
  ASSERT_TRUE(server.ok());
  server_ = std::move(*server);
  // Driven step by step, so each connection is accepted at a known time.
  auto accept_one = [&](RawConnection& c) {
    ASSERT_TRUE(c.connected());
    const auto before = server_->counters().connections;
    for (int i = 0; i < 100 && server_->counters().connections == before; ++i) {
      ASSERT_TRUE(server_->poll_once(50ms).ok());
    }
    clock.advance(1s);
  };
  RawConnection a(server_->port());
  accept_one(a);
  RawConnection b(server_->port());
  accept_one(b);
  ASSERT_TRUE(a.send(good_request(1)));  // a is now the most recently active
  for (int i = 0; i < 100 && server_->counters().requests == 0; ++i) {
    ASSERT_TRUE(server_->poll_once(50ms).ok());
  }
  expect_answer(a, 1);
  clock.advance(1s);
  RawConnection c(server_->port());
  accept_one(c);

  EXPECT_TRUE(b.closed_by_peer());
  const ServerCounters counters = server_->counters();
  EXPECT_EQ(counters.evicted, 1U);
  EXPECT_EQ(counters.clients, 2U);
  ASSERT_TRUE(server_->start().ok());
  ASSERT_TRUE(a.send(good_request(2)));
  expect_answer(a, 2);
  ASSERT_TRUE(c.send(good_request(3)));
  expect_answer(c, 3);
}

TEST_F(ServerTest, UnreachableDropsRequestsAndRefusesConnections) {
  // Driven step by step, so each request and connection is handled in a known order.
  auto server = Server::listen(device_, ServerOptions{});
  ASSERT_TRUE(server.ok());
  server_ = std::move(*server);
  auto serve_until = [&](auto done) {
    for (int i = 0; i < 100 && !done(server_->counters()); ++i) {
      ASSERT_TRUE(server_->poll_once(50ms).ok());
    }
  };
  RawConnection existing(server_->port());
  ASSERT_TRUE(existing.send(good_request(1)));
  serve_until([](const ServerCounters& c) { return c.requests == 1; });
  expect_answer(existing, 1);

  device_.set_fault(Fault::unreachable());
  ASSERT_TRUE(existing.send(good_request(2)));
  serve_until([](const ServerCounters& c) { return c.unanswered == 1; });
  RawConnection fresh(server_->port());
  serve_until([](const ServerCounters& c) { return c.refused == 1; });
  EXPECT_TRUE(fresh.closed_by_peer());

  device_.set_fault(Fault{});
  ASSERT_TRUE(existing.send(good_request(3)));
  serve_until([](const ServerCounters& c) { return c.requests == 3; });
  expect_answer(existing, 3);  // request 2 was dropped, not answered late
  const ServerCounters counters = server_->counters();
  EXPECT_EQ(counters.unanswered, 1U);
  EXPECT_EQ(counters.refused, 1U);
  EXPECT_EQ(counters.clients, 1U);
}

TEST_F(ServerTest, UnreachableIsAConnectionErrorForANewClient) {
  start();
  device_.set_fault(Fault::unreachable());
  auto client = TcpClient::create(TcpClientOptions{.port = server_->port(), .response_timeout = 200ms});
  ASSERT_TRUE(client.ok());
  auto r = (*client)->read_holding_registers(1000, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(r.error().code == Errc::io || r.error().code == Errc::timeout) << r.error().describe();
  EXPECT_FALSE(r.error().exception.has_value());
}

TEST_F(ServerTest, ExceptionFaultAnswersEvenUnknownFunctions) {
  start();
  device_.set_fault(Fault::answer(ExceptionCode::server_device_busy));
  RawConnection c(server_->port());
  ASSERT_TRUE(c.send(adu(1, 1, pdu(0x41, {0, 1}))));
  expect_exception(c, 0x41, 0x06);
  ASSERT_TRUE(c.send(good_request(2)));
  expect_exception(c, 0x03, 0x06);
}

TEST_F(ServerTest, EchoesTransactionAndUnitIds) {
  start();
  RawConnection c(server_->port());
  ASSERT_TRUE(c.send(adu(0xBEEF, 42, pdu(0x03, {1000, 2}))));
  const auto r = c.read_response();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->transaction, 0xBEEF);
  EXPECT_EQ(r->unit, 42);
  EXPECT_EQ(r->body, (std::vector<std::uint8_t>{4, 0, 0, 0, 0}));
  const std::lock_guard lock(device_.mutex());
  ASSERT_FALSE(device_.before.empty());
  EXPECT_EQ(device_.before.back().unit_id, 42);
}

TEST_F(ServerTest, PollOnceServesWithoutAThread) {
  auto server = Server::listen(device_, ServerOptions{});
  ASSERT_TRUE(server.ok());
  server_ = std::move(*server);
  RawConnection c(server_->port());
  ASSERT_TRUE(c.send(good_request(1)));
  for (int i = 0; i < 100 && server_->counters().requests == 0; ++i) {
    ASSERT_TRUE(server_->poll_once(50ms).ok());
  }
  expect_answer(c, 1);
}

TEST_F(ServerTest, AdoptsAConnectedSocket) {
  auto server = Server::listen(device_, ServerOptions{});
  ASSERT_TRUE(server.ok());
  server_ = std::move(*server);
  int fds[2];
  ASSERT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds), 0);
  ASSERT_TRUE(server_->adopt(fds[0]).ok());
  RawConnection c(fds[1]);
  ASSERT_TRUE(c.send(good_request(5)));
  ASSERT_TRUE(server_->poll_once(0ms).ok());
  expect_answer(c, 5);
  EXPECT_EQ(server_->counters().connections, 1U);
}

TEST_F(ServerTest, OneWayOfRunningAtATime) {
  start();
  EXPECT_EQ(server_->start().error().code, Errc::state);
  EXPECT_EQ(server_->poll_once(0ms).error().code, Errc::state);
  server_->stop();
  EXPECT_FALSE(server_->running());
  EXPECT_TRUE(server_->poll_once(0ms).ok());
  EXPECT_TRUE(server_->start().ok());
}

TEST_F(ServerTest, RefusesHostsItCannotBind) {
  auto named = Server::listen(device_, ServerOptions{.host = "localhost"});
  ASSERT_FALSE(named.ok());
  EXPECT_EQ(named.error().code, Errc::invalid_argument);

  start();
  auto taken = Server::listen(device_, ServerOptions{.port = server_->port()});
  ASSERT_FALSE(taken.ok());
  EXPECT_EQ(taken.error().code, Errc::io);
}

TEST_F(ServerTest, ListensOnIpv6) {
  auto server = Server::listen(device_, ServerOptions{.host = "::1"});
  if (!server.ok()) {
    GTEST_SKIP() << "no IPv6 loopback here: " << server.error().describe();
  }
  server_ = std::move(*server);
  ASSERT_TRUE(server_->start().ok());
  auto client = TcpClient::create(TcpClientOptions{.host = "::1", .port = server_->port()});
  ASSERT_TRUE(client.ok());
  EXPECT_TRUE((*client)->read_holding_registers(1000, 1).ok());
  EXPECT_EQ(server_->endpoint(), "[::1]:" + std::to_string(server_->port()));
}

}  // namespace
}  // namespace sf::modbus::test
