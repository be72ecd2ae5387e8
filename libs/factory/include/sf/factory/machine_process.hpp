// The smart robot's IPC as a process (`smartfactory machine --config FILE`,
// paper §VII.A): the EtherCAT master of the robot's own segment, the
// SmartRobot controller on its cycle thread (ControllerThread, SCHED_FIFO
// when allowed) and the robot's contractor in the Contract Net over Cyclone
// DDS on the process's main thread (negotiation::run_agents), which reaches
// the controller through a RemoteController. Job ends come back to the main
// thread through the DDS executor, as INFORM-DONE or FAILURE.
//
// Its OPC UA server (the opcua settings: port, security, users, the
// ontology's NodeSet2) publishes the controller's machine model
// (machine_host.hpp), fed from the cycle thread's status snapshots;
// operators' PackML methods become calls on the cycle thread.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/executor.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/factory/contract_net.hpp"
#include "sf/factory/controller_process.hpp"
#include "sf/factory/controller_thread.hpp"
#include "sf/factory/machine_config.hpp"
#include "sf/factory/machine_host.hpp"
#include "sf/factory/smart_robot.hpp"
#include "sf/negotiation/agents.hpp"

namespace sf::factory {

// What the process reports: the controller, its cycle and its part in the Contract Net.
struct MachineReport {
  Identification identification;
  std::string link;  // the EtherCAT link spec
  ControllerStatus controller;
  negotiation::ContractorStats contract_net;
  std::uint64_t cycles = 0;
  bool realtime = false;  // the cycle thread got SCHED_FIFO
  std::chrono::nanoseconds lateness_p50{0};
  std::chrono::nanoseconds lateness_p99{0};
  std::chrono::nanoseconds lateness_max{0};
  std::string opcua_endpoint;  // opc.tcp://host:port
  std::string opcua_security;  // what the server's security came to
};

class MachineProcess {
 public:
  // Opens the EtherCAT link, brings the segment up to OP, joins the Contract
  // Net. `clock` (real time in deployment) must outlive the process. Nothing
  // runs yet; an error names what did not come up.
  static Result<std::unique_ptr<MachineProcess>> create(MachineSetup setup, Clock& clock);
  ~MachineProcess();
  MachineProcess(const MachineProcess&) = delete;
  MachineProcess& operator=(const MachineProcess&) = delete;

  // Starts the cycle thread and runs the Contract Net on the calling thread
  // until stop() is true (checked at least every 100 ms); on_report gets a
  // report every `interval` and whenever the PackML state, the job or the
  // queue changed. The cycle thread stops before run returns.
  void run(const std::function<bool()>& stop, const std::function<void(const MachineReport&)>& on_report,
           std::chrono::nanoseconds interval);

  [[nodiscard]] MachineReport report() const;
  [[nodiscard]] ControllerThread& controller_thread() { return hosted_->thread(); }
  [[nodiscard]] RemoteController& remote() { return hosted_->remote(); }
  [[nodiscard]] const MachineSetup& setup() const { return setup_; }
  [[nodiscard]] opcua::server::Server& opcua_server() { return hosted_->model().server(); }
  [[nodiscard]] const MachineHost& machine_model() const { return hosted_->model().host(); }

 private:
  explicit MachineProcess(MachineSetup setup);

  MachineSetup setup_;
  std::unique_ptr<ethercat::Link> link_;
  std::unique_ptr<ethercat::master::Master> master_;
  std::unique_ptr<SmartRobot> robot_;
  std::unique_ptr<HostedController> hosted_;  // its job ends go to the executor
  dds::Executor executor_;
  std::unique_ptr<ControllerBackend> backend_;
  std::unique_ptr<negotiation::MachineAgent> agent_;  // after the executor: its readers deliver there
};

}  // namespace sf::factory
