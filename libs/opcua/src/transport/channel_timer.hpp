// The timer that wakes a secure channel at its next deadline (token renewal, request and
// Hello timeouts: SecureChannel::next_deadline), shared by the client and server transports.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>

#include "sf/core/clock.hpp"
#include "sf/net/event_loop.hpp"

namespace sf::opcua::detail {

// The timer is re-armed at least this often, so a clock that jumps (a ManualClock in tests) is
// caught up within a second.
inline constexpr std::chrono::milliseconds kMaxChannelTimerDelay{1000};

// Cancels `timer` and, for a deadline, sets it again to run `fire` then (not later than
// kMaxChannelTimerDelay). `fire` clears `timer`: it has run.
inline void arm_channel_timer(net::EventLoop& loop, const Clock& clock, net::EventLoop::TimerId& timer,
                              std::optional<Clock::time_point> deadline, std::function<void()> fire) {
  if (timer != 0) {
    loop.cancel_timer(timer);
    timer = 0;
  }
  if (!deadline) {
    return;
  }
  const auto delay = std::clamp(std::chrono::duration_cast<std::chrono::nanoseconds>(*deadline - clock.now()),
                                std::chrono::nanoseconds{0}, std::chrono::nanoseconds{kMaxChannelTimerDelay});
  timer = loop.add_timer(delay, std::move(fire));
}

}  // namespace sf::opcua::detail
