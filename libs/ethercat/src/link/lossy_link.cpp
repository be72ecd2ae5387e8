// LossyLink: drops frames at random, from a seeded generator, to test how the
// master copes with lost frames (retries, WKC errors, watchdogs).
#include <algorithm>

#include "sf/ethercat/link.hpp"

namespace sf::ethercat {

LossyLink::LossyLink(std::unique_ptr<Link> inner, LossyLinkOptions options)
    : inner_(std::move(inner)), options_(options), rng_(options.seed) {
  options_.send_drop_probability = std::clamp(options_.send_drop_probability, 0.0, 1.0);
  options_.receive_drop_probability = std::clamp(options_.receive_drop_probability, 0.0, 1.0);
}

bool LossyLink::drop(double probability) {
  if (probability <= 0.0) {
    return false;
  }
  const std::lock_guard lock(mutex_);
  // 53 random bits → uniform double in [0, 1); identical on every platform.
  const double u = static_cast<double>(rng_() >> 11U) * 0x1.0p-53;
  return u < probability;
}

Status LossyLink::send(ByteSpan frame) {
  if (drop(options_.send_drop_probability)) {
    ++dropped_sent_;
    return {};
  }
  return inner_->send(frame);
}

Result<std::size_t> LossyLink::receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::max(std::chrono::nanoseconds{0}, deadline - std::chrono::steady_clock::now());
    auto n = inner_->receive(buf, left);
    if (!n || *n == 0) {
      return n;
    }
    if (!drop(options_.receive_drop_probability)) {
      return n;
    }
    ++dropped_received_;  // keep waiting: each pass consumes a frame, so this ends
  }
}

}  // namespace sf::ethercat
