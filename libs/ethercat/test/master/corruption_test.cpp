// Frames that come back damaged (a bad switch, a bit error the FCS missed)
// must cost a cycle, never a crash or a read outside a buffer.
#include <random>

#include <gtest/gtest.h>

#include "segment_bench.hpp"

namespace sf::ethercat::master::test {
namespace {

// Wraps a link and damages received frames: random bytes, random lengths.
class CorruptingLink final : public Link {
 public:
  explicit CorruptingLink(Link& inner) : inner_(inner) {}
  bool active = false;
  Status send(ByteSpan frame) override { return inner_.send(frame); }
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override {
    auto n = inner_.receive(buf, timeout);
    if (!active || !n || *n == 0) {
      return n;
    }
    std::size_t len = *n;
    switch (rng_() % 4) {
      case 0:  // cut short
        len = std::uniform_int_distribution<std::size_t>(0, len)(rng_);
        break;
      case 1:  // a length field or command byte hit
        for (int i = 0; i < 3; ++i) {
          buf[std::uniform_int_distribution<std::size_t>(kEthernetHeaderSize, 40)(rng_) % len] ^=
              static_cast<std::uint8_t>(rng_() | 1U);
        }
        break;
      case 2:  // anywhere
        buf[rng_() % len] ^= 0xFF;
        break;
      default:  // left alone
        break;
    }
    return len;
  }
  [[nodiscard]] MacAddress mac() const override { return inner_.mac(); }
  [[nodiscard]] std::string name() const override { return "corrupting"; }

 private:
  Link& inner_;
  std::mt19937 rng_{3};
};

TEST(Corruption, DamagedCyclicFramesAreLostCyclesOnly) {
  ManualClock clock;
  auto segment = slave::Segment::create("smart-controller:1,digital-io:4,servo:3", clock);
  ASSERT_TRUE(segment.ok());
  slave::SegmentLink inner(**segment);
  CorruptingLink link(inner);
  Master master(link, clock, quick_options());
  ASSERT_TRUE(master.bring_up().ok());

  link.active = true;
  for (int i = 0; i < 5000; ++i) {
    clock.advance(std::chrono::milliseconds{1});
    (void)master.exchange();
    master.maintain();
  }
  link.active = false;
  EXPECT_GT(master.statistics().lost_frames, 0U);
  // Afterwards the segment runs normally again (recovering anything the
  // damage knocked out of OP).
  for (int i = 0; i < 2000; ++i) {
    clock.advance(std::chrono::milliseconds{1});
    (void)master.exchange();
    master.maintain();
  }
  for (int i = 0; i < 10; ++i) {
    clock.advance(std::chrono::milliseconds{1});
    EXPECT_TRUE(master.exchange().ok());
  }
}

}  // namespace
}  // namespace sf::ethercat::master::test
