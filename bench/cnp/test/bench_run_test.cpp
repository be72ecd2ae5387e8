// The Contract Net benchmark's driver (run_bench) with contractors in this
// process over real DDS (loopback, a partition private to this process): each
// phase measures every negotiation it was asked for. The one-at-a-time phase
// starts each negotiation from the handler of the previous one's end, and the
// throughput phase from the handler of a confirmation, so a chain that broke
// would leave the phase waiting and the run failing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fmt/format.h>

#include "sf/bench/cnp.hpp"

namespace sf::negotiation {
namespace {

BenchOptions options(bool inline_delivery) {
  BenchOptions o;
  o.contractors = 3;
  o.negotiations = 40;
  o.window = 4;
  o.warmup = 2;
  o.ddsperf = false;
  o.inline_delivery = inline_delivery;
  o.dds.machining_domain = 76;
  o.dds.conveying_domain = 75;
  o.dds.partition = fmt::format("sf-cnp-bench-test-{}-{}", ::getpid(),
                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
  return o;
}

class RunBench : public ::testing::TestWithParam<bool> {};

INSTANTIATE_TEST_SUITE_P(Delivery, RunBench, ::testing::Bool(),
                         [](const auto& param_info) { return param_info.param ? "Inline" : "Queued"; });

TEST_P(RunBench, EveryPhaseMeasuresEveryNegotiationItWasAskedFor) {
  const auto r = run_bench(options(GetParam()), {});
  ASSERT_TRUE(r) << r.error().describe();
  EXPECT_EQ(r->latency.samples, 40u);
  EXPECT_EQ(r->failed, 0u);
  EXPECT_FALSE(r->ratio_p50.has_value());  // no ddsperf asked for
}

// A chain of no negotiations starts none (nothing is left running into the next phase).
TEST(RunBenchOptions, NoWarmupStartsNoWarmupNegotiation) {
  auto o = options(true);
  o.warmup = 0;
  const auto r = run_bench(o, {});
  ASSERT_TRUE(r) << r.error().describe();
  EXPECT_EQ(r->latency.samples, 40u);
}

TEST(RunBenchOptions, NoContractorsIsAnError) {
  auto o = options(true);
  o.contractors = 0;
  const auto r = run_bench(o, {});
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, Errc::invalid_argument);
}

}  // namespace
}  // namespace sf::negotiation
