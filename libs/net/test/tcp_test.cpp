#include "sf/net/tcp.hpp"

#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <optional>

namespace sf::net {
namespace {

using namespace std::chrono_literals;

class TcpTest : public ::testing::Test {
 protected:
  void SetUp() override {
    loop_.add_timer(20s, [this] {
      watchdog_ = true;
      loop_.stop();
    });
  }
  void TearDown() override { EXPECT_FALSE(watchdog_) << "the test timed out"; }

  EventLoop loop_;
  bool watchdog_ = false;
};

Bytes pattern(std::size_t size, std::uint8_t seed) {
  Bytes b(size);
  for (std::size_t i = 0; i < size; ++i) {
    b[i] = static_cast<std::uint8_t>((i * 31U + seed) & 0xFFU);
  }
  return b;
}

// A port on 127.0.0.1 with nothing listening.
std::uint16_t closed_port(EventLoop& loop) {
  auto listener = TcpListener::listen(loop, "127.0.0.1", 0, [](auto) {});
  EXPECT_TRUE(listener.ok());
  return (*listener)->port();
}

TEST_F(TcpTest, EchoOverLoopback) {
  std::vector<std::shared_ptr<TcpConnection>> server_side;
  auto listener = TcpListener::listen(loop_, "127.0.0.1", 0, [&](std::shared_ptr<TcpConnection> c) {
    TcpConnection* raw = c.get();
    c->set_on_data([raw](ByteSpan b) { raw->send(b); });
    server_side.push_back(std::move(c));
  });
  ASSERT_TRUE(listener.ok()) << listener.error().describe();
  EXPECT_NE((*listener)->port(), 0);
  std::shared_ptr<TcpConnection> client;
  std::string received;
  connect_tcp(loop_, "127.0.0.1", (*listener)->port(), 5s, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_TRUE(r.ok()) << r.error().describe();
    client = *r;
    EXPECT_EQ(client->peer().rfind("127.0.0.1:", 0), 0U) << client->peer();
    client->set_on_data([&](ByteSpan b) {
      received.append(reinterpret_cast<const char*>(b.data()), b.size());
      if (received == "hello") {
        loop_.stop();
      }
    });
    const std::string text = "hello";
    client->send(ByteSpan(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  });
  loop_.run();
  EXPECT_EQ(received, "hello");
  ASSERT_EQ(server_side.size(), 1U);
}

TEST_F(TcpTest, LargeTransfersBothWays) {
  constexpr std::size_t kSize = 10U * 1024U * 1024U;
  const Bytes up = pattern(kSize, 1);
  const Bytes down = pattern(kSize, 7);
  Bytes server_got;
  Bytes client_got;
  std::shared_ptr<TcpConnection> server_conn;
  std::shared_ptr<TcpConnection> client;
  int finished = 0;
  auto check_done = [&] {
    if (++finished == 2) {
      loop_.stop();
    }
  };
  auto listener = TcpListener::listen(loop_, "127.0.0.1", 0, [&](std::shared_ptr<TcpConnection> c) {
    server_conn = std::move(c);
    server_conn->set_on_data([&](ByteSpan b) {
      server_got.insert(server_got.end(), b.begin(), b.end());
      if (server_got.size() == kSize) {
        check_done();
      }
    });
    server_conn->send(ByteSpan(down));  // both directions at once
  });
  ASSERT_TRUE(listener.ok());
  connect_tcp(loop_, "localhost", (*listener)->port(), 5s, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_TRUE(r.ok()) << r.error().describe();
    client = *r;
    client->set_on_data([&](ByteSpan b) {
      client_got.insert(client_got.end(), b.begin(), b.end());
      if (client_got.size() == kSize) {
        check_done();
      }
    });
    client->send(ByteSpan(up));
    EXPECT_GT(client->queued_bytes(), 0U);  // 10 MB do not fit the socket buffer
  });
  loop_.run();
  EXPECT_EQ(server_got, up);
  EXPECT_EQ(client_got, down);
  EXPECT_EQ(client->queued_bytes(), 0U);
}

TEST_F(TcpTest, PeerCloseIsReportedOnceAfterTheLastBytes) {
  std::shared_ptr<TcpConnection> client;
  auto listener = TcpListener::listen(loop_, "127.0.0.1", 0, [&](std::shared_ptr<TcpConnection> c) {
    const std::string bye = "bye";
    c->send(ByteSpan(reinterpret_cast<const std::uint8_t*>(bye.data()), bye.size()));
    c->close();  // flushes "bye", then FIN
  });
  ASSERT_TRUE(listener.ok());
  std::string received;
  int closes = 0;
  std::optional<bool> close_ok;
  connect_tcp(loop_, "127.0.0.1", (*listener)->port(), 5s, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_TRUE(r.ok());
    client = *r;
    client->set_on_data(
        [&](ByteSpan b) { received.append(reinterpret_cast<const char*>(b.data()), b.size()); });
    client->set_on_close([&](const Status& st) {
      ++closes;
      close_ok = st.ok();
      loop_.add_timer(10ms, [&] { loop_.stop(); });  // a second close report would land here
    });
  });
  loop_.run();
  EXPECT_EQ(received, "bye");
  EXPECT_EQ(closes, 1);
  EXPECT_EQ(close_ok, true);
  EXPECT_FALSE(client->is_open());
}

TEST_F(TcpTest, AbortReportsCloseFromTheLoop) {
  std::shared_ptr<TcpConnection> server_conn;
  auto listener = TcpListener::listen(loop_, "127.0.0.1", 0,
                                      [&](std::shared_ptr<TcpConnection> c) { server_conn = std::move(c); });
  ASSERT_TRUE(listener.ok());
  bool closed = false;
  std::shared_ptr<TcpConnection> client;
  connect_tcp(loop_, "127.0.0.1", (*listener)->port(), 5s, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_TRUE(r.ok());
    client = *r;
    client->set_on_close([&](const Status&) {
      closed = true;
      loop_.stop();
    });
    client->abort();
    EXPECT_FALSE(closed);          // never from inside abort()
    client->send(Bytes{1, 2, 3});  // ignored after abort
    EXPECT_EQ(client->queued_bytes(), 0U);
  });
  loop_.run();
  EXPECT_TRUE(closed);
}

