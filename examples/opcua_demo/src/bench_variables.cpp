// The demo model's benchmark variables (DemoModelOptions::bench_variables): the folder Demo/Bench
// with Demo.Bench.<i>, all changing on every step of one timer.
#include <memory>
#include <string>
#include <vector>

#include "sf/examples/opcua_demo.hpp"

namespace sf::examples {

using namespace opcua;          // NOLINT(google-build-using-namespace): the model is built of
using namespace opcua::server;  // NOLINT(google-build-using-namespace): OPC UA nodes throughout

namespace {

// Variable i at step s: changes on every step, differs between variables.
double bench_value(std::size_t i, std::uint64_t step) {
  return static_cast<double>(step) + static_cast<double>(i) / 1000.0;
}

NodeId bench_node_id(std::uint16_t ns, std::size_t i) {
  return NodeId(ns, String("Demo.Bench." + std::to_string(i)));
}

}  // namespace

Status add_bench_variables(AddressSpace& space, std::size_t count) {
  const auto ns = space.namespace_index(kDemoNamespaceUri);
  if (!ns) {
    return make_error(Errc::not_found, "add_bench_variables: the demo model is missing");
  }
  ObjectSpec folder;
  folder.node_id = NodeId(*ns, String("Demo.Bench"));
  folder.browse_name = QualifiedName(*ns, "Bench");
  folder.description = LocalizedText("en", "Variables that all change every 100 ms, for benchmarks");
  folder.parent = NodeId(*ns, String("Demo"));
  folder.reference_type = NodeId(0, id::Organizes);
  folder.type_definition = NodeId(0, id::FolderType);
  auto folder_id = space.add_object(folder);
  if (!folder_id) {
    return folder_id.error();
  }
  for (std::size_t i = 0; i < count; ++i) {
    VariableSpec variable;
    variable.node_id = bench_node_id(*ns, i);
    variable.browse_name = QualifiedName(*ns, std::to_string(i));
    variable.parent = *folder_id;
    variable.reference_type = NodeId(0, id::Organizes);
    variable.data_type = NodeId(0, id::Double);
    variable.value = DataValue(Variant(bench_value(i, 0)));
    variable.access_level = access_level::CurrentRead;
    variable.user_access_level = access_level::CurrentRead;
    variable.minimum_sampling_interval = 100.0;
    if (auto id = space.add_variable(variable); !id) {
      return id.error();
    }
  }
  return {};
}

void start_bench_timer(Server& server, std::size_t count, std::chrono::milliseconds period) {
  server.with_address_space([&server, count, period](AddressSpace& space) {
    const auto ns = space.namespace_index(kDemoNamespaceUri);
    if (!ns) {
      return;
    }
    auto ids = std::make_shared<std::vector<NodeId>>();
    for (std::size_t i = 0; i < count; ++i) {
      ids->push_back(bench_node_id(*ns, i));
    }
    auto step = std::make_shared<std::uint64_t>(0);
    const Clock& clock = server.loop().clock();
    server.loop().add_periodic(period, [&space, &clock, ids, step] {
      ++*step;
      const auto now = DateTime::from_system_clock(clock.utc_now());
      for (std::size_t i = 0; i < ids->size(); ++i) {
        DataValue value(Variant(bench_value(i, *step)));
        value.source_timestamp = now;
        (void)space.set_value((*ids)[i], std::move(value));
      }
    });
  });
}

}  // namespace sf::examples
