// The fixed part of a machine's OPC UA model (machine_model.hpp) as tables: its objects, the
// variables the controller's status fills and the PackML methods. MachineModel builds the nodes
// from them, StatusPublisher names its values after them; one place says what the model holds.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "sf/factory/packml.hpp"
#include "sf/opcua/node_ids.hpp"

namespace sf::factory::model {

namespace ua_id = opcua::id;

// An object below the machine: its path, its stand-in type (in the machine namespace; "" =
// FolderType) and the reference from its parent.
struct ObjectRow {
  std::string_view path;
  std::string_view type;
  std::uint32_t reference = ua_id::HasComponent;
};

inline constexpr std::array kObjects{
    ObjectRow{"Identification", "MachineIdentificationType", ua_id::HasAddIn},  // OPC 40001-1 §8.4
    ObjectRow{"PackML", "PackMLBaseObjectType"},                                // OPC 30050 §6.3.2
    ObjectRow{"PackML.Status", "PackMLStatusObjectType"},                       // §6.3.3
    ObjectRow{"PackML.Admin", "PackMLAdminObjectType"},                         // §6.3.4
    ObjectRow{"PackML.Admin.StopReason", "PackMLStopReasonType"},
    ObjectRow{"PackML.BaseStateMachine", "PackMLBaseStateMachineType"},                  // §6.3.6
    ObjectRow{"PackML.BaseStateMachine.MachineState", "PackMLMachineStateMachineType"},  // §6.3.7
    ObjectRow{"PackML.BaseStateMachine.MachineState.ExecuteState",
              "PackMLExecuteStateMachineType"},  // §6.3.8
    ObjectRow{"Job", "MachineJobType"},
    ObjectRow{"Tags", ""},
};

// A data variable of the status: its path, DataType and whether it is an array (the Duration
// array of StateCumulativeTime is indexed by the OPC 30050 state number).
struct VariableRow {
  std::string_view path;
  std::uint32_t data_type;
  bool array = false;
};

inline constexpr std::array kVariables{
    VariableRow{"PackML.Status.StateCurrent", ua_id::Int32},
    VariableRow{"PackML.Status.UnitModeCurrent", ua_id::Int32},
    VariableRow{"PackML.Admin.ProdProcessedCount", ua_id::Int32},
    VariableRow{"PackML.Admin.ProdDefectiveCount", ua_id::Int32},
    VariableRow{"PackML.Admin.StateCurrentTime", ua_id::Duration},
    VariableRow{"PackML.Admin.StateCumulativeTime", ua_id::Duration, true},
    VariableRow{"PackML.Admin.StopReason.ID", ua_id::Int32},
    VariableRow{"PackML.Admin.StopReason.Message", ua_id::String},
    VariableRow{"PackML.Admin.StopReason.DateTime", ua_id::UtcTime},
    VariableRow{"PackML.BaseStateMachine.CurrentState", ua_id::LocalizedText},
    VariableRow{"PackML.BaseStateMachine.MachineState.CurrentState", ua_id::LocalizedText},
    VariableRow{"PackML.BaseStateMachine.MachineState.ExecuteState.CurrentState", ua_id::LocalizedText},
    VariableRow{"Job.JobId", ua_id::String},
    VariableRow{"Job.Operation", ua_id::String},
    VariableRow{"Job.Parameters", ua_id::String},
    VariableRow{"Job.Queued", ua_id::UInt32},
    VariableRow{"Job.WorkingTime", ua_id::Duration},
    VariableRow{"Fault", ua_id::String},
};

// The PackML commands as methods without arguments, on the state machine that OPC 30050 §6.7
// gives each of them.
struct MethodRow {
  std::string_view object;
  PackMLCommand command;
};

inline constexpr std::string_view kBaseStateMachine = "PackML.BaseStateMachine";
inline constexpr std::string_view kMachineState = "PackML.BaseStateMachine.MachineState";
inline constexpr std::string_view kExecuteState = "PackML.BaseStateMachine.MachineState.ExecuteState";

inline constexpr std::array kMethods{
    MethodRow{kBaseStateMachine, PackMLCommand::Abort}, MethodRow{kBaseStateMachine, PackMLCommand::Clear},
    MethodRow{kMachineState, PackMLCommand::Stop},      MethodRow{kExecuteState, PackMLCommand::Reset},
    MethodRow{kExecuteState, PackMLCommand::Start},     MethodRow{kExecuteState, PackMLCommand::Hold},
    MethodRow{kExecuteState, PackMLCommand::Unhold},    MethodRow{kExecuteState, PackMLCommand::Suspend},
    MethodRow{kExecuteState, PackMLCommand::Unsuspend},
};

// The current states of the three nested machines for a unit state (OPC 30050 §6.3.6-8): the
// base machine is Aborting, Aborted or Cleared; inside Cleared the machine state is Stopped,
// Stopping, Clearing or Running; inside Running the execute state is the unit state. A machine
// whose parent state is not active has no current state ("").
struct NestedStates {
  std::string_view base;
  std::string_view machine;
  std::string_view execute;
};
NestedStates nested_states(PackMLState state);

}  // namespace sf::factory::model
