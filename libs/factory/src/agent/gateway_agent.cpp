// A gateway's roles in the Contract Net (gateway_agent.hpp).
#include "sf/factory/gateway_agent.hpp"

#include <fmt/format.h>

namespace sf::factory {

std::vector<negotiation::Hop> ConveyorSegments::segments(const negotiation::TransportRequest& /*request*/,
                                                         std::string& why_not) {
  if (auto why = gateway_->unavailable()) {
    why_not = *why;
    return {};
  }
  const auto start_in = gateway_->backlog();
  std::vector<negotiation::Hop> out;
  for (const TransportSegment& s : gateway_->segments()) {
    out.push_back({s.from, s.to, s.transit_time, start_in});
  }
  return out;
}

Result<std::unique_ptr<GatewayRoles>> GatewayRoles::create(Gateway& gateway,
                                                           negotiation::ContractorTransport& machining,
                                                           negotiation::ConveyorTransport* conveying,
                                                           const Clock& clock) {
  const bool conveyor = gateway.config().kind == GatewayKind::conveyor;
  if (conveyor != (conveying != nullptr)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: a conveyor's gateway, and only one, answers transport REQUESTs",
                                  gateway.config().controller.machine));
  }
  auto roles = std::unique_ptr<GatewayRoles>(new GatewayRoles(gateway));
  negotiation::ContractorConfig config{gateway.config().controller.machine, roles->backend_.skills()};
  config.backend = &roles->backend_;
  auto contractor = negotiation::Contractor::create(machining, clock, std::move(config));
  if (!contractor) {
    return contractor.error();
  }
  roles->contractor_.emplace(std::move(*contractor));
  roles->backend_.bind(*roles->contractor_);
  if (conveyor) {
    auto c = negotiation::Conveyor::create(
        *conveying, clock, {gateway.config().controller.machine, {}, {}, {}, &roles->segments_});
    if (!c) {
      return c.error();
    }
    roles->conveyor_.emplace(std::move(*c));
  }
  return roles;
}

Result<std::unique_ptr<GatewayAgent>> GatewayAgent::create(Gateway& gateway,
                                                           const negotiation::DdsSettings& settings,
                                                           dds::Executor& executor, const Clock& clock) {
  auto agent = std::unique_ptr<GatewayAgent>(new GatewayAgent(gateway, clock));
  const std::string& name = gateway.config().controller.machine;
  auto machining =
      negotiation::MachineEndpoints::create(settings, name, gateway.operations(), executor, clock);
  if (!machining) {
    return machining.error();
  }
  agent->machining_ = std::move(*machining);
  if (gateway.config().kind == GatewayKind::conveyor) {
    auto conveying = negotiation::ConveyorEndpoints::create(settings, name, executor);
    if (!conveying) {
      return conveying.error();
    }
    agent->conveying_ = std::move(*conveying);
  }
  auto roles = GatewayRoles::create(gateway, *agent->machining_, agent->conveying_.get(), clock);
  if (!roles) {
    return roles.error();
  }
  agent->roles_ = std::move(*roles);
  agent->machining_->bind(agent->roles_->contractor());
  if (agent->conveying_) {
    agent->conveying_->bind(*agent->roles_->conveyor());
  }
  return agent;
}

GatewayAgent::~GatewayAgent() = default;

void GatewayAgent::tick() {
  const auto now = clock_->now();
  if (now >= next_poll_) {
    next_poll_ = gateway_->poll(now);
    if (on_poll_) {
      on_poll_(now);
    }
  }
  roles_->contractor().tick();
  machining_->flush_ended();
  machining_->assert_liveliness();
}

std::optional<Clock::time_point> GatewayAgent::next_deadline() const {
  return earliest(next_poll_, earliest(roles_->contractor().next_deadline(),
                                       earliest(machining_->ends_due(), machining_->liveliness_due())));
}

std::vector<const dds::Participant*> GatewayAgent::participants() const {
  std::vector<const dds::Participant*> out{&machining_->participant()};
  if (conveying_) {
    out.push_back(&conveying_->participant());
  }
  return out;
}

}  // namespace sf::factory
