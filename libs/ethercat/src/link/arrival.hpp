// What the socket links share about a frame's time in the socket (udp_link.cpp,
// raw_socket_link.cpp): on a wire an EtherCAT frame passes the slaves within microseconds and is
// never queued (ETG.1000.4: the slaves process it on the fly); a socket queues datagrams while the
// process that reads them is not scheduled. A segment emulated in such a process would answer, once
// it runs again, frames its master gave up long before, and once the master's 8-bit datagram index
// has wrapped such a stale answer carries the index of a new frame and is taken for its answer. A
// link with a maximum queue age drops what waited longer, as a wire would have lost it.
#pragma once

#include <sys/socket.h>

#include <chrono>
#include <optional>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat::detail {

// Asks the kernel to stamp each datagram with its arrival time (socket(7) SO_TIMESTAMPNS).
Status stamp_arrivals(int fd, std::string_view link);

// recvmsg(2) of one datagram into `buf` (flags as recvfrom), its sender into `from`; `waited` is
// how long it was in the socket (nullopt without a stamp). Returns recvmsg's result (errno set).
ssize_t receive_stamped(int fd, MutableByteSpan buf, int flags, sockaddr* from, socklen_t* from_len,
                        std::optional<std::chrono::nanoseconds>& waited);

// True when a frame that waited `waited` is older than `max_age` (0: no limit).
inline bool too_old(const std::optional<std::chrono::nanoseconds>& waited, std::chrono::nanoseconds max_age) {
  return max_age.count() > 0 && waited && *waited > max_age;
}

}  // namespace sf::ethercat::detail
