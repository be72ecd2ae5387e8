// The OPC UA model of a shop-floor controller (paper §VII: every controller publishes its
// machine on its own OPC UA server). Any MachineController gets the same model:
//
//   Objects
//   └─ Machines                              Folder (OPC 40001-1 §10: where machines are found)
//      └─ ScaraRobot1                        the ontology's individual (kb to-nodeset) when loaded
//         ├─ Identification                  HasAddIn, MachineIdentificationType (OPC 40001-1 §8)
//         │    Manufacturer, Model, SerialNumber, ProductInstanceUri, DeviceClass, ComponentName
//         ├─ PackML                          PackMLBaseObjectType (OPC 30050 §6.3.2)
//         │  ├─ Status                       StateCurrent, UnitModeCurrent (§6.3.3, PackTags)
//         │  ├─ Admin                        ProdProcessedCount, ProdDefectiveCount,
//         │  │  │                            StateCurrentTime, StateCumulativeTime (§6.3.4)
//         │  │  └─ StopReason                ID, Message, DateTime
//         │  └─ BaseStateMachine             CurrentState; Abort(), Clear() (§6.3.6, §6.7.5-6)
//         │     └─ MachineState              CurrentState; Stop() (§6.3.7, §6.7.7)
//         │        └─ ExecuteState           CurrentState; Reset(), Start(), Hold(), Unhold(),
//         │                                  Suspend(), Unsuspend() (§6.3.8, §6.7.8-14)
//         ├─ Job                             JobId, Operation, Parameters, Queued
//         ├─ Fault
//         └─ Tags                            one variable per controller tag, with its Reason
//
// The machine object is named after the layout's machine in the ontology (line::iri_name:
// "scara-robot-1" → ScaraRobot1), so the ontology, the OPC UA model and the cloud's series use
// one name. When the ontology's NodeSet2 is in the address space the machine object is the
// individual itself (its type, properties and place in the line stay); without it the object is
// made here, typed by the ontology's class for the machine's kind if that exists. Everything
// else is in the namespace kMachineNamespace with string NodeIds "<Machine>.<path>", e.g.
// "ScaraRobot1.PackML.Status.StateCurrent", "ScaraRobot1.Tags.axis1.position".
//
// The stand-in ObjectTypes carry the companion specifications' names (PackMLStatusObjectType,
// MachineIdentificationType, ...) in kMachineNamespace: the Machinery and PackML NodeSets are not
// loaded, so only names and layout follow them. Numbers follow PackTags where OPC 30050 uses
// structures (counts are Int32, StopReason an object instead of a PackMLAlarmDataType).
//
// A tag with a unit (Tag::unit) gets the EngineeringUnits property (OPC 10000-8 §5.6.3,
// "ScaraRobot1.Tags.axis1.position.EngineeringUnits"): values are SI (radians, metres) or °C.
//
// Tag quality (Tag::quality) becomes the variable's StatusCode: uncertain →
// UncertainLastUsableValue, bad → BadNoCommunication, both with the value kept; Tag::reason is
// the tag's Reason property (empty when good).
//
// Threads: MachineModel and StatusPublisher are used by one thread, the server's loop thread
// (inside Server::with_address_space or a loop timer); the methods call the CommandHandler there
// too. MachineHost (machine_host.hpp) connects them to the controller's own thread.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/factory/machine.hpp"
#include "sf/opcua/server/address_space.hpp"

