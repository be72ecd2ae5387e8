#include "sf/net/tcp.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <vector>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "socket_util.hpp"

namespace sf::net {
namespace {

// Per readiness event, read at most this much so one busy peer cannot starve the others.
constexpr std::size_t kReadBudget = 1024U * 1024U;
constexpr std::size_t kReadChunk = 64U * 1024U;
// After close() flushed, how long to wait for the peer's FIN before closing anyway.
constexpr std::chrono::seconds kLingerTimeout{2};

}  // namespace

std::shared_ptr<TcpConnection> TcpConnection::adopt(EventLoop& loop, int fd, std::string peer) {
  detail::set_no_delay(fd);
  auto conn = std::make_shared<TcpConnection>(Token{}, loop, fd, std::move(peer));
  std::weak_ptr<TcpConnection> weak = conn;
  loop.watch(fd, 0, [weak](unsigned ready) {
    if (auto self = weak.lock()) {
      self->on_ready(ready);
    }
  });
  return conn;
}

TcpConnection::TcpConnection(Token, EventLoop& loop, int fd, std::string peer)
    : loop_(loop), fd_(fd), peer_(std::move(peer)) {}

TcpConnection::~TcpConnection() {
  if (fd_ >= 0) {
    loop_.unwatch(fd_);
    ::close(fd_);
  }
  if (linger_timer_ != 0) {
    loop_.cancel_timer(linger_timer_);
  }
}

void TcpConnection::set_on_data(std::function<void(ByteSpan)> fn) {
  on_data_ = std::move(fn);
  reading_ = true;
  update_interest();
}

void TcpConnection::set_on_close(std::function<void(const Status&)> fn) {
  on_close_ = std::move(fn);
}

void TcpConnection::send(ByteSpan bytes) {
  send(Bytes(bytes.begin(), bytes.end()));
}

void TcpConnection::send(Bytes&& bytes) {
  if (fd_ < 0 || closing_ || bytes.empty()) {
    return;
  }
  queued_ += bytes.size();
  out_.push_back(std::move(bytes));
  if (out_.size() == 1) {
    flush();  // try at once: the socket buffer usually has room
  }
}

void TcpConnection::close() {
  if (fd_ < 0 || closing_) {
    return;
  }
  closing_ = true;
  on_data_ = nullptr;
  // The timer holds the connection, so the owner may drop it right after close().
  linger_timer_ = loop_.add_timer(kLingerTimeout, [self = shared_from_this()] {
    self->linger_timer_ = 0;
    self->finish({});
  });
  if (out_.empty()) {
    shutdown_write();
  }
  update_interest();
}

void TcpConnection::abort() {
  if (fd_ >= 0) {
    finish({});
  }
}

void TcpConnection::on_ready(unsigned ready) {
  auto self = shared_from_this();  // callbacks below may drop the last other reference
  if ((ready & EventLoop::kWritable) != 0U && fd_ >= 0) {
    flush();
  }
  if ((ready & EventLoop::kReadable) != 0U && fd_ >= 0) {
    read_some();
  }
  if ((ready & EventLoop::kError) != 0U && fd_ >= 0) {
    const int err = detail::socket_error(fd_);
    if (err != 0) {
      finish(make_error(Errc::io, fmt::format("connection {}: {}", peer_, detail::errno_text(err))));
    } else if ((ready & EventLoop::kReadable) == 0U) {
      finish({});  // hang-up without readable data left
    }
  }
}

void TcpConnection::read_some() {
  std::uint8_t buffer[kReadChunk];
  std::size_t total = 0;
  while (fd_ >= 0 && total < kReadBudget) {
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    if (n > 0) {
      total += static_cast<std::size_t>(n);
      if (on_data_ && !closing_) {
        on_data_(ByteSpan(buffer, static_cast<std::size_t>(n)));
      }
      continue;
    }
    if (n == 0) {
      finish({});  // orderly shutdown by the peer
      return;
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return;
    }
    finish(make_error(Errc::io, fmt::format("receive from {}: {}", peer_, detail::errno_text(errno))));
    return;
  }
}

void TcpConnection::flush() {
  while (fd_ >= 0 && !out_.empty()) {
    const Bytes& front = out_.front();
    const ssize_t n =
        ::send(fd_, front.data() + out_offset_, front.size() - out_offset_, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        break;
      }
      // Reported from the loop, never from inside the caller's send().
      const auto error =
          make_error(Errc::io, fmt::format("send to {}: {}", peer_, detail::errno_text(errno)));
      std::weak_ptr<TcpConnection> weak = weak_from_this();
      loop_.add_timer(std::chrono::nanoseconds{0}, [weak, error] {
        if (auto self = weak.lock()) {
          self->finish(error);
        }
      });
      out_.clear();
      queued_ = 0;
      out_offset_ = 0;
      update_interest();
      return;
    }
    const auto written = static_cast<std::size_t>(n);
    out_offset_ += written;
    queued_ -= written;
    if (out_offset_ == front.size()) {
      out_.pop_front();
      out_offset_ = 0;
    }
  }
  if (out_.empty() && closing_) {
    shutdown_write();
  }
  update_interest();
}

