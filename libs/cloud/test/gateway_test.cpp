// The gateway end to end: several OPC UA servers with monotonic counters → gateway → historian
// (SQLite, and a real PostgreSQL server the test starts). The database must hold every value
// the servers produced, in order, once — also when the database is killed and restarted and when
// a server restarts mid-stream.
#include "sf/cloud/gateway.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <mutex>
#include <numeric>
#include <thread>

#include "counter_server.hpp"
#include "pg_server.hpp"
#include "sf/opcua/server/history.hpp"

namespace sf::cloud {
namespace {

using test::Counter;
using test::CounterServer;
using test::eventually;
using test::node_rule;
using test::path_rule;
using test::server_config;
using test::TempDir;

constexpr std::size_t kServers = 3;
constexpr std::size_t kCounters = 4;

class GatewayEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    for (std::size_t s = 0; s < kServers; ++s) {
      std::vector<std::shared_ptr<Counter>> counters;
      for (std::size_t c = 0; c < kCounters; ++c) {
        counters.push_back(std::make_shared<Counter>());
      }
      counters_.push_back(counters);
      servers_.push_back(std::make_unique<CounterServer>(0, counters));
      ASSERT_TRUE(servers_.back()->ok());
    }
  }

  GatewayConfig config_for(const std::string& url) {
    GatewayConfig config;
    config.historian.url = url;
    config.historian.buffer = dir_.path() / "buffer";
    config.historian.batch = 64;
    config.historian.flush_interval = std::chrono::milliseconds(20);
    for (std::size_t s = 0; s < kServers; ++s) {
      ServerConfig server = server_config("line-" + std::to_string(s),
                                          "opc.tcp://127.0.0.1:" + std::to_string(servers_[s]->port()),
                                          {path_rule("/Objects/Line", 1)});
      server.publishing_interval_ms = 20;
      server.sampling_interval_ms = 10;
      server.queue_size = 1000;
      config.servers.push_back(server);
    }
    return config;
  }

  // Every counter to `value`, then wait until each server sampled it.
  void step(std::int64_t value) {
    for (auto& server : counters_) {
      for (auto& counter : server) {
        counter->set(value);
      }
    }
    ASSERT_TRUE(eventually([&] {
      for (std::size_t s = 0; s < kServers; ++s) {
        if (servers_[s] &&
            !std::all_of(counters_[s].begin(), counters_[s].end(), [](auto& c) { return c->sampled(); })) {
          return false;
        }
      }
      return true;
    }));
  }

  void wait_subscribed(Gateway& gateway) {
    ASSERT_TRUE(eventually([&] {
      const auto status = gateway.status();
      return std::all_of(status.servers.begin(), status.servers.end(), [](const ServerStatus& s) {
        return s.phase == "subscribed" && s.series == kCounters;
      });
    }));
    for (auto& server : servers_) {
      ASSERT_TRUE(eventually([&] { return server->monitored_items() == kCounters; }));
    }
  }

  // Each series holds 0, 1, ..., last exactly once, in order.
  void expect_complete(historian::Store& store, std::int64_t last) {
    auto series = store.list_series();
    ASSERT_TRUE(series.ok()) << series.error().message;
    ASSERT_EQ(series->size(), kServers * kCounters);
    std::vector<std::int64_t> expected;
    for (std::int64_t v = 0; v <= last; ++v) {
      expected.push_back(v);
    }
    for (const historian::Series& s : *series) {
      auto samples =
          store.read_raw(s.id, historian::from_micros(0), historian::from_micros(INT64_MAX / 2), 1'000'000);
      ASSERT_TRUE(samples.ok()) << samples.error().message;
      std::vector<std::int64_t> values;
      for (const historian::Sample& sample : *samples) {
        values.push_back(std::get<std::int64_t>(sample.value));
      }
      std::vector<std::int64_t> missing;
      std::set_difference(expected.begin(), expected.end(), values.begin(), values.end(),
                          std::back_inserter(missing));
      EXPECT_EQ(values, expected) << s.info.server << " " << s.info.browse_path << ": " << values.size()
                                  << " values, missing " << ::testing::PrintToString(missing);
    }
  }

  void wait_written(Gateway& gateway, std::uint64_t samples) {
    ASSERT_TRUE(eventually([&] { return gateway.status().samples_written >= samples; }))
        << "written " << gateway.status().samples_written << " of " << samples;
  }