namespace sf::factory {

inline constexpr std::string_view kMachineNamespace = "urn:smartfactory:machines";
// The namespace `kb to-nodeset` gives the candy-factory ontology (its owl:Ontology IRI).
inline constexpr std::string_view kOntologyNamespace = "http://smartfactory.example/ontology/candy";

struct MachineModelOptions {
  std::string namespace_uri = std::string(kMachineNamespace);
  // Where the machine's individual and class are looked up; empty: never.
  std::string ontology_namespace = std::string(kOntologyNamespace);
};

// A value of the model as the controller's thread computes it. fixed: a node of the tree above,
// by its path below the machine ("PackML.Status.StateCurrent"); tag / tag_reason: a controller
// tag by name, and its Reason.
struct ModelValue {
  enum class Kind : std::uint8_t { fixed, tag, tag_reason };
  Kind kind = Kind::fixed;
  std::string name;
  opcua::DataValue value;
  std::string unit{};  // tag: Tag::unit, given to the variable when it is made
};

// OPC 10000-4 §7.39 codes of Tag::quality (Good, UncertainLastUsableValue, BadNoCommunication).
opcua::StatusCode status_of(Tag::Quality quality);

// A PackML command of an operator, answered with the method's result: Good, BadInvalidState
// when the state machine refuses it (Errc::state), BadTimeout or BadShutdown when the
// controller did not take it.
using CommandHandler = std::function<opcua::StatusCode(PackMLCommand)>;

// The Object below a machine whose method a PackML command is, as a browse path relative to the
// machine ("PackML/BaseStateMachine/MachineState/ExecuteState" for Start; OPC 30050 §6.3.6-8):
// what a client calls through the model.
std::string method_object_path(PackMLCommand command);
// "Start" → PackMLCommand::Start; nullopt for a name that is no command.
std::optional<PackMLCommand> packml_command(std::string_view name);

class MachineModel {
 public:
  // Builds the machine's nodes (and, once per address space, the Machines folder and the
  // stand-in types). Errors: a node that cannot be added (e.g. a second model of the same name).
  static Result<MachineModel> create(opcua::server::AddressSpace& space, const Identification& identification,
                                     const CommandHandler& commands, const MachineModelOptions& options = {});

  // Writes the values (StatusPublisher::changes) to their nodes; a tag seen for the first time
  // gets its variable (typed by its value), a tag gone is deleted.
  void apply(opcua::server::AddressSpace& space, const std::vector<ModelValue>& values);

  [[nodiscard]] const opcua::NodeId& machine() const { return machine_; }
  // The NodeId of a node of the tree by its path ("PackML.Status.StateCurrent"), of a tag
  // ("Tags.axis1.position") or of a tag's reason ("Tags.axis1.position.Reason").
  [[nodiscard]] opcua::NodeId node(std::string_view path) const;
  [[nodiscard]] std::uint16_t namespace_index() const { return ns_; }
  // The object's browse name: line::iri_name of the layout's name.
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  MachineModel(std::uint16_t ns, std::string name, opcua::NodeId machine)
      : ns_(ns), name_(std::move(name)), machine_(std::move(machine)) {}
  Status add_tag(opcua::server::AddressSpace& space, const ModelValue& value);
  void remove_tag(opcua::server::AddressSpace& space, const std::string& tag);

  std::uint16_t ns_ = 0;
  std::string name_;
  opcua::NodeId machine_;
  std::map<std::string, opcua::BuiltinType, std::less<>> tags_;  // the tag variables made, by type
};

// ControllerStatus as ModelValues, keeping what was published last so that only changes are
// written to the address space (and subscribers see exactly those).
class StatusPublisher {
 public:
  // Durations (StateCurrentTime, StateCumulativeTime) are published in whole `time_resolution`
  // steps, so a machine that only runs changes them once per step.
  explicit StatusPublisher(std::chrono::milliseconds time_resolution = std::chrono::seconds(1))
      : resolution_(time_resolution) {}

  // Every value of the model for `status` that differs (value or StatusCode) from the last
  // call, everything on the first call; tags that vanished come as tag values with a null
  // Variant and BadNotFound. Source timestamps are `utc`.
  std::vector<ModelValue> changes(const ControllerStatus& status, Clock::utc_time utc);

 private:
  std::vector<ModelValue> values(const ControllerStatus& status, Clock::utc_time utc);

  std::chrono::milliseconds resolution_;
  std::map<std::pair<ModelValue::Kind, std::string>, opcua::DataValue> last_;
};

}  // namespace sf::factory
