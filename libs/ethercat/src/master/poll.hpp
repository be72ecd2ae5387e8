// Polling with a deadline on the injected clock (private to the master).
#pragma once

#include <chrono>
#include <string_view>

#include <fmt/format.h>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat::master::detail {

// Calls check() until it returns true (done) or an error, sleeping
// `interval` between calls; past `timeout` the result is an Errc::timeout
// naming `what`. check: () -> Result<bool>.
template <typename Check>
Status poll_until(Clock& clock, std::chrono::nanoseconds timeout, std::chrono::nanoseconds interval,
                  std::string_view what, Check&& check) {
  const auto deadline = clock.now() + timeout;
  while (true) {
    Result<bool> done = check();
    if (!done) {
      return done.error();
    }
    if (*done) {
      return {};
    }
    const auto now = clock.now();
    if (now >= deadline) {
      return make_error(Errc::timeout,
                        fmt::format("{}: no result after {} ms", what,
                                    std::chrono::duration_cast<std::chrono::milliseconds>(timeout).count()));
    }
    clock.sleep_until(std::min(now + interval, deadline));
  }
}

}  // namespace sf::ethercat::master::detail
