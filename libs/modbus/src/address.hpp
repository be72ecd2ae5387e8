// Which address family a host text names: libmodbus's plain TCP back end takes IPv4 dotted quads
// only, its protocol-independent one (modbus_new_tcp_pi) resolves names and IPv6 addresses.
#pragma once

#include <arpa/inet.h>

#include <string>

namespace sf::modbus::detail {

inline bool is_ipv4(const std::string& host) {
  in_addr a{};
  return ::inet_pton(AF_INET, host.c_str(), &a) == 1;
}

inline bool is_ipv6(const std::string& host) {
  in6_addr a{};
  return ::inet_pton(AF_INET6, host.c_str(), &a) == 1;
}

}  // namespace sf::modbus::detail
