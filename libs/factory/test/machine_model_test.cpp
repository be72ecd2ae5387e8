// The OPC UA model of a controller in an address space, without a server: where the machine
// object is (the ontology's individual when its NodeSet2 is loaded), the identification and
// PackML nodes, and how the controller's status becomes values, changes only, with tag quality
// as StatusCode.
#include "sf/factory/machine_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "sf/factory/testing/packml_machine.hpp"
#include "sf/knowledge/nodeset.hpp"
#include "sf/knowledge/rdf_io.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::factory {
namespace {

namespace ua = sf::opcua;
namespace srv = sf::opcua::server;
using testing::PackMLMachine;

// The NodeSet2 `kb to-nodeset` makes of the candy-factory ontology and the prototype line.
std::string ontology_nodeset() {
  knowledge::Dictionary dict;
  std::vector<knowledge::Triple> triples;
  for (const char* file : {"ontology/candy-factory.ttl", "ontology/prototype-line.ttl"}) {
    auto doc = knowledge::read_rdf_file(dict, std::string(SF_SOURCE_DIR) + "/" + file);
    EXPECT_TRUE(doc.ok()) << doc.error().describe();
    if (doc) {
      triples.insert(triples.end(), doc->triples.begin(), doc->triples.end());
    }
  }
  auto model = knowledge::extract_ontology(dict, triples);
  EXPECT_TRUE(model.ok());
  std::ostringstream out;
  EXPECT_TRUE(model.ok() && knowledge::write_nodeset(out, dict, *model).ok());
  return out.str();
}

class MachineModelTest : public ::testing::Test {
 protected:
  MachineModelTest() { EXPECT_TRUE(srv::build_namespace0(space).ok()); }

  MachineModel build(const Identification& id = PackMLMachine::default_identification()) {
    auto m = MachineModel::create(space, id, [this](PackMLCommand c) {
      commands.push_back(c);
      return ua::StatusCode{};
    });
    EXPECT_TRUE(m.ok()) << m.error().describe();
    return std::move(*m);
  }
  ua::DataValue value(const MachineModel& m, std::string_view path) {
    auto v = space.value(m.node(path));
    EXPECT_TRUE(v.ok()) << path;
    return v.ok() ? *v : ua::DataValue{};
  }
  const ua::NodeId* type_of(const ua::NodeId& node) { return space.type_definition(node); }
  bool organizes(const ua::NodeId& folder, const ua::NodeId& target) {
    const auto& refs = space.find(folder)->references;
    return std::any_of(refs.begin(), refs.end(), [&](const srv::Reference& r) {
      return r.is_forward && r.target_id == target && r.reference_type_id == ua::NodeId(0, ua::id::Organizes);
    });
  }

