// The emulated segment: a line of ESCs a frame passes in order, with the
// propagation timing the DC receive-time latches see.
#include "sf/ethercat/slave/segment.hpp"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

#include "sf/core/text.hpp"

namespace sf::ethercat::slave {

namespace {

constexpr std::size_t kMaxSlaves = 0xFFFF;  // auto-increment addresses are 16 bits

Result<SegmentSpecItem> parse_item(std::string_view item, std::size_t n) {
  const auto where = [n](std::string_view what) {
    return make_error(Errc::invalid_argument, fmt::format("segment spec item {}: {}", n, what));
  };
  if (item.empty()) {
    return where("empty (expected kind[:count])");
  }
  SegmentSpecItem out;
  const auto colon = item.find(':');
  const std::string_view kind = trim(item.substr(0, colon));
  if (kind.empty()) {
    return where("missing device kind");
  }
  if (auto model = find_device_model(kind); !model) {
    return where(model.error().message);
  }
  out.kind = std::string(kind);
  if (colon != std::string_view::npos) {
    const std::string_view count = trim(item.substr(colon + 1));
    std::size_t value = 0;
    const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), value);
    if (count.empty() || ec != std::errc{} || end != count.data() + count.size()) {
      return where(fmt::format("count \"{}\" of \"{}\" is not a number", count, kind));
    }
    if (value == 0) {
      return where(fmt::format("count of \"{}\" must be at least 1", kind));
    }
    if (value > kMaxSlaves) {
      return where(fmt::format("count {} of \"{}\" exceeds {} slaves", value, kind, kMaxSlaves));
    }
    out.count = value;
  }
  return out;
}

std::int64_t ns_of(Clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

}  // namespace

Result<std::vector<SegmentSpecItem>> parse_segment_spec(std::string_view spec) {
  std::vector<SegmentSpecItem> items;
  if (trim(spec).empty()) {
    return make_error(Errc::invalid_argument,
                      "segment spec is empty (expected e.g. \"servo:2,digital-io:1\")");
  }
  std::size_t total = 0;
  std::size_t n = 1;
  for (std::size_t start = 0; start <= spec.size(); ++n) {
    const auto comma = spec.find(',', start);
    const auto end = comma == std::string_view::npos ? spec.size() : comma;
    auto item = parse_item(trim(spec.substr(start, end - start)), n);
    if (!item) {
      return item.error();
    }
    total += item->count;
    if (total > kMaxSlaves) {
      return make_error(Errc::invalid_argument,
                        fmt::format("segment spec has more than {} slaves", kMaxSlaves));
    }
    items.push_back(std::move(*item));
    if (comma == std::string_view::npos) {
      break;
    }
    start = comma + 1;
  }
  return items;
}

Result<std::unique_ptr<Segment>> Segment::create(std::string_view spec, const Clock& clock,
                                                 SegmentOptions options) {
  auto items = parse_segment_spec(spec);
  if (!items) {
    return items.error();
  }
  auto segment = std::make_unique<Segment>(clock, options);
  DeviceOptions device = options.device;
  for (const auto& item : *items) {
    for (std::size_t i = 0; i < item.count; ++i) {
      auto made = make_device(item.kind, device);
      if (!made) {
        return made.error();
      }
      segment->add(std::move(*made));
      ++device.serial;
    }
  }
  return segment;
}

Segment::Segment(const Clock& clock, SegmentOptions options)
    : clock_(&clock), options_(options), rng_(options.seed) {}

Esc& Segment::add(std::unique_ptr<Device> device) {
  EscOptions esc = options_.esc;
  if (options_.drift_spread_ppm > 0.0) {
    std::uniform_real_distribution<double> spread(-options_.drift_spread_ppm, options_.drift_spread_ppm);
    esc.drift_ppm += spread(rng_);
  }
  return add(std::move(device), esc);
}

