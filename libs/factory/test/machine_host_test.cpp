// A controller served by MachineHost on our OPC UA server, seen by our OPC UA client over
// loopback: browse and read the model, subscribe to the PackML state, call the PackML methods
// (refused in the wrong state and for viewers), tag quality as StatusCode, and the threading
// contract (commands run on the controller's thread; one it does not take in time times out and
// never runs).
#include "sf/factory/machine_host.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <future>
#include <optional>
#include <thread>

#include "collector.hpp"  // libs/opcua/test
#include "sf/factory/controller_process.hpp"
#include "sf/factory/testing/packml_machine.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::factory {
namespace {

namespace ua = sf::opcua;
using namespace std::chrono_literals;
using testing::PackMLMachine;

constexpr std::string_view kExecuteState = "PackML.BaseStateMachine.MachineState.ExecuteState";

// The controller's thread as a process runs it, without real-time scheduling, its snapshot
// refreshed every 2 ms.
ControllerThreadOptions thread_options() {
  ControllerThreadOptions o;
  o.realtime = false;
  o.status_interval = 2ms;
  return o;
}

class MachineHostTest : public ::testing::Test {
 protected:
  ~MachineHostTest() override {
    host.reset();  // before the controller thread (machine_host.hpp)
    thread.stop();
  }

  // A server whose anonymous users have `role`, and the machine's model on it.
  void serve(std::string_view role, MachineHostOptions options = {}) {
    ua::server::ServerConfig config;
    config.transport.host = "127.0.0.1";
    config.transport.port = 0;
    config.advertised_host = "127.0.0.1";
    config.security.anonymous_role = std::string(role);
    server = std::make_unique<ua::server::Server>(config);
    options.publish_interval = 5ms;
    auto attached = MachineHost::attach(*server, thread, machine.identification(), std::move(options));
    ASSERT_TRUE(attached.ok()) << attached.error().describe();
    host = std::move(*attached);
    ASSERT_TRUE(server->start().ok());
    ua::ClientConfig cc;
    cc.endpoint_url = server->endpoint_url();
    cc.auto_reconnect = false;
    client = std::make_unique<ua::SyncClient>(cc);
    ASSERT_TRUE(client->connect().ok());
  }
  // The state of the controller itself, asked on its thread.
  PackMLState controller_state() {
    return thread.call([](MachineController& m) { return m.status().packml.state; });
  }

  ua::StatusCode call(std::string_view object, PackMLCommand command) {
    auto out = client->call_method(host->node(object),
                                   host->node(fmt::format("{}.{}", object, to_string(command))), {});
    return out.ok() ? ua::StatusCode{} : ua::status_of(out.error());
  }
  ua::StatusCode execute(PackMLCommand command) { return call(kExecuteState, command); }
  ua::DataValue read(std::string_view path) {
    auto v = client->read({ua::value_of(host->node(path))});
    EXPECT_TRUE(v.ok());
    return v.ok() ? v->at(0) : ua::DataValue{};
  }
  std::int32_t state() {
    const ua::DataValue v = read("PackML.Status.StateCurrent");
    const auto* s = v.value.get_if<std::int32_t>();
    return s != nullptr ? *s : -1;
  }
  // The values of a node as a subscription delivers them (every change: sampling on change).
  std::shared_ptr<ua::test::Collector<ua::DataValue>> watch(std::string_view path) {
    auto values = std::make_shared<ua::test::Collector<ua::DataValue>>();
    if (!subscription) {
      auto sub = client->create_subscription({.publishing_interval_ms = 20});
      EXPECT_TRUE(sub.ok());
      subscription = sub.ok() ? *sub : 0;
    }
    ua::MonitoringParameters params;
    params.sampling_interval = 0;
    params.queue_size = 50;
    EXPECT_TRUE(client
                    ->monitor_value(*subscription, ua::value_of(host->node(path)), params,
                                    [values](const ua::DataValue& v) { values->add(v); })
                    .ok());
    return values;
  }
  // Waits until the last value delivered satisfies pred.
  static bool last_is(ua::test::Collector<ua::DataValue>& values,
                      const std::function<bool(const ua::DataValue&)>& pred) {
    return values.wait_until(
        [&](const std::vector<ua::DataValue>& all) { return !all.empty() && pred(all.back()); });
  }
  static bool state_is(ua::test::Collector<ua::DataValue>& states, PackMLState want) {
    return last_is(states, [want](const ua::DataValue& v) {
      return v.value == ua::Variant(static_cast<std::int32_t>(want));
    });
  }

