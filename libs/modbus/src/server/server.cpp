#include "sf/modbus/server.hpp"

#include <arpa/inet.h>
#include <modbus.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <optional>
#include <span>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "address.hpp"
#include "request_path.hpp"
#include "server/socket.hpp"
#include "sf/core/log.hpp"
#include "wire.hpp"

namespace sf::modbus {

namespace {

using detail::UniqueFd;

constexpr int kListenBacklog = 64;

// One client connection: its socket and the bytes of a request not yet complete.
struct Connection {
  UniqueFd fd;
  std::array<std::uint8_t, kMaxAduLength> in{};
  std::size_t length = 0;
  Clock::time_point last_active;
};

// MB TCP §3.1.3: the MBAP header is transaction id, protocol id (0 = Modbus), length (the
// bytes that follow: unit id and PDU), unit id. Returns the frame's length, 0 while it is
// incomplete, nothing when the header cannot be a Modbus header (framing is lost).
std::optional<std::size_t> frame_length(std::span<const std::uint8_t> buffered) {
  if (buffered.size() < kMbapLength) {
    return 0;
  }
  const std::uint16_t protocol = wire::load_be16(&buffered[2]);
  const std::uint16_t length = wire::load_be16(&buffered[4]);
  if (protocol != 0 || length < 2 || length > kMaxPduLength + 1) {
    return std::nullopt;
  }
  const std::size_t total = kMbapLength - 1 + length;
  return buffered.size() >= total ? total : 0;
}

struct ContextFree {
  void operator()(modbus_t* ctx) const {
    modbus_set_socket(ctx, -1);  // the sockets are the server's, not the context's
    modbus_free(ctx);
  }
};
using Context = std::unique_ptr<modbus_t, ContextFree>;

using detail::is_ipv4;
using detail::is_ipv6;

// A libmodbus TCP context whose listening socket libmodbus opens (SO_REUSEADDR, bind, listen);
// the same context then answers every connection through modbus_set_socket.
Result<std::pair<Context, UniqueFd>> open_listener(const ServerOptions& options) {
  const bool v4 = is_ipv4(options.host);
  if (!v4 && !is_ipv6(options.host)) {
    return make_error(
        Errc::invalid_argument,
        fmt::format("Modbus server host '{}' is not a numeric IPv4 or IPv6 address", options.host));
  }
  Context ctx(v4 ? modbus_new_tcp(options.host.c_str(), options.port)
                 : modbus_new_tcp_pi(options.host.c_str(), std::to_string(options.port).c_str()));
  if (!ctx) {
    return make_error(Errc::invalid_argument,
                      fmt::format("Modbus server {}: {}", options.host, modbus_strerror(errno)));
  }
  UniqueFd fd(v4 ? modbus_tcp_listen(ctx.get(), kListenBacklog)
                 : modbus_tcp_pi_listen(ctx.get(), kListenBacklog));
  if (!fd.valid() || !detail::set_non_blocking(fd.get())) {
    return make_error(Errc::io, fmt::format("listen on {} port {}: {}", options.host, options.port,
                                            detail::errno_text(errno)));
  }
  return std::pair{std::move(ctx), std::move(fd)};
}

}  // namespace

struct Server::Impl {
  Impl(Device& d, const ServerOptions& o, Context c, UniqueFd listen, UniqueFd wake)
      : device(d),
        options(o),
        clock(o.clock != nullptr ? *o.clock : SteadyClock::instance()),
        ctx(std::move(c)),
        listen_fd(std::move(listen)),
        wake_fd(std::move(wake)),
        port(static_cast<std::uint16_t>(detail::local_port(listen_fd.get()))) {}

  Status poll(int timeout_ms);
  void accept_all();
  void add(UniqueFd fd);
  void evict_idlest();
  bool receive(Connection& c);
  bool serve(Connection& c, std::span<const std::uint8_t> frame);
  void close(Connection& c);

