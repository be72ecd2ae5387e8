// Bring mixed segments to OP and exchange process data: outputs written by
// the master reach the devices, inputs set in the devices reach the master,
// and every working counter is the expected one.
#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

struct Case {
  std::string spec;
  std::size_t slaves;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << '"' << c.spec << '"';
}

class CyclicExchange : public ::testing::TestWithParam<Case> {};

TEST_P(CyclicExchange, TenThousandCyclesInOp) {
  Bench b(GetParam().spec);
  auto st = b.master->bring_up();
  ASSERT_TRUE(st.ok()) << st.error().describe();
  auto& m = *b.master;
  ASSERT_EQ(m.slave_count(), GetParam().slaves);
  for (std::size_t p = 0; p < m.slave_count(); ++p) {
    EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
  }
  // Every slave has outputs and inputs: 2 (write) + 1 (read) each.
  EXPECT_EQ(m.expected_wkc(), 3 * GetParam().slaves);

  // Resolve the digital IO entries once, as an application would.
  struct Io {
    std::size_t position;
    EntryRef out;
    EntryRef in;
    bool wide;  // the smart controller's 32-bit IO
  };
  std::vector<Io> ios;
  for (std::size_t p = 0; p < m.slave_count(); ++p) {
    auto view = m.slave(p);
    auto out = view.entry(0x7000, 0);
    auto in = view.entry(0x6000, 0);
    if (out && in) {
      ios.push_back({p, *out, *in, out->bit_length == 32});
    }
  }
  ASSERT_FALSE(ios.empty());

  m.statistics().reset();
  constexpr std::uint32_t kCycles = 10'000;
  std::size_t bad_wkc = 0;
  std::size_t bad_outputs = 0;
  std::size_t bad_inputs = 0;
  for (std::uint32_t c = 0; c < kCycles; ++c) {
    for (const auto& io : ios) {
      const auto value = static_cast<std::uint32_t>(c * 7919U + io.position * 131U);
      m.slave(io.position).set<std::uint32_t>(io.out, io.wide ? value : value & 0xFFU);
      if (auto* d = b.segment->device<slave::DigitalIo>(io.position)) {
        d->set_inputs(static_cast<std::uint8_t>(value >> 3));
      } else if (auto* s = b.segment->device<slave::DriveDevice>(io.position)) {
        s->set_digital_inputs(~value);
      }
    }
    const auto r = b.cycle();
    bad_wkc += r.ok() ? 0U : 1U;
    for (const auto& io : ios) {
      const auto value = static_cast<std::uint32_t>(c * 7919U + io.position * 131U);
      const auto in = m.slave(io.position).get<std::uint32_t>(io.in);
      if (auto* d = b.segment->device<slave::DigitalIo>(io.position)) {
        bad_outputs += d->outputs() == (value & 0xFFU) ? 0U : 1U;
        bad_inputs += in == ((value >> 3) & 0xFFU) ? 0U : 1U;
      } else if (auto* s = b.segment->device<slave::DriveDevice>(io.position)) {
        bad_outputs += s->digital_outputs() == value ? 0U : 1U;
        bad_inputs += in == ~value ? 0U : 1U;
      }
    }
  }
  EXPECT_EQ(bad_wkc, 0U);
  EXPECT_EQ(bad_outputs, 0U);
  EXPECT_EQ(bad_inputs, 0U);
  const auto& stats = m.statistics();
  EXPECT_EQ(stats.cycles, kCycles);
  EXPECT_EQ(stats.lost_frames, 0U);
  EXPECT_EQ(stats.wkc_errors, 0U);
  EXPECT_EQ(stats.round_trip.count(), kCycles);
  for (std::size_t p = 0; p < m.slave_count(); ++p) {
    EXPECT_EQ(b.segment->slave(p).state(), AlState::Op) << "slave " << p;
  }
  EXPECT_TRUE(m.diagnose().empty());
}

INSTANTIATE_TEST_SUITE_P(Segments, CyclicExchange,
                         ::testing::Values(Case{"digital-io:1", 1},
                                           Case{"smart-controller:1,digital-io:4,servo:3", 8},
                                           Case{"smart-controller:8,digital-io:32,servo:24", 64}),
                         [](const auto& param_info) {
                           return "slaves_" + std::to_string(param_info.param.slaves);
                         });

}  // namespace
}  // namespace sf::ethercat::master::test