Esc& Segment::add(std::unique_ptr<Device> device, const EscOptions& options) {
  auto lock = this->lock();
  slaves_.push_back(Slave{std::make_unique<Esc>(std::move(device), *clock_, options), true});
  passes_.resize(slaves_.size());
  relink();
  return *slaves_.back().esc;
}

void Segment::relink() {
  // Port 0 faces the master; port 1 has a link if a powered slave follows.
  bool later = false;
  for (std::size_t i = slaves_.size(); i-- > 0;) {
    Slave& s = slaves_[i];
    s.esc->set_link(0, s.connected);
    s.esc->set_link(1, s.connected && later);
    later |= s.connected;
  }
}

void Segment::disconnect(std::size_t position) {
  auto lock = this->lock();
  slaves_.at(position).connected = false;
  relink();
}

void Segment::reconnect(std::size_t position) {
  auto lock = this->lock();
  Slave& s = slaves_.at(position);
  if (!s.connected) {
    s.esc->power_on();
    s.connected = true;
    relink();
  }
}

void Segment::set_drop_probability(double p) {
  auto lock = this->lock();
  options_.drop_probability = std::clamp(p, 0.0, 1.0);
}

SegmentCounters Segment::counters() const {
  auto lock = this->lock();
  return counters_;
}

void Segment::poll() {
  auto lock = this->lock();
  for (Slave& s : slaves_) {
    if (s.connected) {
      s.esc->poll();
    }
  }
}

void Segment::emulation_paused(std::chrono::nanoseconds gap) {
  auto lock = this->lock();
  for (Slave& s : slaves_) {
    s.esc->emulation_paused(gap);
  }
}

bool Segment::random_drop() {
  if (options_.drop_probability <= 0.0) {
    return false;
  }
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < options_.drop_probability;
}

bool Segment::process(MutableByteSpan frame) {
  auto lock = this->lock();
  ++counters_.frames;
  const bool back = process_locked(frame);
  if (back) {
    ++counters_.returned;
  }
  return back;
}

bool Segment::process_locked(MutableByteSpan frame) {
  // An ESC passes frames of other EtherCAT types on without acting on them; it acts on no
  // datagram of a malformed chain (checked in a first walk). It ignores bytes after the last
  // datagram inside the EtherCAT length.
  const auto header = ecat_header(frame);
  if (!header) {
    ++counters_.malformed;
    return false;
  }
  const bool commands = header->type() == kEcatTypeCommands;
  if (commands && !for_each_datagram(frame, [](const DatagramSpan&) {})) {
    ++counters_.malformed;
    return false;
  }
  // The slaves a frame reaches: connected ones, up to a closed port 1.
  chain_.clear();
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    if (slaves_[i].connected) {
      chain_.push_back(i);
      if (!slaves_[i].esc->forwards(1)) {
        break;
      }
    }
  }
  if (chain_.empty()) {
    ++counters_.lost;
    return false;
  }
  const bool drop = random_drop();
  const bool drop_before = drop && (rng_() & 1U) == 0;
  if (drop_before) {
    ++counters_.dropped;
    return false;
  }
  // First bit at port 0 on the way out, at port 1 on the way back.
  const std::int64_t t0 = ns_of(clock_->now());
  const std::int64_t cable = options_.cable_delay.count();
  const std::int64_t forward = options_.forward_delay.count();
  const std::int64_t back = options_.return_delay.count();
  const std::size_t n = chain_.size();
  for (std::size_t k = 0; k < n; ++k) {
    passes_[k].port0 = t0 + cable + static_cast<std::int64_t>(k) * (forward + cable);
  }
  std::int64_t tx0 = passes_[n - 1].port0 + forward;  // the last slave loops back at port 1
  passes_[n - 1].port1_valid = false;
  for (std::size_t k = n - 1; k-- > 0;) {
    passes_[k].port1 = tx0 + cable;
    passes_[k].port1_valid = true;
    tx0 = passes_[k].port1 + back;
  }
  for (std::size_t k = 0; k < n; ++k) {
    Esc& esc = *slaves_[chain_[k]].esc;
    esc.begin_frame(passes_[k]);
    if (commands) {
      (void)for_each_datagram(frame, [&](const DatagramSpan& d) {
        esc.process(DatagramView(frame.data() + d.offset, d.length));
      });
    }
    esc.end_frame();
  }
  if (drop) {
    ++counters_.dropped;
    return false;
  }
  frame[6] |= 0x02;  // source MAC: locally administered (ET1100 section I §3.2)
  return true;
}