  PackMLMachine machine{SteadyClock::instance()};
  ControllerThread thread{machine, SteadyClock::instance(), thread_options()};
  std::unique_ptr<ua::server::Server> server;
  std::unique_ptr<MachineHost> host;
  std::unique_ptr<ua::SyncClient> client;
  std::optional<ua::SyncClient::SubscriptionId> subscription;
};

TEST_F(MachineHostTest, ClientsBrowseTheModelAndReadIdentificationAndState) {
  serve("viewer");
  const auto ns = client->namespace_index(kMachineNamespace);
  ASSERT_TRUE(ns.ok());
  auto objects = client->browse_children(ua::NodeId(0, ua::id::ObjectsFolder));
  ASSERT_TRUE(objects.ok());
  EXPECT_TRUE(std::any_of(objects->begin(), objects->end(), [&](const auto& r) {
    return r.browse_name == ua::QualifiedName(*ns, "Machines");
  }));
  auto machines = client->browse_children(ua::NodeId(*ns, ua::String("Machines")));
  ASSERT_TRUE(machines.ok());
  ASSERT_EQ(machines->size(), 1U);
  EXPECT_EQ(machines->at(0).browse_name, ua::QualifiedName(*ns, "ScaraRobot1"));
  auto children = client->browse_children(host->machine());
  ASSERT_TRUE(children.ok());
  std::vector<std::string> names;
  for (const auto& r : *children) {
    names.push_back(r.browse_name.name.str());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"Fault", "Identification", "Job", "PackML", "Tags"}));
  EXPECT_EQ(read("Identification.Manufacturer").value.get_if<ua::LocalizedText>()->text, "smartfactory");
  EXPECT_EQ(*read("Identification.SerialNumber").value.get_if<ua::String>(), "SR1-0001");
  // attach() published the first status before the server started.
  EXPECT_EQ(state(), static_cast<std::int32_t>(PackMLState::Stopped));
  EXPECT_EQ(*read("PackML.Status.UnitModeCurrent").value.get_if<std::int32_t>(), 1);  // Production
  EXPECT_EQ(*read("Tags.sensor.temperature").value.get_if<double>(), 21.5);
}

TEST_F(MachineHostTest, OperatorsDriveThePackMLStateMachineAndSubscribersSeeIt) {
  serve("operator");
  thread.start();
  auto states = watch("PackML.Status.StateCurrent");
  const auto saw = [&](PackMLState s) { return state_is(*states, s); };
  ASSERT_TRUE(saw(PackMLState::Stopped));
  EXPECT_EQ(execute(PackMLCommand::Reset), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Idle));
  EXPECT_EQ(execute(PackMLCommand::Start), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Execute));
  EXPECT_EQ(execute(PackMLCommand::Hold), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Held));
  EXPECT_EQ(read("PackML.Admin.StopReason.Message").value, ua::Variant("operator"));
  EXPECT_EQ(execute(PackMLCommand::Unhold), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Execute));
  EXPECT_EQ(execute(PackMLCommand::Suspend), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Suspended));
  EXPECT_EQ(execute(PackMLCommand::Unsuspend), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Execute));
  EXPECT_EQ(call("PackML.BaseStateMachine.MachineState", PackMLCommand::Stop), ua::StatusCode{});
  ASSERT_TRUE(saw(PackMLState::Stopped));
  // The commands ran on the controller: its own unit is where the model says.
  EXPECT_EQ(controller_state(), PackMLState::Stopped);
}

