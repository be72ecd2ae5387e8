// The order service: its configuration, and orders handed to it over OPC UA (SubmitOrder)
// while its loop runs on DDS (loopback, a partition of its own).
#include "sf/factory/order_service.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "line_rig.hpp"
#include "sf/factory/line_view.hpp"
#include "sf/line/inspection.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::factory {
namespace {

namespace ua = sf::opcua;
using namespace std::chrono_literals;

TEST(OrderServiceConfig, DefaultsAndSettingsAreRead) {
  auto s = parse_order_service_config("wip: 2\nmax_attempts: 4\nopcua: {port: 4999}\n");
  ASSERT_TRUE(s) << s.error().describe();
  EXPECT_EQ(s->config.host.wip, 2U);
  EXPECT_EQ(s->config.host.max_attempts, 4U);
  EXPECT_EQ(s->config.service.opcua_port, 4999);
  EXPECT_EQ(s->config.service.machine, "order-service");
  EXPECT_EQ(s->layout.line, "prototype");
  EXPECT_TRUE(s->orders.empty());
  auto d = parse_order_service_config("{}\n");
  ASSERT_TRUE(d) << d.error().describe();
  EXPECT_EQ(d->config.service.opcua_port, 4850);
}

TEST(OrderServiceConfig, MistakesNameTheirPlace) {
  auto typo = parse_order_service_config("wip: 2\nmax_attempt: 4\n", "svc.yaml");
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().message.find("svc.yaml:2:"), std::string::npos) << typo.error().message;
  EXPECT_FALSE(parse_order_service_config("max_attempts: 0\n"));
  EXPECT_FALSE(parse_order_service_config("wip: -1\n"));
  auto missing = parse_order_service_config("orders: /no/such/orders.yaml\n");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("/no/such/orders.yaml"), std::string::npos)
      << missing.error().message;
}

class OrderServiceTest : public ::testing::Test {
 protected:
  void start(std::string_view anonymous, int wip = 0) {
    auto setup =
        parse_order_service_config(fmt::format("opcua: {{port: 0, modes: none, anonymous: {}}}\nwip: {}\n"
                                               "dds: {{interface: lo, partition: order-service-test-{}}}\n",
                                               anonymous, wip, getpid()));
    ASSERT_TRUE(setup) << setup.error().describe();
    auto p = OrderServiceProcess::create(std::move(*setup), SteadyClock::instance());
    ASSERT_TRUE(p) << p.error().describe();
    process = std::move(*p);
    loop = std::thread([this] { process->run([this] { return stop.load(); }, nullptr, nullptr, 100ms); });
    ua::ClientConfig cc;
    cc.endpoint_url = process->opcua_endpoint();
    cc.auto_reconnect = false;
    client = std::make_unique<ua::SyncClient>(cc);
    ASSERT_TRUE(client->connect().ok());
    auto index = client->namespace_index("urn:smartfactory:orders");
    ASSERT_TRUE(index) << index.error().describe();
    ns = *index;
  }
  ~OrderServiceTest() override {
    if (client) {
      client->disconnect();
    }
    stop = true;
    if (loop.joinable()) {
      loop.join();
    }
  }

  Result<std::vector<ua::Variant>> submit(std::string id, std::string box, std::vector<ua::String> candy) {
    return client->call_method(
        ua::NodeId(ns, ua::String("OrderService")), ua::NodeId(ns, ua::String("OrderService.SubmitOrder")),
        {ua::Variant(std::move(id)), ua::Variant(std::move(box)), ua::Variant(std::move(candy))});
  }
  Result<std::vector<ua::Variant>> cancel(std::string id) {
    return client->call_method(ua::NodeId(ns, ua::String("OrderService")),
                               ua::NodeId(ns, ua::String("OrderService.CancelOrder")),
                               {ua::Variant(std::move(id))});
  }
  std::uint32_t counter(std::string_view name) {
    auto v = client->read_value(ua::NodeId(ns, ua::String(fmt::format("OrderService.{}", name))));
    EXPECT_TRUE(v) << name;
    const auto* n = v ? v->value.get_if<std::uint32_t>() : nullptr;
    return n != nullptr ? *n : 0xFFFFFFFF;
  }

  std::unique_ptr<OrderServiceProcess> process;
  std::atomic<bool> stop{false};
  std::thread loop;
  std::unique_ptr<ua::SyncClient> client;
  std::uint16_t ns = 0;
};

