// MachineHost: one MachineController served on an OPC UA server (machine_model.hpp), the bridge
// between the controller's thread and the server's loop thread.
//
// Concurrency contract:
// - The controller thread is the one that calls step() (or run(), which calls step()). It is the
//   only thread that touches the controller: poll(), command(), status(), and the tasks given
//   to post(). A process whose loop also drives other work (the negotiation agent) calls step()
//   from that loop and hands set_wake() a way to wake it.
// - The server's loop thread owns the address space. After each step that polled or ran tasks,
//   the controller thread computes what changed (StatusPublisher) and hands only that to the
//   loop with Server::post, which never blocks: a 1 kHz cycle is not held up by OPC UA clients.
//   Subscribers get one notification per change.
// - An operator's method call (Start, Hold, ...) arrives on the loop thread. It is queued for
//   the controller thread, which wakes, runs controller.command() and answers; the loop thread
//   waits for that answer (at most command_timeout, then BadTimeout and the command is
//   dropped unless it already started). So the controller thread must never wait for the
//   server's loop thread while the host runs (no Server::with_address_space, no blocking
//   client calls to this server from it).
// - attach() waits for the loop thread once, to build the model; call it before the controller
//   thread starts stepping. The server must outlive the host; destroy (or stop()) the host
//   before stopping the server. After the host is gone its methods answer BadShutdown.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <stop_token>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/factory/machine.hpp"
#include "sf/factory/machine_model.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::factory {

struct MachineHostOptions {
  MachineModelOptions model;
  // How long an operator's method call waits for the controller thread.
  std::chrono::milliseconds command_timeout{5000};
  // StatusPublisher's resolution of the Admin durations.
  std::chrono::milliseconds time_resolution{1000};
};

class MachineHost {
 public:
  // Builds the controller's model in `server` (waits for its loop thread). `controller` and
  // `server` must outlive the host.
  static Result<std::unique_ptr<MachineHost>> attach(opcua::server::Server& server,
                                                     MachineController& controller, const Clock& clock,
                                                     MachineHostOptions options = {});
  ~MachineHost();
  MachineHost(const MachineHost&) = delete;
  MachineHost& operator=(const MachineHost&) = delete;

  // Controller thread: runs the queued operator commands and posted tasks, polls the controller
  // when its time has come, publishes what changed. Returns when the controller wants its next
  // poll.
  Clock::time_point step(Clock::time_point now);
  // Controller thread: step() until stop(), sleeping until the next poll or a posted task.
  void run();
  // Any thread: run() returns after the current step.
  void stop();
  // Any thread: fn runs on the controller thread in the next step() (e.g. work the Contract Net
  // awarded). Dropped after the host is destroyed.
  void post(std::function<void(MachineController&)> fn);
  // Any thread may call `wake` (after a post or a method call): for a loop of the caller's own
  // that calls step(). Set it before the first post.
  void set_wake(std::function<void()> wake);

  [[nodiscard]] const opcua::NodeId& machine() const;
  // MachineModel::node: the NodeId of a node of the model by its path.
  [[nodiscard]] opcua::NodeId node(std::string_view path) const;

  struct Inbox;

 private:
  MachineHost(opcua::server::Server& server, MachineController& controller, const Clock& clock,
              MachineHostOptions options);
  void publish();

  opcua::server::Server& server_;
  MachineController& controller_;
  const Clock& clock_;
  MachineHostOptions options_;
  std::shared_ptr<Inbox> inbox_;
  std::shared_ptr<MachineModel> model_;
  StatusPublisher publisher_;
  Clock::time_point next_poll_{};
};

// What a `machine` or `gateway` process needs to serve its controller: the server (endpoint,
// security), the NodeSet2 files to import first (the ontology's, from `kb to-nodeset`, so the
// machine object is its individual) and the host's options.
struct MachineServerConfig {
  opcua::server::ServerConfig server;
  std::vector<std::string> nodesets;
  MachineHostOptions host;
};

// The one call for such a process: imports the nodesets, starts the server, attaches the model
// and runs the controller's poll loop on the calling thread until `stop` is requested; then
// stops the server. `started` (may be empty) gets the running server first, e.g. to print its
// endpoint URL. Errors: a nodeset that does not import, a port that does not bind, a model that
// cannot be built.
Status serve_machine(MachineController& controller, const MachineServerConfig& config, const Clock& clock,
                     const std::stop_token& stop,
                     const std::function<void(const opcua::server::Server&)>& started = {});

}  // namespace sf::factory
