// RawSocketLink: EtherCAT frames on a Linux interface through an AF_PACKET
// raw socket (packet(7)). The socket is created with protocol 0 so it sees no
// traffic until bind() narrows it to ETH_P_ECAT on one interface.
#include <arpa/inet.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "arrival.hpp"
#include "sf/ethercat/link.hpp"

namespace sf::ethercat {
namespace {

Error os_error(std::string_view what, const std::string& interface, int err) {
  return make_error(
      Errc::io, fmt::format("{} on interface '{}': {} (errno {})", what, interface, std::strerror(err), err));
}

// Closes the descriptor unless released (error paths of open()).
class FdGuard {
 public:
  explicit FdGuard(int fd) : fd_(fd) {}
  ~FdGuard() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  FdGuard(const FdGuard&) = delete;
  FdGuard& operator=(const FdGuard&) = delete;
  int release() { return std::exchange(fd_, -1); }
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

Result<MacAddress> interface_mac(int fd, const std::string& interface) {
  ifreq req{};
  std::strncpy(req.ifr_name, interface.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd, SIOCGIFHWADDR, &req) != 0) {
    return os_error("ioctl(SIOCGIFHWADDR)", interface, errno);
  }
  MacAddress mac{};
  std::memcpy(mac.data(), req.ifr_hwaddr.sa_data, mac.size());
  return mac;
}

timespec to_timespec(std::chrono::nanoseconds d) {
  if (d.count() < 0) {
    d = std::chrono::nanoseconds{0};
  }
  const auto secs = std::chrono::duration_cast<std::chrono::seconds>(d);
  return timespec{static_cast<time_t>(secs.count()), static_cast<long>((d - secs).count())};
}

}  // namespace

Result<std::unique_ptr<RawSocketLink>> RawSocketLink::open(const std::string& interface,
                                                           RawSocketOptions options) {
  if (interface.empty() || interface.size() >= IFNAMSIZ) {
    return make_error(Errc::invalid_argument, fmt::format("invalid interface name '{}'", interface));
  }
  const unsigned index = ::if_nametoindex(interface.c_str());
  if (index == 0) {
    return os_error("if_nametoindex", interface, errno);
  }
  FdGuard fd(::socket(AF_PACKET, SOCK_RAW | SOCK_CLOEXEC, 0));
  if (fd.get() < 0) {
    return os_error("socket(AF_PACKET, SOCK_RAW) (needs CAP_NET_RAW)", interface, errno);
  }
  sockaddr_ll addr{};
  addr.sll_family = AF_PACKET;
  addr.sll_protocol = htons(kEtherType);
  addr.sll_ifindex = static_cast<int>(index);
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {  // NOLINT
    return os_error("bind(ETH_P_ECAT)", interface, errno);
  }
  // Promiscuous: slaves answer with the master's source MAC untouched or
  // with a changed one (ETG.1000.4 §5.3), so accept every destination.
  packet_mreq mreq{};
  mreq.mr_ifindex = static_cast<int>(index);
  mreq.mr_type = PACKET_MR_PROMISC;
  if (::setsockopt(fd.get(), SOL_PACKET, PACKET_ADD_MEMBERSHIP, &mreq, sizeof mreq) != 0) {
    return os_error("setsockopt(PACKET_MR_PROMISC)", interface, errno);
  }
  auto mac = interface_mac(fd.get(), interface);
  if (!mac) {
    return mac.error();
  }
  // Best effort, packet(7): our own transmissions are not looped back to us
  // (else every send costs a second receive to skip it). Older kernels lack
  // it; the outgoing copies are then skipped in receive().
  const int one = 1;
  (void)::setsockopt(fd.get(), SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one);
  if (options.max_queue_age.count() > 0) {
    SF_TRY(detail::stamp_arrivals(fd.get(), interface));
  }
  return std::unique_ptr<RawSocketLink>(
      new RawSocketLink(fd.release(), static_cast<int>(index), interface, *mac, options));
}

RawSocketLink::~RawSocketLink() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

Status RawSocketLink::send(ByteSpan frame) {
  if (frame.size() < kEthernetHeaderSize || frame.size() > kMaxFrameSize) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: cannot send a frame of {} bytes (Ethernet: {}-{})", interface_,
                                  frame.size(), kEthernetHeaderSize, kMaxFrameSize));
  }
  while (true) {
    const ssize_t n = ::send(fd_, frame.data(), frame.size(), 0);
    if (n >= 0) {
      if (static_cast<std::size_t>(n) != frame.size()) {
        return make_error(Errc::io, fmt::format("send on interface '{}': {} of {} bytes sent", interface_, n,
                                                frame.size()));
      }
      return {};
    }
    if (errno != EINTR) {
      return os_error("send", interface_, errno);
    }
  }
}

Result<std::optional<std::size_t>> RawSocketLink::read_frame(MutableByteSpan buf) {
  sockaddr_ll from{};
  socklen_t from_len = sizeof from;
  std::optional<std::chrono::nanoseconds> waited;
  const ssize_t n = detail::receive_stamped(fd_, buf, MSG_TRUNC | MSG_DONTWAIT,
                                            reinterpret_cast<sockaddr*>(&from), &from_len, waited);  // NOLINT
  if (n < 0) {
    if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) {
      return std::optional<std::size_t>{};
    }
    return os_error("recvmsg", interface_, errno);
  }
  if (detail::too_old(waited, options_.max_queue_age)) {
    ++stale_;
    return std::optional<std::size_t>{};
  }
  // Our own transmissions, where the kernel still loops them back: skip.
  if (from.sll_pkttype == PACKET_OUTGOING) {
    return std::optional<std::size_t>{};
  }
  const auto size = static_cast<std::size_t>(n);
  if (size > buf.size()) {
    return make_error(Errc::out_of_range, fmt::format("{}: frame of {} bytes dropped, receive buffer has {}",
                                                      interface_, size, buf.size()));
  }
  if (!is_ethercat_frame(buf.first(size))) {
    return std::optional<std::size_t>{};
  }
  return std::optional<std::size_t>{size};
}

Result<std::size_t> RawSocketLink::receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) {
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + timeout;
  // First spin on non-blocking reads (no wake-up latency for a frame that
  // comes back quickly), then sleep in ppoll for the rest of the timeout.
  const auto spin_until = start + std::min(timeout, options_.busy_poll);
  while (std::chrono::steady_clock::now() < spin_until) {
    auto got = read_frame(buf);
    if (!got || *got) {
      return got ? Result<std::size_t>{**got} : Result<std::size_t>{got.error()};
    }
  }
  while (true) {
    pollfd pfd{fd_, POLLIN, 0};
    const timespec ts = to_timespec(deadline - std::chrono::steady_clock::now());
    const int ready = ::ppoll(&pfd, 1, &ts, nullptr);
    if (ready < 0) {
      if (errno == EINTR) {
        continue;
      }
      return os_error("ppoll", interface_, errno);
    }
    if (ready == 0) {
      return std::size_t{0};
    }
    auto got = read_frame(buf);
    if (!got) {
      return got.error();
    }
    if (*got) {
      return **got;
    }
  }
}

}  // namespace sf::ethercat