void TcpConnection::shutdown_write() {
  if (fd_ >= 0 && !write_shut_) {
    write_shut_ = true;
    // FIN after the last byte; the socket stays open for reading until the peer closes, so our
    // last message (an ERR, say) is not destroyed by an RST for unread input.
    ::shutdown(fd_, SHUT_WR);
  }
}

void TcpConnection::update_interest() {
  if (fd_ < 0) {
    return;
  }
  unsigned events = 0;
  if (reading_ || closing_) {
    events |= EventLoop::kReadable;
  }
  if (!out_.empty()) {
    events |= EventLoop::kWritable;
  }
  if (events != interest_) {
    interest_ = events;
    loop_.modify(fd_, events);
  }
}

void TcpConnection::finish(const Status& status) {
  if (fd_ < 0) {
    return;
  }
  auto self = shared_from_this();  // cancelling the linger timer may drop the last other reference
  if (!status.ok()) {
    sf::log::get("net")->debug("{}", status.error().message);
  }
  loop_.unwatch(fd_);
  ::close(fd_);
  fd_ = -1;
  closing_ = true;
  out_.clear();
  queued_ = 0;
  on_data_ = nullptr;
  if (linger_timer_ != 0) {
    loop_.cancel_timer(linger_timer_);
    linger_timer_ = 0;
  }
  // Delivered from the loop so that close()/abort() never call back into their caller.
  auto cb = std::move(on_close_);
  on_close_ = nullptr;
  if (cb) {
    loop_.add_timer(std::chrono::nanoseconds{0}, [self, cb = std::move(cb), status] { cb(status); });
  }
}

// ---- listener ----------------------------------------------------------------------------------

Result<std::unique_ptr<TcpListener>> TcpListener::listen(EventLoop& loop, const std::string& host,
                                                         std::uint16_t port, AcceptFn on_accept) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  const int gai = ::getaddrinfo(host.empty() ? nullptr : host.c_str(), service.c_str(), &hints, &found);
  if (gai != 0) {
    return make_error(Errc::io, fmt::format("listen on {}:{}: {}", host, port, ::gai_strerror(gai)));
  }
  std::string last_error = "no address";
  for (addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    const int fd = ::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (fd < 0) {
      last_error = detail::errno_text(errno);
      continue;
    }
    const int one = 1;
    (void)::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd, ai->ai_addr, ai->ai_addrlen) != 0 || ::listen(fd, SOMAXCONN) != 0) {
      last_error = detail::errno_text(errno);
      ::close(fd);
      continue;
    }
    sockaddr_storage bound{};
    socklen_t len = sizeof bound;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);  // NOLINT
    std::uint16_t bound_port = port;
    if (bound.ss_family == AF_INET) {
      bound_port = ntohs(reinterpret_cast<const sockaddr_in*>(&bound)->sin_port);  // NOLINT
    } else if (bound.ss_family == AF_INET6) {
      bound_port = ntohs(reinterpret_cast<const sockaddr_in6*>(&bound)->sin6_port);  // NOLINT
    }
    ::freeaddrinfo(found);
    auto listener = std::make_unique<TcpListener>(Token{}, loop, fd, bound_port, std::move(on_accept));
    TcpListener* raw = listener.get();
    loop.watch(fd, EventLoop::kReadable, [raw](unsigned) { raw->accept_all(); });
    sf::log::get("net")->debug("listening on {}:{}", host, bound_port);
    return listener;
  }
  ::freeaddrinfo(found);
  return make_error(Errc::io, fmt::format("listen on {}:{}: {}", host, port, last_error));
}

TcpListener::TcpListener(Token, EventLoop& loop, int fd, std::uint16_t port, AcceptFn on_accept)
    : loop_(loop), fd_(fd), port_(port), on_accept_(std::move(on_accept)) {}

TcpListener::~TcpListener() {
  loop_.unwatch(fd_);
  ::close(fd_);
}