// --- SegmentLink ---

SegmentLink::SegmentLink(Segment& segment, MacAddress mac)
    : segment_(&segment), mac_(mac), ring_(kQueueFrames), lengths_(kQueueFrames) {}

Status SegmentLink::send(ByteSpan frame) {
  std::lock_guard lock(mutex_);
  if (frame.size() > work_.size()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("frame of {} bytes exceeds {}", frame.size(), work_.size()));
  }
  std::copy(frame.begin(), frame.end(), work_.begin());
  const MutableByteSpan work(work_.data(), frame.size());
  if (!segment_->process(work)) {
    return {};  // lost on the wire: the master sees a timeout
  }
  if (count_ == ring_.size()) {
    return make_error(Errc::limit_exceeded, "segment link: receive queue full (frames not collected)");
  }
  const std::size_t slot = (head_ + count_) % ring_.size();
  std::copy(work.begin(), work.end(), ring_[slot].begin());
  lengths_[slot] = work.size();
  ++count_;
  return {};
}

Result<std::size_t> SegmentLink::receive(MutableByteSpan buf, std::chrono::nanoseconds /*timeout*/) {
  std::lock_guard lock(mutex_);
  if (count_ == 0) {
    return std::size_t{0};  // nothing in flight: waiting could not change that
  }
  const std::size_t n = lengths_[head_];
  if (buf.size() < n) {
    return make_error(Errc::out_of_range,
                      fmt::format("receive buffer of {} bytes for a {}-byte frame", buf.size(), n));
  }
  std::copy_n(ring_[head_].begin(), n, buf.begin());
  head_ = (head_ + 1) % ring_.size();
  --count_;
  return n;
}

// --- SegmentRunner ---

SegmentRunner::SegmentRunner(Segment& segment, Link& link, std::chrono::nanoseconds poll_interval)
    : segment_(&segment), link_(&link), poll_interval_(poll_interval) {}

SegmentRunner::~SegmentRunner() {
  stop();
}

Status SegmentRunner::start() {
  if (running_.exchange(true)) {
    return make_error(Errc::state, "segment runner already running");
  }
  stop_ = false;
  thread_ = std::thread([this] {
    while (!stop_.load()) {
      (void)run_once(poll_interval_);
    }
  });
  return {};
}

void SegmentRunner::stop() {
  stop_ = true;
  if (thread_.joinable()) {
    thread_.join();
  }
  running_ = false;
}

Result<bool> SegmentRunner::run_once(std::chrono::nanoseconds timeout) {
  // A turn that comes far later than the last one ended: this thread was not scheduled (the
  // frames of that time wait in the link), which is no silence of the master's.
  const auto now = segment_->clock().now();
  if (last_turn_ && now - *last_turn_ > kStall + timeout) {
    segment_->emulation_paused(now - *last_turn_ - timeout);
  }
  auto received = link_->receive(buf_, timeout);
  last_turn_ = segment_->clock().now();
  if (!received) {
    ++errors_;
    return received.error();
  }
  if (*received == 0) {
    segment_->poll();
    return false;
  }
  ++frames_;
  const MutableByteSpan frame(buf_.data(), *received);
  if (!segment_->process(frame)) {
    ++dropped_;
    return true;
  }
  if (auto sent = link_->send(frame); !sent) {
    ++errors_;
    return sent.error();
  }
  ++answered_;
  return true;
}

SegmentRunnerCounters SegmentRunner::counters() const {
  return SegmentRunnerCounters{frames_.load(), answered_.load(), dropped_.load(), errors_.load()};
}

}  // namespace sf::ethercat::slave
