// A gateway's roles in the Contract Net (gateway_agent.hpp).
#include "sf/factory/gateway_agent.hpp"

#include <fmt/format.h>

namespace sf::factory {

std::vector<negotiation::Hop> ConveyorSegments::segments(const negotiation::TransportRequest& /*request*/,
                                                         std::string& why_not) {
  const ConveyorOffer offer = offer_();
  if (offer.unavailable) {
    why_not = *offer.unavailable;
    return {};
  }
  std::vector<negotiation::Hop> out;
  for (const TransportSegment& s : offer.segments) {
    out.push_back({s.from, s.to, s.transit_time, offer.backlog});
  }
  return out;
}

GatewayAccess GatewayAccess::direct(Gateway& gateway) {
  return {&gateway.config(), &gateway, [g = &gateway] { return g->conveyor_offer(); }};
}

Result<std::unique_ptr<GatewayRoles>> GatewayRoles::create(GatewayAccess gateway,
                                                           negotiation::ContractorTransport& machining,
                                                           negotiation::ConveyorTransport* conveying,
                                                           const Clock& clock) {
  const GatewayConfig& c = *gateway.config;
  const bool conveyor = c.kind == GatewayKind::conveyor;
  if (conveyor != (conveying != nullptr)) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: a conveyor's gateway, and only one, answers transport REQUESTs",
                                  c.controller.machine));
  }
  auto roles = std::unique_ptr<GatewayRoles>(new GatewayRoles(gateway));
  negotiation::ContractorConfig config{c.controller.machine, roles->backend_.skills()};
  config.backend = &roles->backend_;
  auto contractor = negotiation::Contractor::create(machining, clock, std::move(config));
  if (!contractor) {
    return contractor.error();
  }
  roles->contractor_.emplace(std::move(*contractor));
  roles->backend_.bind(*roles->contractor_);
  if (conveyor) {
    auto role = negotiation::Conveyor::create(*conveying, clock,
                                              {c.controller.machine, {}, {}, {}, &roles->segments_});
    if (!role) {
      return role.error();
    }
    roles->conveyor_.emplace(std::move(*role));
  }
  return roles;
}

Result<std::unique_ptr<GatewayAgent>> GatewayAgent::create(GatewayAccess gateway,
                                                           const negotiation::DdsSettings& settings,
                                                           dds::Executor& executor, const Clock& clock) {
  auto agent = std::unique_ptr<GatewayAgent>(new GatewayAgent());
  const std::string& name = gateway.config->controller.machine;
  auto machining = negotiation::MachineEndpoints::create(settings, name, gateway.controller->operations(),
                                                         executor, clock);
  if (!machining) {
    return machining.error();
  }
  agent->machining_ = std::move(*machining);
  if (gateway.config->kind == GatewayKind::conveyor) {
    auto conveying = negotiation::ConveyorEndpoints::create(settings, name, executor);
    if (!conveying) {
      return conveying.error();
    }
    agent->conveying_ = std::move(*conveying);
  }
  auto roles = GatewayRoles::create(std::move(gateway), *agent->machining_, agent->conveying_.get(), clock);
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
  roles_->contractor().tick();
  machining_->flush_ended();
  machining_->assert_liveliness();
}

std::optional<Clock::time_point> GatewayAgent::next_deadline() const {
  return earliest(roles_->contractor().next_deadline(),
                  earliest(machining_->ends_due(), machining_->liveliness_due()));
}

std::vector<const dds::Participant*> GatewayAgent::participants() const {
  std::vector<const dds::Participant*> out{&machining_->participant()};
  if (conveying_) {
    out.push_back(&conveying_->participant());
  }
  return out;
}

}  // namespace sf::factory