  TempDir dir_;
  std::vector<std::vector<std::shared_ptr<Counter>>> counters_;
  std::vector<std::unique_ptr<CounterServer>> servers_;
};

TEST_F(GatewayEndToEnd, EveryValueOfEveryServerReachesSqliteInOrder) {
  auto gateway = Gateway::create(config_for("sqlite:" + (dir_.path() / "history.db").string()));
  ASSERT_TRUE(gateway.ok()) << gateway.error().message;
  // Updates of different servers arrive on different threads.
  std::mutex live_mutex;
  std::map<std::string, std::size_t> live;
  auto on = (*gateway)->live().subscribe([&](const LiveUpdate& u) {
    const std::lock_guard lock(live_mutex);
    ++live[u.series->server];
  });
  ASSERT_TRUE((*gateway)->start().ok());
  wait_subscribed(**gateway);
  constexpr std::int64_t kSteps = 40;
  for (std::int64_t v = 1; v <= kSteps; ++v) {
    step(v);
  }
  wait_written(**gateway, kServers * kCounters * (kSteps + 1));
  (*gateway)->stop();
  expect_complete((*gateway)->store(), kSteps);
  const auto status = (*gateway)->status();
  EXPECT_EQ(status.samples_received, kServers * kCounters * (kSteps + 1));
  EXPECT_EQ(status.samples_failed, 0U);
  // The live bus saw every value too, per server.
  const std::lock_guard lock(live_mutex);
  for (std::size_t s = 0; s < kServers; ++s) {
    EXPECT_EQ(live["line-" + std::to_string(s)], kCounters * (kSteps + 1));
  }
}

// A server that keeps its values (a shop-floor controller's MemoryHistory): one Historizing
// Int64 under Objects/Line, written by the test with source times a millisecond apart.
class HistoryServer {
 public:
  HistoryServer() {
    opcua::server::ServerConfig config;
    config.transport.host = "127.0.0.1";
    config.advertised_host = "127.0.0.1";
    server_ = std::make_unique<opcua::server::Server>(config);
    auto history = std::make_shared<opcua::server::MemoryHistory>();
    server_->with_address_space([&](opcua::server::AddressSpace& space) {
      const opcua::server::ObjectSpec line = test::add_line_object(space, "urn:smartfactory:test:history");
      const std::uint16_t ns = line.node_id.namespace_index;
      opcua::server::VariableSpec v;
      v.node_id = node_ = opcua::NodeId(ns, opcua::String("Line.Count"));
      v.browse_name = opcua::QualifiedName(ns, "Count");
      v.parent = line.node_id;
      v.data_type = opcua::NodeId(0, opcua::id::Int64);
      v.value = opcua::DataValue(opcua::Variant(std::int64_t{0}));
      v.value.source_timestamp = stamp(0);
      v.historizing = true;
      v.access_level = v.user_access_level =
          opcua::server::access_level::CurrentRead | opcua::server::access_level::HistoryRead;
      (void)space.add_variable(v);
      history->attach(space);
    });
    server_->set_history_database(history);
    ok_ = server_->start().ok();
  }
  void set(std::int64_t value) {
    opcua::DataValue v{opcua::Variant(value)};
    v.source_timestamp = stamp(value);
    server_->with_address_space([&](opcua::server::AddressSpace& space) { (void)space.set_value(node_, v); });
  }
  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] std::uint16_t port() const { return server_->port(); }

 private:
  static opcua::DateTime stamp(std::int64_t value) {
    return opcua::DateTime(opcua::DateTime::from_unix_seconds(1'700'000'000).ticks() + value * 10'000);
  }
  std::unique_ptr<opcua::server::Server> server_;
  opcua::NodeId node_;
  bool ok_ = false;
};

std::vector<std::int64_t> stored_values(historian::Store& store) {
  std::vector<std::int64_t> values;
  auto series = store.list_series();
  if (!series || series->size() != 1) {
    return values;
  }
  auto samples = store.read_raw(series->front().id, historian::from_micros(0),
                                historian::from_micros(INT64_MAX / 2), 1'000'000);
  for (const historian::Sample& sample : samples ? *samples : std::vector<historian::Sample>{}) {
    values.push_back(std::get<std::int64_t>(sample.value));
  }
  return values;
}