TEST_F(OrderServiceTest, AnOperatorsOrderIsAcceptedAndBadOnesAreRefused) {
  start("operator");
  auto ok = submit("alice-1", "small-box", {"gummy:4", "toffee:2"});
  ASSERT_TRUE(ok) << ok.error().describe();
  ASSERT_EQ(ok->size(), 1U);
  EXPECT_EQ(ok->at(0).get_if<ua::String>()->str(), "alice-1");
  for (const auto& [box, candy] : std::vector<std::pair<std::string, ua::String>>{{"small-box", "mint:4"},
                                                                                  {"small-box", "gummy:13"},
                                                                                  {"gift-12", "gummy:1"},
                                                                                  {"small-box", "gummy"}}) {
    auto bad = submit("bob-1", box, {candy});
    ASSERT_FALSE(bad) << box << " " << candy.str();
    EXPECT_NE(bad.error().message.find("BadInvalidArgument"), std::string::npos) << bad.error().message;
  }
  auto again = submit("alice-1", "small-box", {"gummy:1"});
  ASSERT_FALSE(again);
  EXPECT_NE(again.error().message.find("BadInvalidArgument"), std::string::npos);
  // The loop took the order: one in work (its product announces with nobody listening).
  for (int i = 0; i < 100 && counter("InWork") + counter("Queued") == 0; ++i) {
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(counter("InWork") + counter("Queued"), 1U);
  EXPECT_EQ(counter("Done"), 0U);
}

TEST_F(OrderServiceTest, TheLineViewReadsItsCountersAsTheDemoShowsThem) {
  start("operator");
  sf::testing::TempDir dir;
  auto plan = plan_line(line_rig::options(dir.path()));
  ASSERT_TRUE(plan) << plan.error().describe();
  for (auto& p : plan->processes) {
    if (p.role == LineRole::orders) {
      p.opcua_port = static_cast<std::uint16_t>(std::stoi(process->opcua_endpoint().substr(
          process->opcua_endpoint().rfind(':') + 1)));  // this test's order service
    }
  }
  auto view = LineView::open(*plan);
  ASSERT_TRUE(view) << view.error().describe();
  ASSERT_TRUE(submit("alice-1", "small-box", {"gummy:4"}));
  OrderCounts counts;
  for (int i = 0; i < 100 && counts.in_work + counts.queued == 0; ++i) {
    auto read = view->orders();
    ASSERT_TRUE(read) << read.error().describe();
    counts = *read;
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(counts.in_work + counts.queued, 1U);
  EXPECT_EQ(counts.done, 0U);
  // No controller of the plan runs here: no working times, and no hang.
  EXPECT_TRUE(view->working_times().empty());
  plan->processes.erase(std::remove_if(plan->processes.begin(), plan->processes.end(),
                                       [](const LineProcess& p) { return p.role == LineRole::orders; }),
                        plan->processes.end());
  EXPECT_FALSE(LineView::open(*plan));
}

TEST_F(OrderServiceTest, AViewerMayNotOrder) {
  start("viewer");
  auto refused = submit("v-1", "small-box", {"gummy:1"});
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().message.find("BadUserAccessDenied"), std::string::npos)
      << refused.error().message;
}

// Every step of an order is an OPC UA event of the Server object (SourceName: the order, Message:
// the step), and CancelOrder withdraws a queued order but not one in work.
TEST_F(OrderServiceTest, StepsAreEventsAndAQueuedOrderCanBeCancelled) {
  start("operator", 1);  // one box on the line: the second order waits in the queue
  std::mutex mutex;
  std::vector<std::pair<std::string, line::OrderStep>> steps;
  auto sub = client->create_subscription({});
  ASSERT_TRUE(sub) << sub.error().describe();
  auto item = client->monitor_events(*sub, ua::NodeId(0, ua::id::Server),
                                     ua::select_event_fields({"SourceName", "Message"}),
                                     [&](const std::vector<ua::Variant>& fields) {
                                       const auto* source = fields.at(0).get_if<ua::String>();
                                       const auto* message = fields.at(1).get_if<ua::LocalizedText>();
                                       ASSERT_TRUE(source != nullptr && message != nullptr);
                                       auto step = line::parse_order_step(message->text.view());
                                       ASSERT_TRUE(step) << step.error().message;
                                       std::lock_guard lock(mutex);
                                       steps.emplace_back(source->str(), *step);
                                     });
  ASSERT_TRUE(item) << item.error().describe();
  ASSERT_TRUE(submit("first", "small-box", {"gummy:1"}));
  for (int i = 0; i < 200 && counter("InWork") == 0; ++i) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_TRUE(submit("second", "small-box", {"toffee:2"}));
  for (int i = 0; i < 200 && counter("Queued") == 0; ++i) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_EQ(counter("Queued"), 1U);
  ASSERT_TRUE(cancel("second"));
  ASSERT_TRUE(cancel("first"));  // taken, refused by the loop: its box is on the way
  auto unknown = cancel("nobody");
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().message.find("BadNotFound"), std::string::npos) << unknown.error().message;
  auto seen = [&](const std::string& order, const std::string& what) {
    std::lock_guard lock(mutex);
    return std::any_of(steps.begin(), steps.end(),
                       [&](const auto& s) { return s.first == order && s.second.what == what; });
  };
  for (int i = 0; i < 300 && !(seen("second", "cancelled") && seen("first", "cancel-refused")); ++i) {
    std::this_thread::sleep_for(10ms);
  }
  EXPECT_TRUE(seen("first", "accepted"));
  EXPECT_TRUE(seen("second", "accepted"));
  EXPECT_TRUE(seen("second", "cancelled"));
  EXPECT_TRUE(seen("first", "cancel-refused"));
  EXPECT_FALSE(seen("first", "cancelled"));
  EXPECT_EQ(counter("Cancelled"), 1U);
  EXPECT_EQ(counter("Queued"), 0U);
}

}  // namespace
}  // namespace sf::factory
