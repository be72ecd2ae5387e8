// Segment: an emulated EtherCAT segment — an ordered line of ESCs that a
// frame passes like the ring of a real segment (out through every slave's
// port 0 → processing unit → port 1, back from the last one through the
// closed loop). Built from a spec like "smart-controller:2,digital-io:4,servo:1".
//
//   SegmentLink    a Link whose send() runs the frame through the segment
//                  synchronously and queues the reply for receive(): the
//                  deterministic in-memory path for master tests.
//   SegmentRunner  serves a segment on any Link (a raw socket on a veth
//                  pair, a memory link): receive → process → send back.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/esc.hpp"

namespace sf::ethercat::slave {

struct SegmentSpecItem {
  std::string kind;
  std::size_t count = 1;
  bool operator==(const SegmentSpecItem&) const = default;
};
// "kind[:count],kind[:count],..." (spaces ignored); errors name the item.
Result<std::vector<SegmentSpecItem>> parse_segment_spec(std::string_view spec);

struct SegmentOptions {
  // Propagation model for DC: each ESC takes forward_delay from port 0 to
  // port 1 (through its processing unit) and return_delay from port 1 back
  // to port 0; every cable adds cable_delay. Equal delays (the default) let
  // a master's (t_port1 − t_port0)/2 arithmetic come out exact; unequal ones
  // model the asymmetry of real ESCs.
  std::chrono::nanoseconds forward_delay{500};
  std::chrono::nanoseconds return_delay{500};
  std::chrono::nanoseconds cable_delay{10};
  // Probability that a frame is lost (half of the losses before the slaves
  // saw it, half on the way back), from a seeded generator.
  double drop_probability = 0.0;
  std::uint64_t seed = 1;
  // Every slave's oscillator drifts by a random value in ±drift_spread_ppm
  // (seeded), plus esc.drift_ppm.
  double drift_spread_ppm = 0.0;
  EscOptions esc;
  DeviceOptions device;  // serial numbers count up from device.serial
};

struct SegmentCounters {
  std::uint64_t frames = 0;     // frames offered to process()
  std::uint64_t returned = 0;   // frames that came back
  std::uint64_t dropped = 0;    // lost by the drop probability
  std::uint64_t malformed = 0;  // not EtherCAT or inconsistent lengths
  std::uint64_t lost = 0;       // no slave connected to answer
};

class Segment {
 public:
  // A segment from a spec; each slave gets its own device.
  static Result<std::unique_ptr<Segment>> create(std::string_view spec, const Clock& clock,
                                                 SegmentOptions options = {});
  Segment(const Clock& clock, SegmentOptions options = {});

  // Appends a slave at the end of the line.
  Esc& add(std::unique_ptr<Device> device);
  Esc& add(std::unique_ptr<Device> device, const EscOptions& options);

  // Passes one Ethernet frame (header included, no FCS) through every
  // connected slave in order, in place. Returns true if the frame comes back
  // (the source MAC then has the locally administered bit set, as ESCs do);
  // false if it was lost, dropped or not a valid EtherCAT frame.
  bool process(MutableByteSpan frame);
  // Runs every slave's timers (watchdogs, SYNC0, SII busy) without a frame.
  void poll();
  // Every slave's Esc::emulation_paused.
  void emulation_paused(std::chrono::nanoseconds gap);
  [[nodiscard]] const Clock& clock() const { return *clock_; }

  // The slave loses power and drops out of the ring (later positions shift).
  void disconnect(std::size_t position);
  // Power comes back: INIT, station address 0, SMs/FMMUs cleared.
  void reconnect(std::size_t position);
  void set_drop_probability(double p);

  // Slaves by their place in the line (disconnected ones included).
  [[nodiscard]] std::size_t size() const { return slaves_.size(); }
  [[nodiscard]] Esc& slave(std::size_t position) { return *slaves_.at(position).esc; }
  [[nodiscard]] const Esc& slave(std::size_t position) const { return *slaves_.at(position).esc; }
  [[nodiscard]] bool connected(std::size_t position) const { return slaves_.at(position).connected; }
  // The device of a slave as its concrete type (nullptr if it is another).
  template <typename D>
  [[nodiscard]] D* device(std::size_t position) {
    return dynamic_cast<D*>(&slave(position).device());
  }
  [[nodiscard]] SegmentCounters counters() const;
  // Guards process()/poll() against observers in other threads.
  [[nodiscard]] std::unique_lock<std::mutex> lock() const { return std::unique_lock(mutex_); }

 private:
  struct Slave {
    std::unique_ptr<Esc> esc;
    bool connected = true;
  };
  bool process_locked(MutableByteSpan frame);
  bool random_drop();
  void relink();

  const Clock* clock_;
  SegmentOptions options_;
  std::vector<Slave> slaves_;
  std::vector<std::size_t> chain_;  // connected slaves reached by a frame, in order
  std::vector<FramePass> passes_;
  std::mt19937_64 rng_;
  mutable std::mutex mutex_;
  SegmentCounters counters_;
};

// Link to a segment: send() processes the frame at once (segment clock), the
// reply waits in a bounded queue for receive(), which never blocks.
class SegmentLink final : public Link {
 public:
  static constexpr std::size_t kQueueFrames = 64;

  explicit SegmentLink(Segment& segment, MacAddress mac = {0x02, 0x00, 0x00, 0x00, 0x5e, 0x01});
  Status send(ByteSpan frame) override;
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override;
  [[nodiscard]] MacAddress mac() const override { return mac_; }
  [[nodiscard]] std::string name() const override { return "segment"; }

 private:
  Segment* segment_;
  MacAddress mac_;
  std::mutex mutex_;
  std::vector<std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize>> ring_;
  std::vector<std::size_t> lengths_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize> work_{};
};

struct SegmentRunnerCounters {
  std::uint64_t frames = 0;    // received and processed
  std::uint64_t answered = 0;  // sent back
  std::uint64_t dropped = 0;   // not returned (lost, dropped, malformed)
  std::uint64_t errors = 0;    // link errors
};

class SegmentRunner {
 public:
  SegmentRunner(Segment& segment, Link& link,
                std::chrono::nanoseconds poll_interval = std::chrono::milliseconds{1});
  ~SegmentRunner();
  SegmentRunner(const SegmentRunner&) = delete;
  SegmentRunner& operator=(const SegmentRunner&) = delete;

  // Serves frames in a thread until stop().
  Status start();
  void stop();
  [[nodiscard]] bool running() const { return running_.load(); }
  // One step in the caller's thread: waits up to `timeout` for a frame,
  // processes and answers it, runs the timers. Returns true if a frame came.
  Result<bool> run_once(std::chrono::nanoseconds timeout);
  [[nodiscard]] SegmentRunnerCounters counters() const;

 private:
  Segment* segment_;
  Link* link_;
  static constexpr std::chrono::milliseconds kStall{20};
  std::chrono::nanoseconds poll_interval_;
  std::optional<Clock::time_point> last_turn_;  // when the last run_once ended
  std::array<std::uint8_t, kMaxFrameSize + kVlanTagSize> buf_{};
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::atomic<std::uint64_t> frames_{0};
  std::atomic<std::uint64_t> answered_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> errors_{0};
};

}  // namespace sf::ethercat::slave
