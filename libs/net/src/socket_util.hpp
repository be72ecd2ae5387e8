// Small POSIX socket helpers shared by the TCP classes.
#pragma once

#include <sys/socket.h>

#include <string>

#include "sf/core/result.hpp"

namespace sf::net::detail {

// "strerror(err) (errno err)".
std::string errno_text(int err);
// "127.0.0.1:53124" or "[::1]:4840".
std::string address_text(const sockaddr* addr);
// O_NONBLOCK and FD_CLOEXEC; false on failure (errno set).
bool set_non_blocking(int fd);
void set_no_delay(int fd);
// The error pending on a socket (SO_ERROR), 0 if none.
int socket_error(int fd);
// The peer's address text, or "?" when unavailable.
std::string peer_text(int fd);

}  // namespace sf::net::detail