TEST_F(TcpTest, ConnectRefusedNamesTheAddress) {
  const std::uint16_t port = closed_port(loop_);
  std::optional<Error> error;
  connect_tcp(loop_, "127.0.0.1", port, 5s, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_FALSE(r.ok());
    error = r.error();
    loop_.stop();
  });
  loop_.run();
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->code, Errc::io);
  EXPECT_NE(error->message.find("127.0.0.1:" + std::to_string(port)), std::string::npos) << error->message;
  EXPECT_NE(error->message.find("refused"), std::string::npos) << error->message;
}

TEST_F(TcpTest, UnknownHostFails) {
  std::optional<Error> error;
  connect_tcp(loop_, "no-such-host.invalid", 4840, 5s, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_FALSE(r.ok());
    error = r.error();
    loop_.stop();
  });
  loop_.run();
  ASSERT_TRUE(error.has_value());
  EXPECT_NE(error->message.find("no-such-host.invalid:4840"), std::string::npos) << error->message;
}

TEST_F(TcpTest, ConnectTimesOutWhenTheListenQueueIsFull) {
  // A listener that never accepts, with its queue filled: further SYNs are dropped, so a
  // connect neither succeeds nor fails until our timeout.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(::listen(fd, 0), 0);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  const std::uint16_t port = ntohs(addr.sin_port);
  std::vector<int> fillers;
  for (int i = 0; i < 8; ++i) {
    const int c = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
    (void)::connect(c, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
    fillers.push_back(c);
  }
  std::optional<Error> error;
  connect_tcp(loop_, "127.0.0.1", port, 300ms, [&](Result<std::shared_ptr<TcpConnection>> r) {
    ASSERT_FALSE(r.ok());
    error = r.error();
    loop_.stop();
  });
  loop_.run();
  for (const int c : fillers) {
    ::close(c);
  }
  ::close(fd);
  ASSERT_TRUE(error.has_value());
  EXPECT_EQ(error->code, Errc::timeout) << error->message;
  EXPECT_NE(error->message.find("timed out"), std::string::npos);
}

TEST_F(TcpTest, ListenOnABusyPortFails) {
  auto first = TcpListener::listen(loop_, "127.0.0.1", 0, [](auto) {});
  ASSERT_TRUE(first.ok());
  auto second = TcpListener::listen(loop_, "127.0.0.1", (*first)->port(), [](auto) {});
  ASSERT_FALSE(second.ok());
  EXPECT_NE(second.error().message.find(std::to_string((*first)->port())), std::string::npos);
  EXPECT_NE(second.error().message.find("in use"), std::string::npos) << second.error().message;
}

}  // namespace
}  // namespace sf::net
