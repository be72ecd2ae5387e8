// MachineHost: a controller's OPC UA model (machine_model.hpp) on a server, fed from the
// controller's ControllerThread (controller_thread.hpp); serve_machine: server, controller
// thread and model in one call, for the `machine` and `gateway` processes.
//
// Concurrency contract:
// - The controller is driven by its ControllerThread alone: polls on its deadlines, calls other
//   threads post (run after the next poll), a status snapshot refreshed every status_interval.
// - The model lives on the server's loop thread. A timer there (publish_interval) copies the
//   thread's latest snapshot (ControllerThread::status(): a copy under the snapshot's mutex, so
//   the controller's cycle never waits for the server or its clients) and writes only the values
//   that changed (StatusPublisher): subscribers get one notification per change.
// - An operator's method call arrives on the loop thread. The PackML command is posted to the
//   controller thread and the loop thread waits for its answer, at most command_timeout (about
//   one cycle normally); after that it answers BadTimeout and the command is dropped unless the
//   controller thread has already started it (then its answer is awaited: command() does not
//   block). The controller thread never waits for the loop thread.
// - attach() waits for the loop thread once, to build the model. The host must be destroyed
//   before its ControllerThread; then publishing stops and the methods answer BadShutdown. The
//   server may stop before or after the host.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/factory/controller_thread.hpp"
#include "sf/factory/machine.hpp"
#include "sf/factory/machine_model.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::factory {

struct MachineHostOptions {
  MachineModelOptions model;
  // How often the loop thread looks at the controller thread's snapshot.
  std::chrono::milliseconds publish_interval{10};
  // How long an operator's method call waits for the controller thread.
  std::chrono::milliseconds command_timeout{5000};
  // StatusPublisher's resolution of the Admin durations.
  std::chrono::milliseconds time_resolution{1000};
};

class MachineHost {
 public:
  // Builds the model of the controller `thread` drives (its `identification`) in `server` and
  // starts publishing; the thread may be started before or after.
  static Result<std::unique_ptr<MachineHost>> attach(opcua::server::Server& server, ControllerThread& thread,
                                                     const Identification& identification,
                                                     MachineHostOptions options = {});
  ~MachineHost();
  MachineHost(const MachineHost&) = delete;
  MachineHost& operator=(const MachineHost&) = delete;

  [[nodiscard]] const opcua::NodeId& machine() const { return machine_; }
  // MachineModel::node: the NodeId of a node of the model by its path.
  [[nodiscard]] opcua::NodeId node(std::string_view path) const;

  struct Shared;

 private:
  explicit MachineHost(std::shared_ptr<Shared> shared) : shared_(std::move(shared)) {}

  std::shared_ptr<Shared> shared_;
  opcua::NodeId machine_;
};

// What a `machine` or `gateway` process needs to serve its controller: the server (endpoint,
// security), the NodeSet2 files to import first (the ontology's, from `kb to-nodeset`, so the
// machine object is its individual), the controller thread's and the host's options.
struct MachineServerConfig {
  opcua::server::ServerConfig server;
  std::vector<std::string> nodesets;
  ControllerThreadOptions thread;
  MachineHostOptions host;
};

// The one call for such a process: imports the nodesets, attaches the model, starts the server
// and the controller's thread, and serves until `stop` is requested; then stops the thread and
// the server. `started` (may be empty) gets the running server and thread first, e.g. to print
// the endpoint URL or to give the thread to the negotiation agent (a RemoteController). Errors:
// a nodeset that does not import, a port that does not bind, a model that cannot be built.
Status serve_machine(
    MachineController& controller, const MachineServerConfig& config, Clock& clock,
    const std::stop_token& stop,
    const std::function<void(const opcua::server::Server&, ControllerThread&)>& started = {});

}  // namespace sf::factory
