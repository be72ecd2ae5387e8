#include "sf/factory/machine_process.hpp"

#include <fmt/format.h>

namespace sf::factory {

namespace {

// What a report shows changed: state, job, queue, segment.
std::string headline(const ControllerStatus& s) {
  return fmt::format("{}|{}|{}|{}", to_string(s.packml.state), s.job.value_or(""), s.queued, s.fault);
}

}  // namespace

MachineProcess::MachineProcess(MachineSetup setup) : setup_(std::move(setup)) {}

MachineProcess::~MachineProcess() {
  hosted_.reset();  // no job ends from here on
}

Result<std::unique_ptr<MachineProcess>> MachineProcess::create(MachineSetup setup, Clock& clock) {
  std::unique_ptr<MachineProcess> p(new MachineProcess(std::move(setup)));
  const MachineConfig& c = p->setup_.config;
  auto link = ethercat::open_link(c.ethercat.link);
  if (!link) {
    return Error(link.error()).with_context(fmt::format("EtherCAT link {}", c.ethercat.link));
  }
  p->link_ = std::move(*link);
  // Distributed clocks with SYNC0 at the CSP cycle (ETG.1020 §4.2): the drives take their
  // set-points on the segment's common time, not on frame arrival.
  ethercat::master::MasterOptions master_options;
  master_options.sync0_cycle = c.ethercat.cycle;
  p->master_ = std::make_unique<ethercat::master::Master>(*p->link_, clock, master_options);
  p->robot_ = std::make_unique<SmartRobot>(smart_robot_config(c), p->setup_.layout, *p->master_, clock);
  if (auto started = p->robot_->start(); !started) {
    return Error(started.error())
        .with_context(fmt::format("{} on {}", c.controller.machine, c.ethercat.link));
  }
  ControllerThreadOptions thread_options;
  thread_options.realtime = c.ethercat.realtime;
  MachineProcess* self = p.get();
  auto hosted =
      HostedController::create(*p->robot_, c.controller, thread_options, clock,
                               [self](std::function<void()> f) { self->executor_.post(std::move(f)); });
  if (!hosted) {
    return hosted.error();
  }
  p->hosted_ = std::move(*hosted);
  p->backend_ = std::make_unique<ControllerBackend>(p->hosted_->remote());
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
  const auto shown = [this] { return headline(hosted_->thread().status()); };
  const auto print = [&] {
    if (on_report) {
      on_report(report());
    }
  };
  hosted_->run(executor_, *agent_, stop, {shown, print, interval});
  if (on_report) {
    on_report(report());
  }
}

MachineReport MachineProcess::report() const {
  MachineReport r;
  r.identification = robot_->identification();
  r.link = setup_.config.ethercat.link;
  r.controller = hosted_->thread().status();
  r.contract_net = agent_->contractor().stats();
  r.cycles = hosted_->thread().polls();
  r.realtime = hosted_->thread().realtime_active();
  const auto lateness = hosted_->thread().lateness();
  r.lateness_p50 = lateness.quantile(0.5);
  r.lateness_p99 = lateness.quantile(0.99);
  r.lateness_max = lateness.max();
  r.opcua_endpoint = hosted_->model().endpoint();
  r.opcua_security = hosted_->model().security();
  return r;
}

}  // namespace sf::factory
