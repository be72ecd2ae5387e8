#include "sf/factory/machine_process.hpp"

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/server/security_setup.hpp"

namespace sf::factory {

namespace {

constexpr int kBringUpAttempts = 3;

// What a report shows changed: state, job, queue, segment.
std::string headline(const ControllerStatus& s) {
  return fmt::format("{}|{}|{}|{}", to_string(s.packml.state), s.job.value_or(""), s.queued, s.fault);
}

}  // namespace

// Calls on_report on the agents' loop: every interval, and on a change of headline.
class MachineProcess::Reporter final : public negotiation::Agent {
 public:
  Reporter(const MachineProcess& process, const Clock& clock,
           std::function<void(const MachineReport&)> on_report, std::chrono::nanoseconds interval)
      : process_(&process), clock_(&clock), on_report_(std::move(on_report)), interval_(interval) {}

  void tick() override {
    const auto now = clock_->now();
    MachineReport r = process_->report();
    const std::string shown = headline(r.controller);
    if (now < next_ && shown == last_) {
      return;
    }
    last_ = shown;
    next_ = now + interval_;
    if (on_report_) {
      on_report_(r);
    }
  }
  // Checked often enough to see a change of state soon after it happens.
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override {
    return std::min(next_, clock_->now() + std::chrono::milliseconds{50});
  }

 private:
  const MachineProcess* process_;
  const Clock* clock_;
  std::function<void(const MachineReport&)> on_report_;
  std::chrono::nanoseconds interval_;
  Clock::time_point next_{};
  std::string last_;
};

MachineProcess::MachineProcess(MachineSetup setup, Clock& clock) : setup_(std::move(setup)), clock_(&clock) {}

MachineProcess::~MachineProcess() {
  if (thread_) {
    thread_->stop();
  }
  host_.reset();
  if (server_) {
    server_->stop();
  }
}

// The controller's OPC UA server with its machine model, serving.
Status MachineProcess::serve_model() {
  const ControllerSettings& c = setup_.config.controller;
  opcua::server::ServerConfig config;
  config.transport.port = c.opcua_port;
  config.identity.application_name = fmt::format("smartfactory {}", c.machine);
  auto security = opcua::server::configure_server_security(c.opcua_security, false, config);
  if (!security) {
    return Error(security.error()).with_context("OPC UA security");
  }
  security_text_ = *security;
  server_ = std::make_unique<opcua::server::Server>(std::move(config), *clock_);
  Status imported;
  server_->with_address_space([&](opcua::server::AddressSpace& space) {
    auto reports = opcua::server::import_nodeset_files(space, c.opcua_nodesets);
    imported = reports ? Status{} : Status(reports.error());
  });
  SF_TRY(imported);
  auto host = MachineHost::attach(*server_, *thread_, robot_->identification());
  if (!host) {
    return host.error();
  }
  host_ = std::move(*host);
  return server_->start();
}

Result<std::unique_ptr<MachineProcess>> MachineProcess::create(MachineSetup setup, Clock& clock) {
  std::unique_ptr<MachineProcess> p(new MachineProcess(std::move(setup), clock));
  const MachineConfig& c = p->setup_.config;
  auto link = ethercat::open_link(c.ethercat.link);
  if (!link) {
    return Error(link.error()).with_context(fmt::format("EtherCAT link {}", c.ethercat.link));
  }
  p->link_ = std::move(*link);
  p->master_ = std::make_unique<ethercat::master::Master>(*p->link_, clock);
  p->robot_ = std::make_unique<SmartRobot>(smart_robot_config(c), p->setup_.layout, *p->master_, clock);
  if (auto started = p->robot_->start(); !started) {
    return Error(started.error())
        .with_context(fmt::format("{} on {}", c.controller.machine, c.ethercat.link));
  }
  ControllerThreadOptions thread_options;
  thread_options.realtime = c.ethercat.realtime;
  p->thread_ = std::make_unique<ControllerThread>(*p->robot_, clock, thread_options);
  if (auto served = p->serve_model(); !served) {
    return Error(served.error()).with_context("the machine's OPC UA server");
  }
  MachineProcess* self = p.get();
  p->remote_ = std::make_unique<RemoteController>(
      *p->thread_, p->robot_->identification(),
      [self](std::function<void()> f) { self->executor_.post(std::move(f)); });
  p->backend_ = std::make_unique<ControllerBackend>(*p->remote_);
  negotiation::ContractorConfig contractor{c.controller.machine, p->backend_->skills()};
  contractor.backend = p->backend_.get();
  auto agent = negotiation::MachineAgent::create(dds_settings(c.controller.dds), std::move(contractor), {},
                                                 p->executor_, clock);
  if (!agent) {
    return Error(agent.error()).with_context("the Contract Net over DDS");
  }
  p->agent_ = std::move(*agent);
  p->backend_->bind(p->agent_->contractor());
  return p;
}

void MachineProcess::run(const std::function<bool()>& stop,
                         const std::function<void(const MachineReport&)>& on_report,
                         std::chrono::nanoseconds interval) {
  thread_->start();
  Reporter reporter(*this, *clock_, on_report, interval);
  negotiation::run_agents(executor_, *clock_, {agent_.get(), &reporter}, stop);
  thread_->stop();
  if (on_report) {
    on_report(report());
  }
}

MachineReport MachineProcess::report() const {
  MachineReport r;
  r.identification = robot_->identification();
  r.link = setup_.config.ethercat.link;
  r.controller = thread_->status();
  r.contract_net = agent_->contractor().stats();
  r.cycles = thread_->polls();
  r.realtime = thread_->realtime_active();
  const auto lateness = thread_->lateness();
  r.lateness_p50 = lateness.quantile(0.5);
  r.lateness_p99 = lateness.quantile(0.99);
  r.lateness_max = lateness.max();
  r.opcua_endpoint = fmt::format("opc.tcp://{}:{}", "localhost", server_->port());
  r.opcua_security = security_text_;
  return r;
}

}  // namespace sf::factory