TEST_F(MachineHostTest, CommandsTheStateMachineRefusesAreBadInvalidState) {
  serve("engineer");
  thread.start();
  EXPECT_EQ(execute(PackMLCommand::Unhold), ua::status::BadInvalidState);  // Stopped: nothing held
  EXPECT_EQ(execute(PackMLCommand::Start), ua::status::BadInvalidState);   // Start needs Idle
  EXPECT_EQ(call("PackML.BaseStateMachine", PackMLCommand::Clear), ua::status::BadInvalidState);
  EXPECT_EQ(state(), static_cast<std::int32_t>(PackMLState::Stopped));
  auto states = watch("PackML.Status.StateCurrent");
  EXPECT_EQ(call("PackML.BaseStateMachine", PackMLCommand::Abort), ua::StatusCode{});
  ASSERT_TRUE(state_is(*states, PackMLState::Aborted));
  EXPECT_EQ(execute(PackMLCommand::Reset), ua::status::BadInvalidState);
  EXPECT_EQ(call("PackML.BaseStateMachine", PackMLCommand::Clear), ua::StatusCode{});
  EXPECT_TRUE(state_is(*states, PackMLState::Stopped));
}

TEST_F(MachineHostTest, ViewersMayReadButNotCommand) {
  serve("viewer");
  thread.start();
  EXPECT_EQ(execute(PackMLCommand::Reset), ua::status::BadUserAccessDenied);
  EXPECT_EQ(call("PackML.BaseStateMachine", PackMLCommand::Abort), ua::status::BadUserAccessDenied);
  EXPECT_EQ(controller_state(), PackMLState::Stopped);
  EXPECT_EQ(state(), static_cast<std::int32_t>(PackMLState::Stopped));
}

TEST_F(MachineHostTest, TagQualityReachesClientsAsStatusCodeWithTheReason) {
  serve("viewer");
  thread.start();
  thread.post([](MachineController& m) {
    static_cast<PackMLMachine&>(m).set_tag("sensor.temperature", 23.0, Tag::Quality::bad, "PLC unreachable");
  });
  auto temperature = watch("Tags.sensor.temperature");
  ASSERT_TRUE(last_is(*temperature, [](const ua::DataValue& v) { return v.status.is_bad(); }));
  const ua::DataValue v = temperature->values().back();
  EXPECT_EQ(v.status, ua::status::BadNoCommunication);
  EXPECT_EQ(v.value, ua::Variant(23.0));  // the last value stays readable
  EXPECT_EQ(*read("Tags.sensor.temperature.Reason").value.get_if<ua::String>(), "PLC unreachable");
}

TEST_F(MachineHostTest, ACommandTheControllerThreadDoesNotTakeInTimeTimesOutAndNeverRuns) {
  MachineHostOptions options;
  options.command_timeout = 200ms;
  serve("operator", options);
  thread.start();
  std::promise<void> release;
  thread.post([busy = release.get_future().share()](MachineController&) { busy.wait(); });  // a stuck turn
  EXPECT_EQ(execute(PackMLCommand::Reset), ua::status::BadTimeout);
  release.set_value();  // the controller thread comes back: the late Reset is dropped
  EXPECT_EQ(controller_state(), PackMLState::Stopped);
  // A host that is gone answers at once.
  const auto object = host->node(kExecuteState);
  const auto reset = host->node(fmt::format("{}.Reset", kExecuteState));
  host.reset();
  auto out = client->call_method(object, reset, {});
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(ua::status_of(out.error()), ua::status::BadShutdown);
}

TEST(ServeMachine, ServesUntilStoppedAndRefusesABadNodeset) {
  PackMLMachine machine(SteadyClock::instance());
  MachineServerConfig config;
  config.server.transport.host = "127.0.0.1";
  config.server.transport.port = 0;
  config.server.advertised_host = "127.0.0.1";
  config.thread = thread_options();
  std::stop_source stop;
  std::promise<std::string> url;
  Status served;
  std::thread process([&] {
    served = serve_machine(
        machine, config, SteadyClock::instance(), stop.get_token(),
        [&](const ua::server::Server& s, ControllerThread&) { url.set_value(s.endpoint_url()); });
  });
  ua::ClientConfig cc;
  cc.endpoint_url = url.get_future().get();
  cc.auto_reconnect = false;
  ua::SyncClient client(cc);
  ASSERT_TRUE(client.connect().ok());
  const auto ns = client.namespace_index(kMachineNamespace);
  ASSERT_TRUE(ns.ok());
  auto state = client.read_value(ua::NodeId(*ns, ua::String("ScaraRobot1.PackML.Status.StateCurrent")));
  ASSERT_TRUE(state.ok());
  EXPECT_EQ(state->value, ua::Variant(static_cast<std::int32_t>(PackMLState::Stopped)));
  client.disconnect();
  stop.request_stop();
  process.join();
  EXPECT_TRUE(served.ok());

  config.nodesets = {"/nonexistent/candy.xml"};
  const Status refused = serve_machine(machine, config, SteadyClock::instance(), std::stop_token{});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("/nonexistent/candy.xml"), std::string::npos)
      << refused.error().message;
}