  Device& device;
  ServerOptions options;
  Clock& clock;
  Context ctx;
  UniqueFd listen_fd;
  UniqueFd wake_fd;  // eventfd: stop() wakes the thread out of poll()
  std::uint16_t port;
  std::vector<Connection> connections;
  std::vector<pollfd> poll_fds;
  std::thread thread;
  std::atomic<bool> running{false};
  std::atomic<bool> stopping{false};
  log::Logger log = log::get("modbus");

  std::atomic<std::uint64_t> requests{0}, exceptions{0}, malformed{0}, accepted{0}, refused{0}, evicted{0},
      unanswered{0};
  std::atomic<std::size_t> clients{0};
};

Status Server::Impl::poll(int timeout_ms) {
  poll_fds.clear();
  poll_fds.push_back({listen_fd.get(), POLLIN, 0});
  poll_fds.push_back({wake_fd.get(), POLLIN, 0});
  for (const Connection& c : connections) {
    poll_fds.push_back({c.fd.get(), POLLIN, 0});
  }
  if (::poll(poll_fds.data(), poll_fds.size(), timeout_ms) < 0) {
    return errno == EINTR ? Status{} : make_error(Errc::io, "poll: " + detail::errno_text(errno));
  }
  if (poll_fds[1].revents != 0) {
    std::uint64_t count = 0;
    (void)!::read(wake_fd.get(), &count, sizeof count);
  }
  // Connections first: accepting may evict one, which would shift the indices.
  for (std::size_t i = 0; i < connections.size(); ++i) {
    if (poll_fds[i + 2].revents != 0 && !receive(connections[i])) {
      close(connections[i]);
    }
  }
  std::erase_if(connections, [](const Connection& c) { return !c.fd.valid(); });
  clients = connections.size();
  if (poll_fds[0].revents != 0) {
    accept_all();
  }
  return {};
}

void Server::Impl::accept_all() {
  for (;;) {
    const int fd = ::accept4(listen_fd.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EINTR || errno == ECONNABORTED) {
        continue;
      }
      if (errno != EAGAIN && errno != EWOULDBLOCK) {
        log->warn("modbus server {}: accept: {}", port, detail::errno_text(errno));
      }
      return;
    }
    ++accepted;
    if (device.fault().kind == Fault::Kind::unreachable) {
      ::close(fd);
      ++refused;
      continue;
    }
    detail::set_no_delay(fd);
    add(UniqueFd(fd));
  }
}

void Server::Impl::add(UniqueFd fd) {
  if (connections.size() >= std::max<std::size_t>(options.max_clients, 1)) {
    evict_idlest();
  }
  Connection c;
  c.fd = std::move(fd);
  c.last_active = clock.now();
  connections.push_back(std::move(c));
  clients = connections.size();
}

// The bound on clients: a flood of connections costs the idlest ones, never the server.
void Server::Impl::evict_idlest() {
  const auto idlest =
      std::min_element(connections.begin(), connections.end(),
                       [](const auto& a, const auto& b) { return a.last_active < b.last_active; });
  if (idlest != connections.end()) {
    log->debug("modbus server {}: evicting the idlest of {} connections", port, connections.size());
    connections.erase(idlest);
    ++evicted;
  }
}

void Server::Impl::close(Connection& c) {
  c.fd.reset();
  c.length = 0;
}

// Reads what arrived and serves every complete frame; false when the connection must close.
bool Server::Impl::receive(Connection& c) {
  const ssize_t n = ::recv(c.fd.get(), c.in.data() + c.length, c.in.size() - c.length, 0);
  if (n == 0) {
    return false;
  }
  if (n < 0) {
    return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
  }
  c.length += static_cast<std::size_t>(n);
  c.last_active = clock.now();
  for (;;) {
    const auto buffered = std::span<const std::uint8_t>(c.in.data(), c.length);
    const std::optional<std::size_t> length = frame_length(buffered);
    if (!length) {
      ++malformed;
      log->debug("modbus server {}: broken MBAP header, closing the connection", port);
      return false;
    }
    if (*length == 0) {
      return true;
    }
    if (!serve(c, buffered.first(*length))) {
      return false;
    }
    std::memmove(c.in.data(), c.in.data() + *length, c.length - *length);
    c.length -= *length;
  }
}

