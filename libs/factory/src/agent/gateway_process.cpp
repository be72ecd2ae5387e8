// The gateway process (gateway_process.hpp).
#include "sf/factory/gateway_process.hpp"

#include <fmt/format.h>

namespace sf::factory {

namespace {

// A gateway polls its PLC every poll period; that is no hard real-time cycle, so its thread
// keeps the normal scheduler.
ControllerThreadOptions gateway_thread_options() {
  ControllerThreadOptions options;
  options.realtime = false;
  return options;
}

}  // namespace

Result<std::unique_ptr<GatewayProcess>> GatewayProcess::create(GatewaySetup setup, Clock& clock) {
  auto options = tcp_options(setup);
  if (!options) {
    return options.error();
  }
  auto client = modbus::TcpClient::create(*options);
  if (!client) {
    return client.error();
  }
  auto p = std::unique_ptr<GatewayProcess>(new GatewayProcess(std::move(setup), std::move(*client), clock));
  Gateway& gateway = *p->gateway_;
  GatewayProcess* self = p.get();
  auto hosted =
      HostedController::create(gateway, gateway.config().controller, gateway_thread_options(), clock,
                               [self](std::function<void()> f) { self->executor_.post(std::move(f)); });
  if (!hosted) {
    return hosted.error();
  }
  p->hosted_ = std::move(*hosted);
  ControllerThread* thread = &p->hosted_->thread();
  GatewayAccess access{&gateway.config(), &p->hosted_->remote(), [thread, g = &gateway] {
                         return thread->call([g](MachineController&) { return g->conveyor_offer(); });
                       }};
  auto agent = GatewayAgent::create(std::move(access), dds_settings(gateway.config().controller.dds),
                                    p->executor_, clock);
  if (!agent) {
    return Error(agent.error()).with_context("the Contract Net over DDS");
  }
  p->agent_ = std::move(*agent);
  return p;
}

GatewayProcess::GatewayProcess(GatewaySetup setup, std::unique_ptr<modbus::TcpClient> client, Clock& clock)
    : client_(std::move(client)),
      gateway_(std::make_unique<Gateway>(std::move(setup.config), std::move(setup.layout), *client_, clock)) {
}

GatewayProcess::~GatewayProcess() {
  hosted_.reset();  // no job ends from here on
}

void GatewayProcess::run(const std::function<bool()>& stop,
                         const std::function<void(const GatewayReport&)>& on_report,
                         std::chrono::nanoseconds interval) {
  const auto headline = [this] {
    const ControllerStatus s = hosted_->thread().status();
    return fmt::format("{} {} {} {}", to_string(s.packml.state), gateway_->link_state(), s.job.value_or(""),
                       s.queued);
  };
  hosted_->run(executor_, *agent_, stop,
               {headline, [&] { on_report ? on_report(report()) : void(); }, interval});
}

GatewayReport GatewayProcess::report() const {
  GatewayReport r;
  r.identification = gateway_->identification();
  r.endpoint = client_->endpoint();
  r.link = std::string(gateway_->link_state());
  r.controller = hosted_->thread().status();
  r.contract_net = agent_->roles().contractor().stats();
  if (const auto* conveyor = agent_->roles().conveyor()) {
    r.informs = conveyor->informs();
    r.silent = conveyor->silent();
  }
  r.opcua_endpoint = hosted_->model().endpoint();
  r.opcua_security = hosted_->model().security();
  return r;
}

}  // namespace sf::factory
