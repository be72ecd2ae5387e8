// UdpLink (link.hpp): EtherCAT frames carried in UDP datagrams.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

#include <fmt/format.h>

#include "arrival.hpp"
#include "sf/core/bytes.hpp"
#include "sf/ethercat/link.hpp"

namespace sf::ethercat {

struct UdpLink::Peer {
  sockaddr_in addr{};
  bool known = false;
};

namespace {

constexpr MacAddress kUdpLocalMac{0x02, 0x00, 0x00, 0x88, 0xa4, 0x01};
constexpr MacAddress kUdpPeerMac{0x02, 0x00, 0x00, 0x88, 0xa4, 0x02};
constexpr std::uint8_t kEcatTypeCommands = 1;  // EtherCAT header type 1: datagrams follow

Error os_error(std::string_view what, int err) {
  return make_error(Errc::io, fmt::format("udp link: {}: {} (errno {})", what, std::strerror(err), err));
}

Result<sockaddr_in> resolve(const std::string& host, std::uint16_t port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    return make_error(Errc::invalid_argument,
                      fmt::format("udp link: '{}' is not a numeric IPv4 address", host));
  }
  return addr;
}

// A UDP socket to or from host:port: connect() for a master, bind() for a segment.
Result<std::pair<int, sockaddr_in>> open_socket(const std::string& host, std::uint16_t port, bool bind) {
  auto addr = resolve(host, port);
  if (!addr) {
    return addr.error();
  }
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    return os_error("socket(AF_INET, SOCK_DGRAM)", errno);
  }
  const auto* sa = reinterpret_cast<const sockaddr*>(&*addr);  // NOLINT
  if ((bind ? ::bind(fd, sa, sizeof *addr) : ::connect(fd, sa, sizeof *addr)) != 0) {
    const int err = errno;
    ::close(fd);
    return os_error(fmt::format("{} {}:{}", bind ? "bind" : "connect to", host, port), err);
  }
  return std::pair{fd, *addr};
}

std::uint16_t bound_port(int fd) {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);  // NOLINT
  return ntohs(addr.sin_port);
}

// The offset of the EtherCAT header in an Ethernet frame (after one VLAN tag, if any).
std::size_t ecat_offset(ByteSpan frame) {
  const auto type = static_cast<std::uint16_t>(frame[12] << 8 | frame[13]);
  return type == kVlanEtherType ? kEthernetHeaderSize + kVlanTagSize : kEthernetHeaderSize;
}

// True when the payload starts with a type-1 EtherCAT header whose length fits.
bool is_ecat_payload(ByteSpan payload) {
  if (payload.size() < kEcatHeaderSize) {
    return false;
  }
  const auto header = static_cast<std::uint16_t>(payload[0] | payload[1] << 8);
  const std::size_t length = header & 0x07FFU;
  const unsigned type = header >> 12U;
  return type == kEcatTypeCommands && length + kEcatHeaderSize <= payload.size();
}

}  // namespace

UdpLink::UdpLink(int fd, bool listening, std::uint16_t local_port, std::string name)
    : fd_(fd),
      listening_(listening),
      local_port_(local_port),
      name_(std::move(name)),
      mac_(kUdpLocalMac),
      peer_(std::make_unique<Peer>()) {}

UdpLink::~UdpLink() {
  ::close(fd_);
}

Result<std::unique_ptr<UdpLink>> UdpLink::connect(const std::string& host, std::uint16_t port) {
  auto socket = open_socket(host, port, false);
  if (!socket) {
    return socket.error();
  }
  const auto [fd, addr] = *socket;
  auto link =
      std::unique_ptr<UdpLink>(new UdpLink(fd, false, bound_port(fd), fmt::format("udp:{}:{}", host, port)));
  link->peer_->addr = addr;
  link->peer_->known = true;
  return link;
}

Result<std::unique_ptr<UdpLink>> UdpLink::listen(const std::string& host, std::uint16_t port,
                                                 std::chrono::nanoseconds max_queue_age) {
  auto socket = open_socket(host, port, true);
  if (!socket) {
    return socket.error();
  }
  const int fd = socket->first;
  const std::uint16_t local = bound_port(fd);
  auto link = std::unique_ptr<UdpLink>(new UdpLink(fd, true, local, fmt::format("udp:{}:{}", host, local)));
  if (max_queue_age.count() > 0) {
    SF_TRY(detail::stamp_arrivals(fd, link->name_));
    link->max_queue_age_ = max_queue_age;
  }
  return link;
}