TEST(GatewayCatchUp, WhatTheServerKeptWhileTheGatewayWasAwayIsReadBackOnceInOrder) {
  HistoryServer server;
  ASSERT_TRUE(server.ok());
  TempDir dir;
  GatewayConfig config =
      test::sqlite_gateway(dir, server_config("line", "opc.tcp://127.0.0.1:" + std::to_string(server.port()),
                                              {path_rule("/Objects/Line", 1)}));
  const auto expect_values_up_to = [&](std::int64_t last) {
    std::vector<std::int64_t> expected(static_cast<std::size_t>(last + 1));
    std::iota(expected.begin(), expected.end(), 0);
    auto gateway = Gateway::create(config);
    ASSERT_TRUE(gateway.ok()) << gateway.error().message;
    ASSERT_TRUE((*gateway)->start().ok());
    EXPECT_TRUE(eventually([&] { return stored_values((*gateway)->store()) == expected; }))
        << ::testing::PrintToString(stored_values((*gateway)->store()));
    (*gateway)->stop();
  };
  // Before the gateway's first start, faster than any sampling interval.
  for (std::int64_t v = 0; v <= 30; ++v) {  // 0 again: the initial value is not a write
    server.set(v);
  }
  expect_values_up_to(30);
  // While it was stopped.
  for (std::int64_t v = 31; v <= 60; ++v) {
    server.set(v);
  }
  expect_values_up_to(60);
}

class GatewayPostgres : public GatewayEndToEnd {
 protected:
  void SetUp() override {
    if (!historian::testing::PgServer::find_bin_dir()) {
      GTEST_SKIP() << "PostgreSQL is not installed (scripts/setup installs it)";
    }
    GatewayEndToEnd::SetUp();
    auto pg = historian::testing::PgServer::start();
    ASSERT_TRUE(pg.ok()) << pg.error().message;
    pg_ = std::move(*pg);
  }
  std::unique_ptr<historian::testing::PgServer> pg_;
};

TEST_F(GatewayPostgres, EveryValueReachesPostgresql) {
  auto gateway = Gateway::create(config_for(pg_->url()));
  ASSERT_TRUE(gateway.ok()) << gateway.error().message;
  ASSERT_TRUE((*gateway)->start().ok());
  wait_subscribed(**gateway);
  constexpr std::int64_t kSteps = 30;
  for (std::int64_t v = 1; v <= kSteps; ++v) {
    step(v);
  }
  wait_written(**gateway, kServers * kCounters * (kSteps + 1));
  (*gateway)->stop();
  expect_complete((*gateway)->store(), kSteps);
}

// The database dies and comes back, then a server restarts: nothing missing, nothing twice.
TEST_F(GatewayPostgres, DatabaseAndServerRestartsLoseAndDuplicateNothing) {
  auto gateway = Gateway::create(config_for(pg_->url()));
  ASSERT_TRUE(gateway.ok()) << gateway.error().message;
  historian::Store& store = (*gateway)->store();
  ASSERT_TRUE((*gateway)->start().ok());
  wait_subscribed(**gateway);
  std::int64_t v = 0;
  for (; v < 15; ++v) {
    step(v + 1);
  }
  ASSERT_TRUE(pg_->kill().ok());
  for (; v < 30; ++v) {
    step(v + 1);  // buffered: the database is away
  }
  wait_written(**gateway, kServers * kCounters * 31);
  EXPECT_GT((*gateway)->status().buffer.samples_buffered, 0U);
  ASSERT_TRUE(pg_->restart().ok());
  for (; v < 45; ++v) {
    step(v + 1);
  }
  // Server 1 restarts on its port; its counters keep their values, as a device's would.
  const std::uint16_t port = servers_[1]->port();
  servers_[1]->stop();
  servers_[1].reset();
  ASSERT_TRUE(eventually([&] { return (*gateway)->status().servers[1].phase == "reconnecting"; }));
  servers_[1] = std::make_unique<CounterServer>(port, counters_[1]);
  ASSERT_TRUE(servers_[1]->ok());
  wait_subscribed(**gateway);
  for (; v < 60; ++v) {
    step(v + 1);
  }
  wait_written(**gateway, kServers * kCounters * 61);
  ASSERT_TRUE(eventually([&] { return (*gateway)->status().buffer.buffered_records == 0; }));
  (*gateway)->stop();
  expect_complete(store, 60);
}