  srv::AddressSpace space;
  ManualClock clock;
  std::vector<PackMLCommand> commands;
};

TEST_F(MachineModelTest, TheTreeHasIdentificationPackMLJobAndTags) {
  const MachineModel m = build();
  EXPECT_EQ(m.name(), "ScaraRobot1");
  const auto ns = *space.namespace_index(kMachineNamespace);
  const ua::NodeId machines(ns, ua::String("Machines"));
  EXPECT_TRUE(organizes(ua::NodeId(0, ua::id::ObjectsFolder), machines));
  EXPECT_TRUE(organizes(machines, m.machine()));
  EXPECT_EQ(m.machine(), ua::NodeId(ns, ua::String("ScaraRobot1")));
  for (const char* path :
       {"Identification", "PackML", "PackML.Status", "PackML.Admin", "PackML.Admin.StopReason",
        "PackML.BaseStateMachine", "PackML.BaseStateMachine.MachineState",
        "PackML.BaseStateMachine.MachineState.ExecuteState", "Job", "Tags"}) {
    EXPECT_NE(space.find(m.node(path)), nullptr) << path;
  }
  // OPC 40001-1: Identification is an AddIn of the machine.
  EXPECT_EQ(space.child(m.machine(), ua::QualifiedName(ns, "Identification"))->node_id,
            m.node("Identification"));
  EXPECT_EQ(*type_of(m.node("PackML.Status")), ua::NodeId(ns, ua::String("PackMLStatusObjectType")));
  EXPECT_EQ(value(m, "Identification.Manufacturer").value.get_if<ua::LocalizedText>()->text, "smartfactory");
  EXPECT_EQ(value(m, "Identification.Model").value.get_if<ua::LocalizedText>()->text, "SCARA Robot 1");
  EXPECT_EQ(*value(m, "Identification.SerialNumber").value.get_if<ua::String>(), "SR1-0001");
  EXPECT_EQ(*value(m, "Identification.DeviceClass").value.get_if<ua::String>(), "smart-robot");
  // Until the controller publishes, the status reads as waiting.
  EXPECT_EQ(value(m, "PackML.Status.StateCurrent").status, ua::status::BadWaitingForInitialData);
  // The PackML commands, each on the state machine OPC 30050 §6.7 puts it on.
  for (const char* path : {"PackML.BaseStateMachine.Abort", "PackML.BaseStateMachine.Clear",
                           "PackML.BaseStateMachine.MachineState.Stop",
                           "PackML.BaseStateMachine.MachineState.ExecuteState.Hold"}) {
    const srv::Node* n = space.find(m.node(path));
    ASSERT_NE(n, nullptr) << path;
    EXPECT_EQ(n->node_class(), ua::NodeClass::Method) << path;
  }
}

TEST_F(MachineModelTest, TheMachineIsTheOntologysIndividualWhenItsNodesetIsLoaded) {
  auto imported = srv::import_nodeset(space, ontology_nodeset());
  ASSERT_TRUE(imported.ok()) << imported.error().describe();
  const auto onto = *space.namespace_index(kOntologyNamespace);
  const MachineModel m = build();
  // The individual itself: the ontology's namespace, its class as type, its place in the line.
  EXPECT_EQ(m.machine().namespace_index, onto);
  EXPECT_EQ(space.find(m.machine())->browse_name, ua::QualifiedName(onto, "ScaraRobot1"));
  EXPECT_EQ(space.find(*type_of(m.machine()))->browse_name, ua::QualifiedName(onto, "ScaraRobot"));
  EXPECT_NE(space.child(m.machine(), ua::QualifiedName(onto, "manufacturer")), nullptr);
  const auto ns = *space.namespace_index(kMachineNamespace);
  EXPECT_TRUE(organizes(ua::NodeId(ns, ua::String("Machines")), m.machine()));
  EXPECT_NE(space.child(m.machine(), ua::QualifiedName(ns, "PackML")), nullptr);

  // A machine the line does not have: made here, typed by the ontology's class of its kind.
  const MachineModel spare = build({"spare-conveyor", "conveyor", "Siemens", "S7-1200", "9"});
  EXPECT_EQ(spare.machine(), ua::NodeId(ns, ua::String("SpareConveyor")));
  EXPECT_EQ(space.find(*type_of(spare.machine()))->browse_name, ua::QualifiedName(onto, "Conveyor"));
  // Two models of one machine do not fit in one address space.
  EXPECT_FALSE(MachineModel::create(space, PackMLMachine::default_identification(), {}).ok());
}

TEST_F(MachineModelTest, StatusBecomesValuesAndOnlyChangesArePublished) {
  MachineModel m = build();
  PackMLMachine machine(clock);
  StatusPublisher publisher(std::chrono::milliseconds(1000));
  auto first = publisher.changes(machine.status(), clock.utc_now());
  EXPECT_EQ(first.size(), 18U + 2 * 3U);  // every variable, every tag and its reason
  m.apply(space, first);
  EXPECT_EQ(*value(m, "PackML.Status.StateCurrent").value.get_if<std::int32_t>(), 2);  // Stopped
  EXPECT_EQ(
      value(m, "PackML.BaseStateMachine.MachineState.CurrentState").value.get_if<ua::LocalizedText>()->text,
      "Stopped");
  EXPECT_EQ(*value(m, "Tags.sensor.temperature").value.get_if<double>(), 21.5);
  // A tag with a unit has its EngineeringUnits (OPC 10000-8 §5.6.3), one without has none.
  const ua::DataValue eu = value(m, "Tags.sensor.temperature.EngineeringUnits");
  const auto* units = eu.value.get_if<ua::ExtensionObject>();
  ASSERT_NE(units, nullptr);
  ASSERT_NE(units->get_if<ua::EUInformation>(), nullptr);
  EXPECT_EQ(units->get_if<ua::EUInformation>()->display_name.text, "°C");
  EXPECT_EQ(units->get_if<ua::EUInformation>()->unit_id, 4408652);  // CEL, as UNECE Rec 20 lists it
  EXPECT_FALSE(space.contains(m.node("Tags.plc.jobs_done.EngineeringUnits")));
  EXPECT_TRUE(publisher.changes(machine.status(), clock.utc_now()).empty());

  // Reset: the state and the nested machines' states change, nothing else (durations are
  // published in whole seconds).
  ASSERT_TRUE(machine.command(PackMLCommand::Reset).ok());
  clock.advance(std::chrono::milliseconds(300));
  auto reset = publisher.changes(machine.status(), clock.utc_now());
  std::vector<std::string> names(reset.size());
  std::transform(reset.begin(), reset.end(), names.begin(), [](const ModelValue& v) { return v.name; });
  EXPECT_EQ(names, (std::vector<std::string>{
                       "PackML.Status.StateCurrent", "PackML.BaseStateMachine.MachineState.CurrentState",
                       "PackML.BaseStateMachine.MachineState.ExecuteState.CurrentState"}));
  m.apply(space, reset);
  EXPECT_EQ(value(m, "PackML.BaseStateMachine.MachineState.ExecuteState.CurrentState")
                .value.get_if<ua::LocalizedText>()
                ->text,
            "Resetting");
  clock.advance(std::chrono::milliseconds(800));
  auto later = publisher.changes(machine.status(), clock.utc_now());
  ASSERT_EQ(later.size(), 2U);  // 1.1 s in Resetting: the current and cumulative times
  m.apply(space, later);
  EXPECT_EQ(*value(m, "PackML.Admin.StateCurrentTime").value.get_if<double>(), 1000.0);
  EXPECT_EQ(value(m, "PackML.Admin.StateCumulativeTime").value.array_if<double>()->at(15), 1000.0);
}

TEST_F(MachineModelTest, TagQualityIsTheStatusCodeAndTheReasonIsShown) {
  MachineModel m = build();
  PackMLMachine machine(clock);
  StatusPublisher publisher;
  m.apply(space, publisher.changes(machine.status(), clock.utc_now()));
  machine.set_tag("sensor.temperature", 22.0, Tag::Quality::uncertain, "stale: no answer for 60 ms");
  machine.set_tag("plc.exit_eye", true, Tag::Quality::bad, "PLC unreachable: connection refused");
  m.apply(space, publisher.changes(machine.status(), clock.utc_now()));
  const auto temperature = value(m, "Tags.sensor.temperature");
  EXPECT_EQ(temperature.status, ua::status::UncertainLastUsableValue);
  EXPECT_EQ(*temperature.value.get_if<double>(), 22.0);
  EXPECT_EQ(*value(m, "Tags.sensor.temperature.Reason").value.get_if<ua::String>(),
            "stale: no answer for 60 ms");
  const auto eye = value(m, "Tags.plc.exit_eye");
  EXPECT_EQ(eye.status, ua::status::BadNoCommunication);
  EXPECT_EQ(space.find_as<srv::VariableNode>(m.node("Tags.plc.exit_eye"))->data_type,
            ua::NodeId(0, ua::id::Boolean));
  EXPECT_EQ(*value(m, "Tags.plc.exit_eye.Reason").value.get_if<ua::String>(),
            "PLC unreachable: connection refused");

  // Good again: Good, the reason empty; a tag that goes away is removed from the model.
  machine.set_tag("sensor.temperature", 22.5);
  machine.remove_tag("plc.exit_eye");
  m.apply(space, publisher.changes(machine.status(), clock.utc_now()));
  EXPECT_TRUE(value(m, "Tags.sensor.temperature").status.is_good());
  EXPECT_EQ(*value(m, "Tags.sensor.temperature.Reason").value.get_if<ua::String>(), "");
  EXPECT_EQ(space.find(m.node("Tags.plc.exit_eye")), nullptr);
  EXPECT_EQ(space.find(m.node("Tags.plc.exit_eye.Reason")), nullptr);
}

TEST_F(MachineModelTest, JobFaultAndStopReasonAreShown) {
  MachineModel m = build();
  PackMLMachine machine(clock);
  StatusPublisher publisher;
  for (auto c : {PackMLCommand::Reset, PackMLCommand::Start}) {
    ASSERT_TRUE(machine.command(c).ok());
    machine.poll(clock.now());
  }
  ASSERT_TRUE(machine.submit("job-7", {"load", {{"candy", 3}, {"count", 2}}}).ok());
  m.apply(space, publisher.changes(machine.status(), clock.utc_now()));
  EXPECT_EQ(*value(m, "Job.JobId").value.get_if<ua::String>(), "job-7");
  EXPECT_EQ(*value(m, "Job.Operation").value.get_if<ua::String>(), "load");
  EXPECT_EQ(*value(m, "Job.Parameters").value.get_if<ua::String>(), "candy=3, count=2");
  machine.fail(7, "axis 2 following error");
  m.apply(space, publisher.changes(machine.status(), clock.utc_now()));
  EXPECT_EQ(*value(m, "PackML.Status.StateCurrent").value.get_if<std::int32_t>(), 8);  // Aborting
  EXPECT_EQ(value(m, "PackML.BaseStateMachine.CurrentState").value.get_if<ua::LocalizedText>()->text,
            "Aborting");
  EXPECT_EQ(
      value(m, "PackML.BaseStateMachine.MachineState.CurrentState").value.get_if<ua::LocalizedText>()->text,
      "");
  EXPECT_EQ(*value(m, "PackML.Admin.StopReason.ID").value.get_if<std::int32_t>(), 7);
  EXPECT_EQ(*value(m, "PackML.Admin.StopReason.Message").value.get_if<ua::String>(),
            "axis 2 following error");
  EXPECT_EQ(*value(m, "Fault").value.get_if<ua::String>(), "axis 2 following error");
  EXPECT_EQ(value(m, "PackML.Admin.StopReason.DateTime").value.get_if<ua::DateTime>()->to_system_clock(),
            std::chrono::time_point_cast<std::chrono::system_clock::duration>(clock.utc_now()));
}

}  // namespace
}  // namespace sf::factory