std::string UdpLink::name() const {
  return name_;
}

Status UdpLink::send(ByteSpan frame) {
  if (frame.size() < kEthernetHeaderSize + kEcatHeaderSize || frame.size() > kMaxFrameSize + kVlanTagSize) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: cannot send a frame of {} bytes", name_, frame.size()));
  }
  const ByteSpan payload = frame.subspan(ecat_offset(frame));
  sockaddr_in to{};
  {
    std::lock_guard lock(peer_mutex_);
    if (!peer_->known) {
      return make_error(Errc::state, fmt::format("{}: no master has sent a frame yet", name_));
    }
    to = peer_->addr;
  }
  while (true) {
    const ssize_t n = listening_ ? ::sendto(fd_, payload.data(), payload.size(), 0,
                                            reinterpret_cast<const sockaddr*>(&to), sizeof to)  // NOLINT
                                 : ::send(fd_, payload.data(), payload.size(), 0);
    if (n >= 0) {
      return {};
    }
    if (errno != EINTR) {
      return os_error(fmt::format("send on {}", name_), errno);
    }
  }
}

Result<std::size_t> UdpLink::receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) {
  if (buf.size() < kEthernetHeaderSize + kEcatHeaderSize) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: receive buffer of {} bytes", name_, buf.size()));
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left =
        std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - std::chrono::steady_clock::now());
    const timespec ts{static_cast<time_t>(std::max<std::int64_t>(left.count(), 0) / 1'000'000'000),
                      static_cast<long>(std::max<std::int64_t>(left.count(), 0) % 1'000'000'000)};
    pollfd pfd{fd_, POLLIN, 0};
    const int ready = ::ppoll(&pfd, 1, &ts, nullptr);
    if (ready < 0) {
      if (errno == EINTR) {
        continue;
      }
      return os_error("ppoll", errno);
    }
    if (ready == 0) {
      return std::size_t{0};
    }
    sockaddr_in from{};
    socklen_t from_len = sizeof from;
    const MutableByteSpan payload = buf.subspan(kEthernetHeaderSize);
    std::optional<std::chrono::nanoseconds> waited;
    const ssize_t n =
        detail::receive_stamped(fd_, payload, MSG_TRUNC | MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&from),
                                &from_len, waited);  // NOLINT
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK || errno == ECONNREFUSED) {
        continue;  // ECONNREFUSED: an earlier send found no segment listening yet
      }
      return os_error(fmt::format("recvmsg on {}", name_), errno);
    }
    if (detail::too_old(waited, max_queue_age_)) {
      ++stale_;
      continue;
    }
    const auto size = static_cast<std::size_t>(n);
    if (size > payload.size() || !is_ecat_payload(payload.first(size))) {
      ++skipped_;
      continue;
    }
    if (listening_) {
      std::lock_guard lock(peer_mutex_);
      peer_->addr = from;
      peer_->known = true;
    }
    std::copy(mac_.begin(), mac_.end(), buf.begin());
    std::copy(kUdpPeerMac.begin(), kUdpPeerMac.end(), buf.begin() + 6);
    buf[12] = static_cast<std::uint8_t>(kEtherType >> 8);
    buf[13] = static_cast<std::uint8_t>(kEtherType & 0xFF);
    return kEthernetHeaderSize + size;
  }
}

Result<std::unique_ptr<Link>> open_link(const std::string& spec, RawSocketOptions raw_options) {
  if (spec.rfind("udp:", 0) != 0) {
    auto raw = RawSocketLink::open(spec, raw_options);
    if (!raw) {
      return raw.error();
    }
    return std::unique_ptr<Link>(std::move(*raw));
  }
  const std::string rest = spec.substr(4);
  const auto colon = rest.rfind(':');
  std::string host = rest;
  std::uint16_t port = UdpLink::kPort;
  if (colon != std::string::npos) {
    host = rest.substr(0, colon);
    const std::string p = rest.substr(colon + 1);
    const auto [ptr, ec] = std::from_chars(p.data(), p.data() + p.size(), port);
    if (ec != std::errc{} || ptr != p.data() + p.size() || port == 0) {
      return make_error(Errc::invalid_argument, fmt::format("link '{}': port '{}' is not 1..65535", spec, p));
    }
  }
  auto udp = UdpLink::connect(host, port);
  if (!udp) {
    return udp.error();
  }
  return std::unique_ptr<Link>(std::move(*udp));
}

}  // namespace sf::ethercat
