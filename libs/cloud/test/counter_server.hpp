// Test servers with monotonic counters: our OPC UA server with Int64 counters under
// Objects/Line. The test steps the counters; wait_sampled() returns once the server has sampled
// the latest value of every counter, so no value can be skipped by sampling and the test knows
// exactly which values were produced. A counter keeps its value and source timestamp across a
// server restart (its state lives in the test), as a real device's would.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "sf/cloud/config.hpp"
#include "sf/opcua/server/server.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::cloud::test {

class Counter {
 public:
  void set(std::int64_t value) {
    stamp_ = opcua::DateTime::from_system_clock(std::chrono::system_clock::now()).ticks();
    value_ = value;
    ++generation_;
  }
  [[nodiscard]] bool sampled() const { return sampled_.load() >= generation_.load(); }
  [[nodiscard]] std::int64_t value() const { return value_.load(); }
  opcua::DataValue read() {
    const std::uint64_t generation = generation_.load();
    opcua::DataValue v{opcua::Variant(value_.load())};
    v.source_timestamp = opcua::DateTime(stamp_.load());
    sampled_ = generation;
    return v;
  }

 private:
  std::atomic<std::int64_t> value_{0};
  std::atomic<std::int64_t> stamp_{opcua::DateTime::from_unix_seconds(1'700'000'000).ticks()};
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::uint64_t> sampled_{0};
};

inline SubscribeRule path_rule(std::string path, unsigned depth = 3) {
  SubscribeRule rule;
  rule.browse_path = std::move(path);
  rule.depth = depth;
  return rule;
}

inline SubscribeRule node_rule(std::string node) {
  SubscribeRule rule;
  rule.node = std::move(node);
  return rule;
}

inline ServerConfig server_config(std::string name, std::string url, std::vector<SubscribeRule> rules) {
  ServerConfig server;
  server.name = std::move(name);
  server.url = std::move(url);
  server.subscribe = std::move(rules);
  return server;
}

using TempDir = sf::testing::TempDir;

// A gateway of one server writing to SQLite in `dir`, with a short flush for quick tests.
inline GatewayConfig sqlite_gateway(const TempDir& dir, ServerConfig server) {
  GatewayConfig config;
  config.historian.url = "sqlite:" + (dir.path() / "history.db").string();
  config.historian.buffer = dir.path() / "buffer";
  config.historian.flush_interval = std::chrono::milliseconds(20);
  config.servers.push_back(std::move(server));
  return config;
}

// Objects/Line in a namespace of its own (`uri`), where the test servers put their variables.
inline opcua::server::ObjectSpec add_line_object(opcua::server::AddressSpace& space, std::string_view uri) {
  const std::uint16_t ns = space.add_namespace(std::string(uri));
  opcua::server::ObjectSpec line;
  line.node_id = opcua::NodeId(ns, opcua::String("Line"));
  line.browse_name = opcua::QualifiedName(ns, "Line");
  line.parent = opcua::NodeId(0, opcua::id::ObjectsFolder);
  line.reference_type = opcua::NodeId(0, opcua::id::Organizes);
  (void)space.add_object(line);
  return line;
}

class CounterServer {
 public:
  CounterServer(std::uint16_t port, const std::vector<std::shared_ptr<Counter>>& counters) {
    opcua::server::ServerConfig config;
    config.transport.host = "127.0.0.1";
    config.transport.port = port;
    config.advertised_host = "127.0.0.1";
    server_ = std::make_unique<opcua::server::Server>(config);
    server_->with_address_space([&](opcua::server::AddressSpace& space) {
      const opcua::server::ObjectSpec line = add_line_object(space, "urn:smartfactory:test:counters");
      const std::uint16_t ns = line.node_id.namespace_index;
      line_ = line.node_id;
      for (std::size_t i = 0; i < counters.size(); ++i) {
        (void)add_counter_variable(space, i, counters[i]);
      }
      // Line.Set(Value: Int64) → Previous: Int64 sets the first counter (method calls through
      // the gateway); a value that is not an Int64 is BadInvalidArgument.
      opcua::server::MethodSpec set;
      set.node_id = opcua::NodeId(ns, opcua::String("Line.Set"));
      set.browse_name = opcua::QualifiedName(ns, "Set");
      set.parent = line.node_id;
      opcua::Argument argument;
      argument.name = "Value";
      argument.data_type = opcua::NodeId(0, opcua::id::Int64);
      argument.value_rank = opcua::server::value_rank::Scalar;
      set.input_arguments = {argument};
      set.callback = [first = counters.empty() ? nullptr : counters[0]](const opcua::NodeId&,
                                                                        const std::vector<opcua::Variant>& in,
                                                                        std::vector<opcua::Variant>& out) {
        const auto* value = in.empty() ? nullptr : in[0].get_if<std::int64_t>();
        if (value == nullptr || first == nullptr) {
          return opcua::StatusCode(opcua::status::BadInvalidArgument);
        }
        out.emplace_back(first->value());
        first->set(*value);
        return opcua::StatusCode{};
      };
      (void)space.add_method(set);
    });
    ok_ = server_->start().ok();
  }
  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] std::uint16_t port() const { return server_->port(); }
  [[nodiscard]] std::size_t monitored_items() const { return server_->monitored_item_count(); }
  void stop() { server_->stop(); }
  // Line.Counter<i> added while the server runs (a model that grows, as a controller's tags do).
  Status add_counter(std::size_t i, const std::shared_ptr<Counter>& counter) {
    Status added;
    server_->with_address_space(
        [&](opcua::server::AddressSpace& space) { added = add_counter_variable(space, i, counter); });
    return added;
  }

 private:
  Status add_counter_variable(opcua::server::AddressSpace& space, std::size_t i,
                              const std::shared_ptr<Counter>& counter) {
    const std::uint16_t ns = line_.namespace_index;
    opcua::server::VariableSpec v;
    v.node_id = opcua::NodeId(ns, opcua::String("Line.Counter" + std::to_string(i)));
    v.browse_name = opcua::QualifiedName(ns, opcua::String("Counter" + std::to_string(i)));
    v.parent = line_;
    v.data_type = opcua::NodeId(0, opcua::id::Int64);
    v.reader = [counter] { return counter->read(); };
    auto added = space.add_variable(v);
    if (!added) {
      return added.error();
    }
    return {};
  }

  std::unique_ptr<opcua::server::Server> server_;
  opcua::NodeId line_;
  bool ok_ = false;
};

// Polls pred every few milliseconds until it holds or the timeout passes.
template <typename Pred>
bool eventually(Pred pred, std::chrono::seconds timeout = std::chrono::seconds(30)) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > until) {
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

}  // namespace sf::cloud::test