void TcpListener::accept_all() {
  for (;;) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    const int fd = ::accept4(fd_, reinterpret_cast<sockaddr*>(&addr), &len,  // NOLINT
                             SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) {
        continue;
      }
      if (errno != EAGAIN && errno != EWOULDBLOCK) {
        // EMFILE and friends: the connection stays in the backlog; log and retry on the next event.
        sf::log::get("net")->warn("accept on port {}: {}", port_, detail::errno_text(errno));
      }
      return;
    }
    auto conn =
        TcpConnection::adopt(loop_, fd, detail::address_text(reinterpret_cast<sockaddr*>(&addr)));  // NOLINT
    on_accept_(std::move(conn));
  }
}

// ---- connect -----------------------------------------------------------------------------------

namespace {

struct Connect : std::enable_shared_from_this<Connect> {
  EventLoop& loop;
  std::string where;  // "host:port" for messages
  std::function<void(Result<std::shared_ptr<TcpConnection>>)> done;
  std::vector<std::pair<sockaddr_storage, socklen_t>> addresses;
  std::size_t next = 0;
  int fd = -1;
  EventLoop::TimerId timer = 0;
  std::string last_error;

  Connect(EventLoop& l, std::string w, std::function<void(Result<std::shared_ptr<TcpConnection>>)> d)
      : loop(l), where(std::move(w)), done(std::move(d)) {}

  void finish(Result<std::shared_ptr<TcpConnection>> result) {
    if (!done) {
      return;
    }
    if (timer != 0) {
      loop.cancel_timer(timer);
      timer = 0;
    }
    auto cb = std::move(done);
    done = nullptr;
    cb(std::move(result));
  }

  void drop_socket() {
    if (fd >= 0) {
      loop.unwatch(fd);
      ::close(fd);
      fd = -1;
    }
  }

  // Tries the next address; on the last failure reports it.
  void try_next() {
    while (next < addresses.size()) {
      const auto& [addr, len] = addresses[next++];
      fd = ::socket(addr.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
      if (fd < 0) {
        last_error = detail::errno_text(errno);
        continue;
      }
      if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), len) == 0 ||
          errno == EINPROGRESS) {  // NOLINT
        auto self = shared_from_this();
        loop.watch(fd, EventLoop::kWritable, [self](unsigned) { self->on_writable(); });
        return;
      }
      last_error = detail::errno_text(errno);
      ::close(fd);
      fd = -1;
    }
    finish(make_error(Errc::io, fmt::format("connect to {}: {}", where, last_error)));
  }

  void on_writable() {
    const int err = detail::socket_error(fd);
    if (err != 0) {
      last_error = detail::errno_text(err);
      drop_socket();
      try_next();
      return;
    }
    loop.unwatch(fd);
    const int connected = fd;
    fd = -1;
    finish(TcpConnection::adopt(loop, connected, detail::peer_text(connected)));
  }

  void on_timeout() {
    timer = 0;
    drop_socket();
    finish(make_error(Errc::timeout, fmt::format("connect to {}: timed out", where)));
  }
};

}  // namespace

void connect_tcp(EventLoop& loop, const std::string& host, std::uint16_t port,
                 std::chrono::milliseconds timeout,
                 std::function<void(Result<std::shared_ptr<TcpConnection>>)> done) {
  auto op = std::make_shared<Connect>(loop, fmt::format("{}:{}", host, port), std::move(done));
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  // Names are resolved synchronously: getaddrinfo has no non-blocking form, and endpoint hosts
  // are numeric or in /etc/hosts in the deployments this serves.
  const int gai = ::getaddrinfo(host.c_str(), service.c_str(), &hints, &found);
  if (gai != 0) {
    const auto error = make_error(Errc::io, fmt::format("connect to {}: {}", op->where, ::gai_strerror(gai)));
    loop.add_timer(std::chrono::nanoseconds{0}, [op, error] { op->finish(error); });
    return;
  }
  for (addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    sockaddr_storage ss{};
    std::memcpy(&ss, ai->ai_addr, ai->ai_addrlen);
    op->addresses.emplace_back(ss, ai->ai_addrlen);
  }
  ::freeaddrinfo(found);
  op->timer = loop.add_timer(timeout, [op] { op->on_timeout(); });
  // Started from the loop so `done` is never called from inside connect_tcp.
  loop.add_timer(std::chrono::nanoseconds{0}, [op] {
    if (op->done) {
      op->try_next();
    }
  });
}

std::string host_name() {
  std::array<char, 256> name{};
  if (::gethostname(name.data(), name.size() - 1) != 0 || name[0] == '\0') {
    return "localhost";
  }
  return name.data();
}

}  // namespace sf::net
