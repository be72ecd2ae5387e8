// The mailbox repeat protocol under frame loss (ETG.1000.4 §5.6: mailbox
// counter, SM1 repeat request): 2 % of the frames are lost before the slaves
// see them, 2 % after, and 2 % come back only after the master stopped
// waiting for them (a slave or a wire slower than the frame timeout), while
// a drive raises emergencies now and then (as a drive does that faulted when
// the previous master left it in OP). Every PDO mapping read and SDO
// transfer must still complete, exactly once.
#include <deque>
#include <random>

#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

// Wraps a link whose replies are ready at once (SegmentLink) and holds some
// of them back: receive() reports a timeout, and the frame is delivered on a
// later receive() call, behind whatever else came meanwhile.
class LateLink final : public Link {
 public:
  LateLink(Link& inner, double late_probability, std::uint64_t seed)
      : inner_(inner), late_(late_probability), rng_(seed) {}
  Status send(ByteSpan frame) override { return inner_.send(frame); }
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override {
    if (!held_.empty() && (rng_() & 1U) == 0) {
      return deliver(held_, buf);
    }
    auto n = inner_.receive(buf, timeout);
    if (!n || *n == 0) {
      return held_.empty() ? n : deliver(held_, buf);
    }
    if (std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < late_) {
      held_.emplace_back(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(*n));
      ++late_frames;
      return std::size_t{0};  // "timeout": it comes later
    }
    return n;
  }
  [[nodiscard]] MacAddress mac() const override { return inner_.mac(); }
  [[nodiscard]] std::string name() const override { return "late"; }
  void set_late_probability(double p) { late_ = p; }
  std::uint64_t late_frames = 0;

 private:
  static Result<std::size_t> deliver(std::deque<Bytes>& held, MutableByteSpan buf) {
    const Bytes frame = std::move(held.front());
    held.pop_front();
    std::copy(frame.begin(), frame.end(), buf.begin());
    return frame.size();
  }

  Link& inner_;
  double late_;
  std::mt19937_64 rng_;
  std::deque<Bytes> held_;
};

// A servo that raises a CoE emergency every `every` ticks (one per frame):
// unrelated messages in the read mailbox between requests and answers.
class NoisyServo final : public slave::Device {
 public:
  explicit NoisyServo(unsigned every) : every_(every) {}
  [[nodiscard]] std::string_view kind() const override { return "noisy-servo"; }
  [[nodiscard]] const SiiInfo& sii() const override { return servo_.sii(); }
  [[nodiscard]] slave::ObjectDictionary& objects() override { return servo_.objects(); }
  [[nodiscard]] bool outputs_safe() const override { return servo_.outputs_safe(); }
  void tick(Clock::time_point now) override {
    servo_.tick(now);
    if (noisy && ++ticks_ % every_ == 0) {
      emergency(CoeEmergency{0x8130, 0x11, {}});
      ++emergencies;
    }
  }
  bool noisy = false;
  std::uint64_t emergencies = 0;

 private:
  slave::Servo servo_;
  unsigned every_;
  std::uint64_t ticks_ = 0;
};

struct LossyBench {
  explicit LossyBench(std::uint64_t seed) {
    slave::SegmentOptions so;
    so.seed = seed;
    segment = std::make_unique<slave::Segment>(clock, so);
    segment->add(std::make_unique<slave::SmartController>());
    noisy = &dynamic_cast<NoisyServo&>(segment->add(std::make_unique<NoisyServo>(211)).device());
    inner = std::make_unique<slave::SegmentLink>(*segment);
    link = std::make_unique<LateLink>(*inner, 0.0, seed);
    master = std::make_unique<Master>(*link, clock, quick_options());
  }
  void lossy(bool on) {
    segment->set_drop_probability(on ? 0.04 : 0.0);  // half before, half after the slaves
    link->set_late_probability(on ? 0.02 : 0.0);
    noisy->noisy = on;
  }

  ManualClock clock;
  std::unique_ptr<slave::Segment> segment;
  std::unique_ptr<slave::SegmentLink> inner;
  std::unique_ptr<LateLink> link;
  std::unique_ptr<Master> master;
  NoisyServo* noisy = nullptr;
};

TEST(MailboxLoss, PdoMappingAndSdoSurviveLostAndLateFrames) {
  std::uint64_t repeats = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    LossyBench b(seed);
    ASSERT_TRUE(b.master->scan().ok());
    ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
    b.segment->slave(1).objects().add_string(0x2001, "Blob", std::string(300, '\0'), slave::access::kRW,
                                             slave::DataType::OctetString);
    b.lossy(true);
    Bytes data(300);
    for (int round = 0; round < 40; ++round) {
      for (std::size_t p = 0; p < 2; ++p) {
        auto m = b.master->read_pdo_mapping(p);
        ASSERT_TRUE(m.ok()) << "seed " << seed << " round " << round << ": " << m.error().describe();
        ASSERT_EQ(m->source, PdoMapping::Source::coe);
        ASSERT_EQ(m->output_bits, p == 0 ? 8U * 48U + 32U : 48U);
      }
      for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = static_cast<std::uint8_t>(i * 7U + static_cast<std::size_t>(round));
      }
      auto st = b.master->sdo_download(1, 0x2001, 0, data);
      ASSERT_TRUE(st.ok()) << "seed " << seed << " round " << round << ": " << st.error().describe();
      auto back = b.master->sdo_upload(1, 0x2001, 0);
      ASSERT_TRUE(back.ok()) << "seed " << seed << " round " << round << ": " << back.error().describe();
      ASSERT_EQ(*back, data);
    }
    b.lossy(false);
    repeats += b.master->mailbox_repeats();
    EXPECT_GT(b.link->late_frames, 0U);
    EXPECT_GT(b.noisy->emergencies, 0U);
  }
  EXPECT_GT(repeats, 0U) << "the repeat request was exercised";
}

}  // namespace
}  // namespace sf::ethercat::master::test
