// The demo model's benchmark variables (DemoModelOptions::bench_variables, `smartfactory opcua
// server --bench-variables N`): Demo/Bench/Demo.Bench.<i>, Double, read-only, all changing.
#include "sf/examples/opcua_demo.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "sf/opcua/server/ns0.hpp"

namespace sf::opcua::server {
namespace {

using namespace std::chrono_literals;
using examples::add_bench_variables;
using examples::add_demo_model;
using examples::add_demo_nodes;
using examples::DemoModelOptions;
using examples::kDemoNamespaceUri;

NodeId bench_id(std::uint16_t ns, int i) {
  return NodeId(ns, String("Demo.Bench." + std::to_string(i)));
}

double value_of(const AddressSpace& space, const NodeId& id) {
  auto value = space.value(id);
  const double* d = value ? value->value.get_if<double>() : nullptr;
  return d != nullptr ? *d : -1.0;
}

TEST(DemoModelTest, BenchVariablesAreReadOnlyDoublesInTheBenchFolder) {
  AddressSpace space;
  ASSERT_TRUE(build_namespace0(space));
  ASSERT_TRUE(add_demo_nodes(space));
  ASSERT_TRUE(add_bench_variables(space, 3));
  const std::uint16_t ns = *space.namespace_index(kDemoNamespaceUri);

  const NodeId folder(ns, String("Demo.Bench"));
  ASSERT_NE(space.find(folder), nullptr);
  ASSERT_NE(space.type_definition(folder), nullptr);
  EXPECT_EQ(*space.type_definition(folder), NodeId(0, id::FolderType));
  EXPECT_EQ(space.child(NodeId(ns, String("Demo")), QualifiedName(ns, "Bench"))->node_id, folder);

  for (int i = 0; i < 3; ++i) {
    const auto* variable = space.find_as<VariableNode>(bench_id(ns, i));
    ASSERT_NE(variable, nullptr) << i;
    EXPECT_EQ(variable->data_type, NodeId(0, id::Double));
    EXPECT_EQ(variable->access_level, access_level::CurrentRead);
    EXPECT_EQ(variable->minimum_sampling_interval, 100.0);
    EXPECT_DOUBLE_EQ(value_of(space, bench_id(ns, i)), i / 1000.0);
    EXPECT_EQ(space.child(folder, QualifiedName(ns, std::to_string(i)))->node_id, bench_id(ns, i));
  }
  EXPECT_EQ(space.find(bench_id(ns, 3)), nullptr);
}

TEST(DemoModelTest, BenchVariablesNeedTheDemoModel) {
  AddressSpace space;
  ASSERT_TRUE(build_namespace0(space));
  EXPECT_FALSE(add_bench_variables(space, 1));
}

TEST(DemoModelTest, NoBenchVariablesByDefault) {
  Server server(ServerConfig{});
  ASSERT_TRUE(add_demo_model(server));
  server.with_address_space([](AddressSpace& space) {
    const std::uint16_t ns = *space.namespace_index(kDemoNamespaceUri);
    EXPECT_EQ(space.find(NodeId(ns, String("Demo.Bench"))), nullptr);
  });
}

TEST(DemoModelTest, EveryBenchVariableChangesOnEveryStep) {
  DemoModelOptions options;
  options.bench_variables = 2;
  options.bench_period = 10ms;
  Server server(ServerConfig{});
  ASSERT_TRUE(add_demo_model(server, options));
  double first = 0;
  double second = 0;
  // Waits (without a bound on how fast) until the timer has stepped at least once.
  for (int attempt = 0; attempt < 1000 && first < 1.0; ++attempt) {
    std::this_thread::sleep_for(10ms);
    server.with_address_space([&](AddressSpace& space) {
      const std::uint16_t ns = *space.namespace_index(kDemoNamespaceUri);
      first = value_of(space, bench_id(ns, 0));
      second = value_of(space, bench_id(ns, 1));
    });
  }
  EXPECT_GE(first, 1.0);
  // Both were set in the same step: variable i is step + i/1000.
  EXPECT_NEAR(second - first, 0.001, 1e-9);
}

}  // namespace
}  // namespace sf::opcua::server
