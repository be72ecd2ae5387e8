// Arrival stamps of the socket links (arrival.hpp).
#include "arrival.hpp"

#include <sys/uio.h>
#include <time.h>

#include <array>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "sf/core/text.hpp"

namespace sf::ethercat::detail {

Status stamp_arrivals(int fd, std::string_view link) {
  const int one = 1;
  if (::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) != 0) {
    return make_error(Errc::io, fmt::format("{}: setsockopt(SO_TIMESTAMPNS): {}", link, errno_text(errno)));
  }
  return {};
}

ssize_t receive_stamped(int fd, MutableByteSpan buf, int flags, sockaddr* from, socklen_t* from_len,
                        std::optional<std::chrono::nanoseconds>& waited) {
  iovec iov{buf.data(), buf.size()};
  alignas(cmsghdr) std::array<unsigned char, CMSG_SPACE(sizeof(timespec))> control{};
  msghdr msg{};
  msg.msg_name = from;
  msg.msg_namelen = from_len != nullptr ? *from_len : 0;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control.data();
  msg.msg_controllen = control.size();
  const ssize_t n = ::recvmsg(fd, &msg, flags);
  waited.reset();
  if (n < 0) {
    return n;
  }
  if (from_len != nullptr) {
    *from_len = msg.msg_namelen;
  }
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
      timespec arrived{};
      std::memcpy(&arrived, CMSG_DATA(c), sizeof arrived);
      timespec now{};
      ::clock_gettime(CLOCK_REALTIME, &now);  // the clock the kernel stamps with
      waited = std::chrono::seconds{now.tv_sec - arrived.tv_sec} +
               std::chrono::nanoseconds{now.tv_nsec - arrived.tv_nsec};
    }
  }
  return n;
}

}  // namespace sf::ethercat::detail