TEST(GatewayErrors, UnreachableServersAreRetriedWhileOthersWork) {
  TempDir dir;
  auto counter = std::make_shared<Counter>();
  CounterServer good(0, {counter});
  ASSERT_TRUE(good.ok());
  GatewayConfig config;
  config.historian.url = "sqlite:" + (dir.path() / "h.db").string();
  config.historian.buffer = dir.path() / "buffer";
  // A rule that matches nothing is a warning, not a failure.
  config.servers.push_back(server_config("good", "opc.tcp://127.0.0.1:" + std::to_string(good.port()),
                                         {path_rule("/Objects/Line"), path_rule("/Objects/NoSuchThing")}));
  // Nothing listens on port 1; a host name that does not resolve.
  config.servers.push_back(server_config("refused", "opc.tcp://127.0.0.1:1", {node_rule("i=2258")}));
  config.servers.push_back(
      server_config("unknown", "opc.tcp://no-such-host.invalid:4840", {node_rule("i=2258")}));
  auto gateway = Gateway::create(config);
  ASSERT_TRUE(gateway.ok());
  ASSERT_TRUE((*gateway)->start().ok());
  ASSERT_TRUE(eventually([&] {
    const auto s = (*gateway)->status();
    return s.servers[0].phase == "subscribed" && !s.servers[1].last_error.empty() &&
           !s.servers[2].last_error.empty();
  }));
  const auto status = (*gateway)->status();
  EXPECT_EQ(status.servers[0].series, 1U);
  ASSERT_EQ(status.servers[0].warnings.size(), 1U);
  EXPECT_NE(status.servers[0].warnings[0].find("NoSuchThing"), std::string::npos);
  EXPECT_EQ(status.servers[1].phase, "connecting");
  EXPECT_FALSE(status.servers[1].connected);
  EXPECT_EQ(status.servers[2].phase, "connecting");
  counter->set(7);
  ASSERT_TRUE(eventually([&] { return (*gateway)->status().samples_written >= 2; }));
  (*gateway)->stop();
}

// The dashboard's commands go through the gateway's connections: a method by the browse path of
// its Object and its browse name.
TEST(GatewayCall, AMethodIsCalledOnTheNamedServer) {
  TempDir dir;
  auto counter = std::make_shared<Counter>();
  CounterServer server(0, {counter});
  ASSERT_TRUE(server.ok());
  auto gateway = Gateway::create(
      test::sqlite_gateway(dir, server_config("line", "opc.tcp://127.0.0.1:" + std::to_string(server.port()),
                                              {path_rule("/Objects/Line")})));
  ASSERT_TRUE(gateway) << gateway.error().describe();
  ASSERT_TRUE((*gateway)->start().ok());
  ASSERT_TRUE(eventually([&] { return (*gateway)->status().servers[0].phase == "subscribed"; }));
  counter->set(5);
  auto out = (*gateway)->call("line", "/Objects/Line", "Set", {opcua::Variant(std::int64_t{42})});
  ASSERT_TRUE(out) << out.error().describe();
  ASSERT_EQ(out->size(), 1U);
  EXPECT_EQ(*out->at(0).get_if<std::int64_t>(), 5);
  EXPECT_EQ(counter->value(), 42);
  // Twice: the resolved path is remembered, the call made again.
  ASSERT_TRUE((*gateway)->call("line", "/Objects/Line", "Set", {opcua::Variant(std::int64_t{43})}));
  EXPECT_EQ(counter->value(), 43);

  auto bad = (*gateway)->call("line", "/Objects/Line", "Set", {opcua::Variant(std::string("x"))});
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("BadInvalidArgument"), std::string::npos) << bad.error().message;
  auto no_method = (*gateway)->call("line", "/Objects/Line", "Explode", {});
  ASSERT_FALSE(no_method);
  EXPECT_EQ(no_method.error().code, Errc::not_found);
  EXPECT_NE(no_method.error().message.find("Explode"), std::string::npos);
  auto no_server = (*gateway)->call("other", "/Objects/Line", "Set", {});
  ASSERT_FALSE(no_server);
  EXPECT_EQ(no_server.error().code, Errc::not_found);
  server.stop();
  ASSERT_TRUE(eventually([&] { return !(*gateway)->status().servers[0].connected; }));
  auto away = (*gateway)->call("line", "/Objects/Line", "Set", {opcua::Variant(std::int64_t{1})});
  ASSERT_FALSE(away);
  EXPECT_EQ(away.error().code, Errc::state);
  (*gateway)->stop();
}

