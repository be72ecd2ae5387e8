// What bench_dashboard reads from its browser's half (browser.mjs's result line) and how it pairs
// the page's samples with the gateway's: by series and source millisecond.
#include <gtest/gtest.h>

#include "sf/bench/dashboard.hpp"

namespace sf::bench {
namespace {

TEST(DashboardBrowserResult, PagesAndSamplesAreRead) {
  const auto r = parse_browser_result(
      R"j({"result":{"chromium":"HeadlessChrome/120","operator":[{"path":"operator.html","requests":[)j"
      R"j({"path":"/operator.html","type":"Document","bytes":4000,"failed":""},)j"
      R"j({"path":"/vendor/uPlot.esm.js","type":"Script","bytes":146000,"failed":""},)j"
      R"j({"path":"/api/machines","type":"Fetch","bytes":9000,"failed":""},)j"
      R"j({"path":"/favicon.ico","type":"Other","bytes":300,"failed":"net::ERR_ABORTED"}],)j"
      R"j("load_ms":250.5,"ws_open_ms":400,"first_live_ms":480.25,"first_live_frame_ms":null}],)j"
      R"j("consumer":{"path":"index.html","requests":[{"path":"/","type":"Document","bytes":1500}]},)j"
      R"j("samples":[["4611686018427387904",1700000000123,1700000000150.5],["bad",1,2],["12",3]],)j"
      R"j("client_samples":[["4611686018427387904",1700000000123,1700000000140]],)j"
      R"j("window_ms":[1700000000000,1700000060000.5],"clock_offset_ms":0.25}})j");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->chromium, "HeadlessChrome/120");
  ASSERT_EQ(r->operator_loads.size(), 1U);
  const auto& op = r->operator_loads[0];
  EXPECT_EQ(op.requests, 4U);
  EXPECT_EQ(op.bytes, 159300U);
  EXPECT_EQ(op.api_bytes, 9000U);
  EXPECT_EQ(op.vendor_bytes, 146000U);
  EXPECT_EQ(op.uplot_js_bytes, 146000U);
  ASSERT_EQ(op.failed.size(), 1U);
  EXPECT_EQ(op.failed[0], "/favicon.ico: net::ERR_ABORTED");
  EXPECT_EQ(op.load_ms, 250.5);
  EXPECT_EQ(op.first_live_ms, 480.25);
  EXPECT_FALSE(op.first_live_frame_ms.has_value());
  EXPECT_EQ(r->consumer.bytes, 1500U);
  ASSERT_EQ(r->samples.size(), 1U);  // the malformed ones are left out
  EXPECT_EQ(r->samples[0].series, 4611686018427387904);
  EXPECT_EQ(r->samples[0].source_ms, 1700000000123);
  EXPECT_DOUBLE_EQ(r->samples[0].received_ms, 1700000000150.5);
  ASSERT_EQ(r->client_samples.size(), 1U);
  EXPECT_DOUBLE_EQ(r->client_samples[0].received_ms, 1700000000140);
  EXPECT_DOUBLE_EQ(r->window.from_ms, 1700000000000);
  EXPECT_DOUBLE_EQ(r->window.to_ms, 1700000060000.5);
  EXPECT_DOUBLE_EQ(r->clock_offset_ms, 0.25);
  EXPECT_FALSE(parse_browser_result("ok: logged in").has_value());
  EXPECT_FALSE(parse_browser_result(R"({"results":{}})").has_value());
}

// A page sample is the gateway's of the same series whose source time falls in the same
// millisecond; latencies use the gateway's exact source time. The gateway's figure of every
// sample takes those of the page's window.
TEST(DashboardLatency, PageSamplesPairWithTheGatewaysBySeriesAndMillisecond) {
  const std::int64_t t = 1'700'000'000'000'000;  // µs
  const std::vector<GatewaySample> gateway{
      {1, t + 500, t + 40'500},            // 40 ms at the gateway
      {2, t + 900, t + 30'900},            // another series, same ms: 30 ms
      {1, t + 100'200, t + 160'200},       // 60 ms, the page missed it (coalesced)
      {1, t + 200'700, t + 220'700},       // 20 ms
      {1, t + 5'000'000, t + 5'010'000}};  // after the page's window: counts nowhere
  const std::vector<PageSample> page{
      {1, (t + 500) / 1000, static_cast<double>(t + 50'500) / 1000},        // 50 ms, 10 after the gateway
      {2, (t + 900) / 1000, static_cast<double>(t + 60'900) / 1000},        // 60 ms, 30 after
      {1, (t + 200'700) / 1000, static_cast<double>(t + 240'700) / 1000},   // 40 ms, 20 after
      {3, (t + 200'000) / 1000, static_cast<double>(t + 290'000) / 1000}};  // not at the gateway: 90 ms
  const std::vector<PageSample> client{
      {1, (t + 500) / 1000, static_cast<double>(t + 45'500) / 1000},        // 45 ms
      {1, (t + 200'700) / 1000, static_cast<double>(t + 225'700) / 1000}};  // 25 ms
  const auto f = latency_figures(gateway, page, client,
                                 {static_cast<double>(t) / 1000, static_cast<double>(t) / 1000 + 1000});
  EXPECT_EQ(f.unpaired, 1U);
  EXPECT_EQ(f.client_ms.samples, 2U);
  EXPECT_DOUBLE_EQ(f.client_ms.p50, 25);
  EXPECT_DOUBLE_EQ(f.client_ms.p99, 45);
  EXPECT_EQ(f.page_ms.samples, 4U);
  EXPECT_DOUBLE_EQ(f.page_ms.p50, 50);
  EXPECT_DOUBLE_EQ(f.page_ms.p99, 90);
  EXPECT_EQ(f.gateway_same_ms.samples, 3U);
  EXPECT_DOUBLE_EQ(f.gateway_same_ms.p50, 30);
  EXPECT_DOUBLE_EQ(f.gateway_same_ms.p99, 40);
  EXPECT_EQ(f.gateway_all_ms.samples, 4U);
  EXPECT_DOUBLE_EQ(f.gateway_all_ms.p99, 60);
  EXPECT_EQ(f.page_after_gateway_ms.samples, 3U);
  EXPECT_DOUBLE_EQ(f.page_after_gateway_ms.p50, 20);
  EXPECT_DOUBLE_EQ(f.page_after_gateway_ms.p99, 30);
}

}  // namespace
}  // namespace sf::bench
