#include "sf/examples/opcua_demo.hpp"

#include <cmath>

#include "sf/opcua/status_codes.hpp"

namespace sf::examples {

using namespace opcua;          // NOLINT(google-build-using-namespace): the model is built of
using namespace opcua::server;  // NOLINT(google-build-using-namespace): OPC UA nodes throughout

namespace {

Argument double_argument(std::string_view name, std::string_view description) {
  Argument arg;
  arg.name = std::string(name);
  arg.data_type = NodeId(0, id::Double);
  arg.value_rank = value_rank::Scalar;
  arg.description = LocalizedText("en", std::string(description));
  return arg;
}

// 20 °C with a slow ±5 K swing and a little ripple: changes on every sample, stays plausible.
double temperature_at(std::uint64_t step) {
  const auto t = static_cast<double>(step) / 10.0;
  return 20.0 + 5.0 * std::sin(t / 30.0) + 0.25 * std::sin(t * 3.0);
}

}  // namespace

Status add_demo_nodes(AddressSpace& space) {
  const std::uint16_t ns = space.add_namespace(kDemoNamespaceUri);

  ObjectSpec demo;
  demo.node_id = NodeId(ns, String("Demo"));
  demo.browse_name = QualifiedName(ns, "Demo");
  demo.description = LocalizedText("en", "The demo model of smartfactory's OPC UA server");
  demo.parent = NodeId(0, id::ObjectsFolder);
  demo.reference_type = NodeId(0, id::Organizes);
  demo.type_definition = NodeId(0, id::BaseObjectType);
  auto demo_id = space.add_object(demo);
  if (!demo_id) {
    return demo_id.error();
  }

  VariableSpec temperature;
  temperature.node_id = NodeId(ns, String("Demo.Temperature"));
  temperature.browse_name = QualifiedName(ns, "Temperature");
  temperature.description = LocalizedText("en", "Simulated temperature in °C, a new value every 100 ms");
  temperature.parent = *demo_id;
  temperature.data_type = NodeId(0, id::Double);
  temperature.value = DataValue(Variant(temperature_at(0)));
  temperature.access_level = access_level::CurrentRead;
  temperature.user_access_level = access_level::CurrentRead;
  temperature.minimum_sampling_interval = 100.0;
  auto temperature_id = space.add_variable(temperature);
  if (!temperature_id) {
    return temperature_id.error();
  }

  VariableSpec counter;
  counter.node_id = NodeId(ns, String("Demo.Counter"));
  counter.browse_name = QualifiedName(ns, "Counter");
  counter.description = LocalizedText("en", "A counter clients may read and write");
  counter.parent = *demo_id;
  counter.data_type = NodeId(0, id::Int32);
  counter.value = DataValue(Variant(std::int32_t{0}));
  counter.access_level = access_level::ReadWrite;
  counter.user_access_level = access_level::ReadWrite;
  auto counter_id = space.add_variable(counter);
  if (!counter_id) {
    return counter_id.error();
  }

  MethodSpec multiply;
  multiply.node_id = NodeId(ns, String("Demo.Multiply"));
  multiply.browse_name = QualifiedName(ns, "Multiply");
  multiply.description = LocalizedText("en", "Returns a × b");
  multiply.parent = *demo_id;
  multiply.input_arguments = {double_argument("a", "first factor"), double_argument("b", "second factor")};
  multiply.output_arguments = {double_argument("product", "a × b")};
  multiply.callback = [](const NodeId&, const std::vector<Variant>& in, std::vector<Variant>& out) {
    // InputArguments were checked against the Argument types before the call.
    const double* a = in.at(0).get_if<double>();
    const double* b = in.at(1).get_if<double>();
    if (a == nullptr || b == nullptr) {
      return StatusCode(status::BadInvalidArgument);
    }
    out.emplace_back(*a * *b);
    return StatusCode{};
  };
  auto multiply_id = space.add_method(multiply);
  if (!multiply_id) {
    return multiply_id.error();
  }
  return {};
}

Status add_demo_model(Server& server, DemoModelOptions options) {
  Status result;
  server.with_address_space([&](AddressSpace& space) {
    result = add_demo_nodes(space);
    if (result && options.bench_variables > 0) {
      result = add_bench_variables(space, options.bench_variables);
    }
  });
  if (!result) {
    return result;
  }
  if (options.bench_variables > 0) {
    start_bench_timer(server, options.bench_variables, options.bench_period);
  }
  server.with_address_space([&server, options](AddressSpace& space) {
    const NodeId temperature(*space.namespace_index(kDemoNamespaceUri), String("Demo.Temperature"));
    auto step = std::make_shared<std::uint64_t>(0);
    const Clock& clock = server.loop().clock();
    server.loop().add_periodic(options.temperature_period, [&space, &clock, temperature, step] {
      ++*step;
      DataValue value(Variant(temperature_at(*step)));
      value.source_timestamp = DateTime::from_system_clock(clock.utc_now());
      (void)space.set_value(temperature, std::move(value));
    });
  });
  return {};
}

}  // namespace sf::examples
