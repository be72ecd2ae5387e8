// The demo information model of issue 5 (`smartfactory opcua server --demo-model`): namespace
// urn:smartfactory:demo with the object Demo under Objects holding
//   Temperature  Double, read-only, a new value every 100 ms
//   Counter      Int32, read-write
//   Multiply     method (a: Double, b: Double) → Double
// NodeIds are strings ("Demo", "Demo.Temperature", ...) so clients can name them.
#pragma once

#include <chrono>

#include "sf/core/result.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::opcua::server {

inline constexpr std::string_view kDemoNamespaceUri = "urn:smartfactory:demo";

struct DemoModelOptions {
  std::chrono::milliseconds temperature_period{100};
};

// Adds the model and starts the Temperature timer on the server's loop.
Status add_demo_model(Server& server, DemoModelOptions options = {});

// The model without the timer (for tests of the address space alone).
Status add_demo_nodes(AddressSpace& space);

}  // namespace sf::opcua::server
