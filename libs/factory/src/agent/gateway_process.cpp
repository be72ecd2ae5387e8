// The gateway process (gateway_process.hpp).
#include "sf/factory/gateway_process.hpp"

#include <fmt/format.h>

namespace sf::factory {

Result<std::unique_ptr<GatewayProcess>> GatewayProcess::create(GatewaySetup setup, const Clock& clock) {
  auto options = tcp_options(setup);
  if (!options) {
    return options.error();
  }
  auto client = modbus::TcpClient::create(*options);
  if (!client) {
    return client.error();
  }
  auto process =
      std::unique_ptr<GatewayProcess>(new GatewayProcess(std::move(setup), std::move(*client), clock));
  auto agent =
      GatewayAgent::create(*process->gateway_, dds_settings(process->gateway_->config().controller.dds),
                           process->executor_, clock);
  if (!agent) {
    return agent.error();
  }
  process->agent_ = std::move(*agent);
  process->agent_->on_poll([p = process.get()](Clock::time_point now) { p->after_poll(now); });
  return process;
}

GatewayProcess::GatewayProcess(GatewaySetup setup, std::unique_ptr<modbus::TcpClient> client,
                               const Clock& clock)
    : clock_(&clock),
      client_(std::move(client)),
      gateway_(std::make_unique<Gateway>(std::move(setup.config), std::move(setup.layout), *client_, clock)) {
}

GatewayProcess::~GatewayProcess() = default;

void GatewayProcess::on_poll(std::function<void(Gateway&)> hook) {
  hooks_.push_back(std::move(hook));
}

void GatewayProcess::run(const std::function<bool()>& stop,
                         const std::function<void(const GatewayReport&)>& on_report,
                         std::chrono::nanoseconds interval) {
  on_report_ = on_report;
  interval_ = interval;
  next_report_ = clock_->now();
  negotiation::run_agents(executor_, *clock_, {agent_.get()}, stop);
  on_report_ = nullptr;
}

void GatewayProcess::after_poll(Clock::time_point now) {
  for (auto& hook : hooks_) {
    hook(*gateway_);
  }
  if (!on_report_) {
    return;
  }
  const ControllerStatus s = gateway_->status();
  std::string shown = fmt::format("{} {} {} {}", to_string(s.packml.state), gateway_->link_state(),
                                  s.job.value_or(""), s.queued);
  if (shown == last_shown_ && (interval_.count() <= 0 || now < next_report_)) {
    return;
  }
  last_shown_ = std::move(shown);
  next_report_ = now + interval_;
  on_report_(report());
}

GatewayReport GatewayProcess::report() const {
  GatewayReport r;
  r.identification = gateway_->identification();
  r.endpoint = client_->endpoint();
  r.link = std::string(gateway_->link_state());
  r.controller = gateway_->status();
  r.contract_net = agent_->roles().contractor().stats();
  if (const auto* conveyor = agent_->roles().conveyor()) {
    r.informs = conveyor->informs();
    r.silent = conveyor->silent();
  }
  return r;
}

}  // namespace sf::factory
