// In-memory Link pair: two bounded queues under one mutex, one condition
// variable per direction. Used by unit tests and by `demo` to run master and
// emulated segment in one process without a network.
#include <algorithm>
#include <array>
#include <condition_variable>
#include <deque>
#include <mutex>

#include <fmt/format.h>

#include "sf/ethercat/link.hpp"

namespace sf::ethercat {
namespace {

struct Direction {
  std::deque<Bytes> queue;
  std::condition_variable ready;
};

struct SharedWire {
  std::mutex mutex;
  std::array<Direction, 2> to;  // to[i]: frames waiting for end i
  std::array<bool, 2> alive{true, true};
  std::size_t capacity = 0;
};

class MemoryLink final : public Link {
 public:
  MemoryLink(std::shared_ptr<SharedWire> wire, std::size_t self, MacAddress mac, std::string name)
      : wire_(std::move(wire)), self_(self), peer_(1 - self), mac_(mac), name_(std::move(name)) {}

  ~MemoryLink() override {
    const std::lock_guard lock(wire_->mutex);
    wire_->alive[self_] = false;
    wire_->to[peer_].ready.notify_all();
  }
  MemoryLink(const MemoryLink&) = delete;
  MemoryLink& operator=(const MemoryLink&) = delete;

  Status send(ByteSpan frame) override {
    if (frame.size() < kEthernetHeaderSize || frame.size() > kMaxFrameSize) {
      return make_error(Errc::invalid_argument,
                        fmt::format("{}: cannot send a frame of {} bytes (Ethernet: {}-{})", name_,
                                    frame.size(), kEthernetHeaderSize, kMaxFrameSize));
    }
    const std::lock_guard lock(wire_->mutex);
    if (!wire_->alive[peer_]) {
      return make_error(Errc::state, fmt::format("{}: peer closed", name_));
    }
    Direction& out = wire_->to[peer_];
    if (out.queue.size() >= wire_->capacity) {
      return make_error(Errc::limit_exceeded,
                        fmt::format("{}: queue to the peer is full ({} frames)", name_, wire_->capacity));
    }
    out.queue.emplace_back(frame.begin(), frame.end());
    out.ready.notify_one();
    return {};
  }

  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::unique_lock lock(wire_->mutex);
    Direction& in = wire_->to[self_];
    while (true) {
      if (!in.ready.wait_until(lock, deadline, [&] { return !in.queue.empty() || !wire_->alive[peer_]; })) {
        return std::size_t{0};
      }
      if (in.queue.empty()) {
        return make_error(Errc::state, fmt::format("{}: peer closed", name_));
      }
      Bytes frame = std::move(in.queue.front());
      in.queue.pop_front();
      if (!is_ethercat_frame(frame)) {
        continue;
      }
      if (frame.size() > buf.size()) {
        return make_error(Errc::out_of_range,
                          fmt::format("{}: frame of {} bytes dropped, receive buffer has {}", name_,
                                      frame.size(), buf.size()));
      }
      std::copy(frame.begin(), frame.end(), buf.begin());
      return frame.size();
    }
  }

  [[nodiscard]] MacAddress mac() const override { return mac_; }
  [[nodiscard]] std::string name() const override { return name_; }

 private:
  std::shared_ptr<SharedWire> wire_;
  std::size_t self_;
  std::size_t peer_;
  MacAddress mac_;
  std::string name_;
};

}  // namespace

MemoryLinkPair make_memory_link_pair(const MemoryLinkOptions& options) {
  auto wire = std::make_shared<SharedWire>();
  wire->capacity = std::max<std::size_t>(options.capacity, 1);
  return MemoryLinkPair{std::make_unique<MemoryLink>(wire, 0, options.mac_a, options.name + ":a"),
                        std::make_unique<MemoryLink>(wire, 1, options.mac_b, options.name + ":b")};
}

}  // namespace sf::ethercat