// One complete frame: decoded outside the lock, admitted and answered inside it (device.hpp).
bool Server::Impl::serve(Connection& c, std::span<const std::uint8_t> frame) {
  ++requests;
  const detail::Decoded decoded = detail::decode_request(frame[kMbapLength - 1], frame.subspan(kMbapLength));
  if (decoded.refusal == ExceptionCode::illegal_data_value) {
    ++malformed;
  }
  modbus_set_socket(ctx.get(), c.fd.get());
  int rc = 0;
  {
    const std::lock_guard lock(device.mutex());
    const detail::Verdict verdict = detail::admit(device, decoded);
    switch (verdict.kind) {
      case detail::Verdict::Kind::silent:
        ++unanswered;
        return true;
      case detail::Verdict::Kind::exception:
        ++exceptions;
        rc = modbus_reply_exception(ctx.get(), frame.data(), static_cast<unsigned>(verdict.exception));
        break;
      case detail::Verdict::Kind::answer:
        rc = modbus_reply(ctx.get(), frame.data(), static_cast<int>(frame.size()), device.bank().mapping());
        if (decoded.request.writes()) {
          device.after_write(decoded.request);
        }
        break;
    }
  }
  // A response that does not fit the socket's buffer: the client does not read its answers.
  return rc >= 0;
}

Result<std::unique_ptr<Server>> Server::listen(Device& device, const ServerOptions& options) {
  auto listener = open_listener(options);
  if (!listener) {
    return listener.error();
  }
  UniqueFd wake(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC));
  if (!wake.valid()) {
    return make_error(Errc::io, "eventfd: " + detail::errno_text(errno));
  }
  auto impl = std::make_unique<Impl>(device, options, std::move(listener->first), std::move(listener->second),
                                     std::move(wake));
  return std::unique_ptr<Server>(new Server(std::move(impl)));
}

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Server::~Server() {
  stop();
}

std::uint16_t Server::port() const {
  return impl_->port;
}

std::string Server::endpoint() const {
  if (impl_->options.host.find(':') != std::string::npos) {
    return fmt::format("[{}]:{}", impl_->options.host, impl_->port);
  }
  return fmt::format("{}:{}", impl_->options.host, impl_->port);
}

Status Server::start() {
  if (impl_->running.exchange(true)) {
    return make_error(Errc::state, "Modbus server " + endpoint() + " is already running");
  }
  impl_->stopping = false;
  impl_->thread = std::thread([impl = impl_.get()] {
    while (!impl->stopping) {
      if (auto st = impl->poll(-1); !st) {
        impl->log->error("modbus server {}: {}", impl->port, st.error().describe());
        break;
      }
    }
  });
  return {};
}

void Server::stop() {
  if (!impl_->thread.joinable()) {
    return;
  }
  impl_->stopping = true;
  const std::uint64_t one = 1;
  (void)!::write(impl_->wake_fd.get(), &one, sizeof one);
  impl_->thread.join();
  impl_->running = false;
}

bool Server::running() const {
  return impl_->running;
}

Status Server::poll_once(std::chrono::milliseconds timeout) {
  if (impl_->running) {
    return make_error(Errc::state, "Modbus server " + endpoint() + " runs on its own thread");
  }
  return impl_->poll(static_cast<int>(timeout.count()));
}

Status Server::adopt(int fd) {
  UniqueFd owned(fd);
  if (impl_->running) {
    return make_error(Errc::state, "Modbus server " + endpoint() + " runs on its own thread");
  }
  if (!detail::set_non_blocking(fd)) {
    return make_error(Errc::io, "adopt socket: " + detail::errno_text(errno));
  }
  ++impl_->accepted;
  impl_->add(std::move(owned));
  return {};
}

ServerCounters Server::counters() const {
  ServerCounters c;
  c.requests = impl_->requests;
  c.exceptions = impl_->exceptions;
  c.malformed = impl_->malformed;
  c.connections = impl_->accepted;
  c.refused = impl_->refused;
  c.evicted = impl_->evicted;
  c.unanswered = impl_->unanswered;
  c.clients = impl_->clients;
  return c;
}

}  // namespace sf::modbus
