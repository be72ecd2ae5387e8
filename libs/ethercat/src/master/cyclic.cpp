// Cyclic exchange: every cycle the prepared frame(s) go out with the current
// outputs, come back with the inputs, and the working counters tell whether
// every slave did its part (ETG.1000.4 §5.4.2). The frames are built once
// (configure.cpp); a cycle only patches index, data and WKC in place, so it
// allocates nothing.
#include <algorithm>
#include <cstring>

#include "cyclic_frame.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

void put_u16(Bytes& b, std::size_t at, std::uint16_t v) {
  store_le<std::uint16_t>(b.data() + at, v);
}

// The returned frame has the same datagrams as the one sent: same length,
// same commands at the same places.
bool same_layout(const Bytes& tx, ByteSpan rx, const std::vector<std::size_t>& headers) {
  if (rx.size() < tx.size()) {
    return false;
  }
  return std::all_of(headers.begin(), headers.end(), [&](std::size_t h) { return rx[h] == tx[h]; });
}

}  // namespace

ExchangeResult Master::exchange() {
  std::lock_guard lock(bus_.mutex());
  ExchangeResult result;
  result.expected_wkc = expected_wkc();
  ++stats_.cycles;
  if (frames_.empty()) {
    last_ = result;
    return result;
  }
  const auto start = clock_.now();
  for (auto& f : frames_) {
    f.index = bus_.next_index();
    f.received = false;
    for (const auto h : f.headers) {
      f.tx[h + 1] = f.index;
    }
    if (f.lrw) {
      std::memcpy(f.tx.data() + f.lrw->data_offset, image_.data() + f.lrw->image_offset, f.lrw->size);
      put_u16(f.tx, f.lrw->data_offset + f.lrw->size, 0);
    }
    if (f.state_data) {
      std::memset(f.tx.data() + *f.state_data, 0, 2 + kWkcSize);
    }
    if (f.dc_data) {
      std::memset(f.tx.data() + *f.dc_data, 0, 8 + kWkcSize);
      // Without its reference the FRMW would feed zeros into every slave's
      // time control loop: send a NOP until the reference is back.
      const bool reference_lost = dc_reference_ && slaves_[*dc_reference_].lost;
      f.tx[*f.dc_data - kDatagramHeaderSize] =
          static_cast<std::uint8_t>(reference_lost ? Command::NOP : Command::FRMW);
    }
    if (!bus_.send_raw(f.tx)) {
      log_->warn("cyclic frame could not be sent");
    }
  }
  const auto pending = receive_cyclic(start, result);
  result.received = pending == 0;
  stats_.lost_frames += pending;
  if (result.received && result.wkc != result.expected_wkc) {
    ++stats_.wkc_errors;
  }
  last_ = result;
  return result;
}

std::size_t Master::receive_cyclic(std::chrono::steady_clock::time_point sent_at, ExchangeResult& result) {
  std::size_t pending = frames_.size();
  // Late frames of earlier cycles may still arrive: skip a few of them.
  const std::size_t attempts = frames_.size() + 8;
  for (std::size_t i = 0; pending > 0 && i < attempts; ++i) {
    auto n = bus_.receive_frame(rx_);
    if (!n || *n == 0) {
      break;
    }
    const ByteSpan rx{rx_.data(), *n};
    if (rx.size() <= Bus::kFirstIndexOffset) {
      continue;
    }
    auto it = std::find_if(frames_.begin(), frames_.end(), [&](const CyclicFrame& f) {
      return !f.received && f.index == rx[Bus::kFirstIndexOffset];
    });
    if (it == frames_.end() || !same_layout(it->tx, rx, it->headers)) {
      continue;
    }
    it->received = true;
    --pending;
    if (it->lrw) {
      const auto& lrw = *it->lrw;
      for (const auto& r : lrw.inputs) {
        std::memcpy(image_.data() + r.offset, rx.data() + lrw.data_offset + (r.offset - lrw.image_offset),
                    r.size);
      }
      result.wkc = static_cast<std::uint16_t>(result.wkc +
                                              load_le<std::uint16_t>(rx.data() + lrw.data_offset + lrw.size));
    }
    if (it->state_data) {
      result.al_state_or = load_le<std::uint16_t>(rx.data() + *it->state_data);
      result.responding = load_le<std::uint16_t>(rx.data() + *it->state_data + 2);
    }
    if (it->dc_data && load_le<std::uint16_t>(rx.data() + *it->dc_data + 8) != 0) {
      dc_time_ = load_le<std::uint64_t>(rx.data() + *it->dc_data);
    }
  }
  if (pending == 0) {
    stats_.round_trip.record(clock_.now() - sent_at);
  }
  return pending;
}

std::vector<std::size_t> Master::cyclic_frame_sizes() const {
  std::vector<std::size_t> sizes;
  sizes.reserve(frames_.size());
  for (const auto& f : frames_) {
    sizes.push_back(f.tx.size());
  }
  return sizes;
}

}  // namespace sf::ethercat::master