TEST(ModelServerHistory, TheServerKeepsThePackMLStatesForHistoryRead) {
  // A controller process's server (settings_server): a cloud that was away reads back the states
  // it missed (OPC 10000-11 §6.4.3).
  sf::testing::TempDir dir;
  PackMLMachine machine{SteadyClock::instance()};
  ControllerThread thread{machine, SteadyClock::instance(), thread_options()};
  ControllerSettings settings;
  settings.machine = "scara-robot-1";
  settings.opcua_port = 0;
  settings.opcua_security.pki = (dir.path() / "pki").string();
  settings.opcua_security.modes = "none";
  settings.opcua_security.anonymous = "operator";
  auto model = ModelServer::start(settings, thread, machine.identification(), SteadyClock::instance());
  ASSERT_TRUE(model.ok()) << model.error().describe();
  thread.start();
  ua::ClientConfig cc;
  cc.endpoint_url = (*model)->endpoint();
  cc.auto_reconnect = false;
  ua::SyncClient client(cc);
  ASSERT_TRUE(client.connect().ok());
  const auto ns = client.namespace_index(kMachineNamespace);
  ASSERT_TRUE(ns.ok());
  const auto node = [&](std::string_view path) {
    return ua::NodeId(*ns, ua::String(fmt::format("ScaraRobot1.{}", path)));
  };
  const auto state_now = [&] {
    auto v = client.read_value(node("PackML.Status.StateCurrent"));
    const auto* s = v.ok() ? v->value.get_if<std::int32_t>() : nullptr;
    return s != nullptr ? static_cast<PackMLState>(*s) : PackMLState::Undefined;
  };
  const auto run = [&](PackMLCommand command, PackMLState until) {
    const auto object = node(kExecuteState);
    ASSERT_TRUE(
        client.call_method(object, node(fmt::format("{}.{}", kExecuteState, to_string(command))), {}).ok());
    for (int i = 0; i < 500 && state_now() != until; ++i) {
      std::this_thread::sleep_for(10ms);
    }
    ASSERT_EQ(state_now(), until);
  };
  run(PackMLCommand::Reset, PackMLState::Idle);
  run(PackMLCommand::Start, PackMLState::Execute);

  ua::HistoryRawParams params;
  params.start = ua::DateTime::from_unix_seconds(0);
  params.end = ua::DateTime::from_system_clock(std::chrono::system_clock::now() + 1s);
  auto history = client.history_read_raw(node("PackML.Status.StateCurrent"), params);
  ASSERT_TRUE(history.ok()) << history.error().describe();
  std::vector<std::int32_t> states;
  for (const ua::DataValue& v : *history) {
    if (const auto* s = v.value.get_if<std::int32_t>()) {
      states.push_back(*s);
    }
  }
  // Stopped, then Idle, then Execute, in that order (the transient states between as published).
  const std::vector<PackMLState> wanted{PackMLState::Stopped, PackMLState::Idle, PackMLState::Execute};
  auto at = states.begin();
  for (PackMLState w : wanted) {
    at = std::find(at, states.end(), static_cast<std::int32_t>(w));
    ASSERT_NE(at, states.end()) << to_string(w) << " missing in " << ::testing::PrintToString(states);
  }
  EXPECT_EQ(states.back(), static_cast<std::int32_t>(PackMLState::Execute));
}

}  // namespace
}  // namespace sf::factory