// A variable the server adds after the gateway subscribed (a controller's tag appearing with its
// first publication) is found at the next rediscovery and collected like the others; with
// rediscovery off it is not.
TEST(GatewayRediscovery, AVariableAddedToTheModelLaterIsSubscribed) {
  for (const bool enabled : {true, false}) {
    SCOPED_TRACE(enabled ? "rediscover every second" : "rediscovery off");
    TempDir dir;
    auto first = std::make_shared<Counter>();
    CounterServer server(0, {first});
    ASSERT_TRUE(server.ok());
    ServerConfig config = server_config("line", "opc.tcp://127.0.0.1:" + std::to_string(server.port()),
                                        {path_rule("/Objects/Line", 1)});
    config.rediscover = std::chrono::seconds(enabled ? 1 : 0);
    auto gateway = Gateway::create(test::sqlite_gateway(dir, config));
    ASSERT_TRUE(gateway) << gateway.error().describe();
    ASSERT_TRUE((*gateway)->start().ok());
    ASSERT_TRUE(eventually([&] {
      const auto s = (*gateway)->status().servers[0];
      return s.phase == "subscribed" && s.series == 1;
    }));

    auto later = std::make_shared<Counter>();
    later->set(77);
    ASSERT_TRUE(server.add_counter(1, later));
    const auto stored_77 = [&] {
      auto series = (*gateway)->store().list_series();
      for (const auto& s : series ? *series : std::vector<historian::Series>{}) {
        auto latest = (*gateway)->store().latest(s.id);
        if (s.info.browse_path == "/Objects/Line/Counter1" && latest && *latest &&
            std::get<std::int64_t>((*latest)->value) == 77) {
          return true;
        }
      }
      return false;
    };
    if (enabled) {
      EXPECT_TRUE(eventually(stored_77)) << "the added counter's value reaches the historian";
      EXPECT_EQ((*gateway)->status().servers[0].series, 2U);
      EXPECT_TRUE(eventually([&] { return server.monitored_items() == 2; }));
    } else {
      std::this_thread::sleep_for(std::chrono::seconds(2));
      EXPECT_FALSE(stored_77());
      EXPECT_EQ((*gateway)->status().servers[0].series, 1U);
    }
    (*gateway)->stop();
  }
}

// A subscriber that comes late gets the newest value of every series first (retained values);
// one that does not ask for them gets only what comes after.
TEST(LiveBusTest, ALateSubscriberStartsWithTheNewestValueOfEverySeries) {
  LiveBus bus;
  const historian::SeriesInfo a{"s", "ns=1;s=A", "/Objects/A", historian::DataType::int64};
  const historian::SeriesInfo b{"s", "ns=1;s=B", "/Objects/B", historian::DataType::int64};
  auto update = [](const historian::SeriesInfo& series, std::int64_t seconds, std::int64_t value) {
    LiveUpdate u;
    u.series = &series;
    u.sample.source_time = historian::Timestamp{std::chrono::seconds(seconds)};
    u.sample.value = value;
    return u;
  };
  bus.publish(update(a, 1, 10));
  bus.publish(update(a, 3, 30));
  bus.publish(update(a, 2, 20));  // older than the newest: not the current value
  bus.publish(update(b, 1, 7));
  std::vector<std::pair<std::string, std::int64_t>> seen;
  std::size_t replayed = 0;
  auto late = bus.subscribe_with_current([&](const LiveUpdate& u) {
    replayed += u.replayed ? 1 : 0;
    seen.emplace_back(u.series->browse_path, std::get<std::int64_t>(u.sample.value));
  });
  EXPECT_EQ(replayed, 2U);
  EXPECT_EQ(seen, (std::vector<std::pair<std::string, std::int64_t>>{{"/Objects/A", 30}, {"/Objects/B", 7}}));
  std::size_t plain = 0;
  auto other = bus.subscribe([&](const LiveUpdate&) { ++plain; });
  EXPECT_EQ(plain, 0U);
  bus.publish(update(b, 2, 8));
  EXPECT_EQ(plain, 1U);
  EXPECT_EQ(seen.size(), 3U);
}

TEST(GatewayErrors, AnUnusableHistorianIsRefusedAtCreate) {
  GatewayConfig config;
  config.historian.url = "sqlite:/nonexistent/dir/h.db";
  config.historian.buffer = "/proc/sf-cannot-create-this";
  auto gateway = Gateway::create(config);
  ASSERT_FALSE(gateway.ok());
  EXPECT_NE(gateway.error().message.find("historian"), std::string::npos) << gateway.error().message;
}

}  // namespace
}  // namespace sf::cloud
