// Non-blocking TCP over EventLoop: connections with buffered in-order sends, a listener and an
// asynchronous connect with timeout. Everything here runs on the loop thread only.
// TCP_NODELAY is set on every connection, SO_REUSEADDR on listeners, and sends use
// MSG_NOSIGNAL so a closed peer gives EPIPE instead of SIGPIPE.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <string>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/net/event_loop.hpp"

namespace sf::net {

class TcpConnection : public std::enable_shared_from_this<TcpConnection> {
 private:
  struct Token {};

 public:
  // Takes ownership of a connected non-blocking socket (use listen/connect_tcp instead).
  static std::shared_ptr<TcpConnection> adopt(EventLoop& loop, int fd, std::string peer);
  TcpConnection(Token, EventLoop& loop, int fd, std::string peer);
  ~TcpConnection();
  TcpConnection(const TcpConnection&) = delete;
  TcpConnection& operator=(const TcpConnection&) = delete;

  // Bytes as they arrive. Setting it starts reading.
  void set_on_data(std::function<void(ByteSpan)> fn);
  // Called once: the peer closed (ok Status), an error (Errc::io with errno text), or close()/
  // abort() (ok Status). After it, no callback is called again.
  void set_on_close(std::function<void(const Status&)> fn);
  // Buffered, non-blocking, in order. Ignored after close()/abort().
  void send(ByteSpan bytes);
  void send(Bytes&& bytes);
  // Stops delivering data, flushes what is queued, then closes (the connection keeps itself
  // alive until then, so the owner may drop it right after close()).
  void close();
  // Closes now, dropping queued bytes.
  void abort();
  [[nodiscard]] bool is_open() const { return fd_ >= 0 && !closing_; }
  [[nodiscard]] std::size_t queued_bytes() const { return queued_; }
  // "127.0.0.1:53124"
  [[nodiscard]] const std::string& peer() const { return peer_; }
  [[nodiscard]] EventLoop& loop() { return loop_; }

 private:
  void on_ready(unsigned ready);
  void read_some();
  void flush();
  void update_interest();
  void finish(const Status& status);
  void shutdown_write();

  EventLoop& loop_;
  int fd_;
  std::string peer_;
  std::function<void(ByteSpan)> on_data_;
  std::function<void(const Status&)> on_close_;
  std::deque<Bytes> out_;
  std::size_t out_offset_ = 0;  // bytes of out_.front() already written
  std::size_t queued_ = 0;
  unsigned interest_ = 0;
  bool closing_ = false;
  bool reading_ = false;
  bool write_shut_ = false;
  EventLoop::TimerId linger_timer_ = 0;  // owns a reference to this connection while closing
};

class TcpListener {
 private:
  struct Token {};

 public:
  using AcceptFn = std::function<void(std::shared_ptr<TcpConnection>)>;
  // Binds host:port (port 0 = any free port) and calls on_accept for every new connection.
  static Result<std::unique_ptr<TcpListener>> listen(EventLoop& loop, const std::string& host,
                                                     std::uint16_t port, AcceptFn on_accept);
  TcpListener(Token, EventLoop& loop, int fd, std::uint16_t port, AcceptFn on_accept);
  // Closes the socket (loop thread).
  ~TcpListener();
  TcpListener(const TcpListener&) = delete;
  TcpListener& operator=(const TcpListener&) = delete;

  // The bound port.
  [[nodiscard]] std::uint16_t port() const { return port_; }

 private:
  void accept_all();

  EventLoop& loop_;
  int fd_;
  std::uint16_t port_;
  AcceptFn on_accept_;
};

// Resolves host (numeric, or a name via getaddrinfo), connects non-blocking and calls done on
// the loop thread exactly once: the connection, or an error naming host:port and the errno text
// (Errc::io; Errc::timeout after timeout). Call on the loop thread.
void connect_tcp(EventLoop& loop, const std::string& host, std::uint16_t port,
                 std::chrono::milliseconds timeout,
                 std::function<void(Result<std::shared_ptr<TcpConnection>>)> done);

// This host's name (gethostname), "localhost" when it has none: what a server advertises and what
// its own certificate names.
std::string host_name();

}  // namespace sf::net
