// The demo information model (`smartfactory opcua server --demo-model`, the node-opcua peer
// tests/peers/opcua/node_server.mjs has the same): namespace
// urn:smartfactory:demo with the object Demo under Objects holding
//   Temperature  Double, read-only, a new value every 100 ms
//   Counter      Int32, read-write
//   Multiply     method (a: Double, b: Double) → Double
// NodeIds are strings ("Demo", "Demo.Temperature", ...) so clients can name them.
//
// For benchmarks (bench/bench_opcua_server) the model can carry N more variables: the folder
// Demo/Bench holding Demo.Bench.0 … Demo.Bench.<N-1>, Double, read-only, minimum sampling
// interval 100 ms, all with a new value every bench_period (variable i at step s: s + i/1000).
#pragma once

#include <chrono>
#include <cstddef>

#include "sf/core/result.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::examples {

inline constexpr std::string_view kDemoNamespaceUri = "urn:smartfactory:demo";

struct DemoModelOptions {
  std::chrono::milliseconds temperature_period{100};
  std::size_t bench_variables = 0;  // Demo.Bench.<i>, none by default
  std::chrono::milliseconds bench_period{100};
};

// Adds the model and starts the Temperature timer on the server's loop.
Status add_demo_model(opcua::server::Server& server, DemoModelOptions options = {});

// The model without the timer (for tests of the address space alone).
Status add_demo_nodes(opcua::server::AddressSpace& space);

// The Bench folder under Demo with `count` variables at step 0, without the timer (after
// add_demo_nodes).
Status add_bench_variables(opcua::server::AddressSpace& space, std::size_t count);
// Steps the first `count` bench variables every `period` on the server's loop.
void start_bench_timer(opcua::server::Server& server, std::size_t count, std::chrono::milliseconds period);

}  // namespace sf::examples
