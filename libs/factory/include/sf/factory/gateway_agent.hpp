// A gateway in the Contract Net (paper §IV.B, §VII.B): the Raspberry Pi next
// to a legacy machine negotiates on the machine's behalf, from the machine's
// real state.
//
//   - Uploader, downloader, legacy robot: the contractor of the machine's
//     operation (MachiningDomain). Bids are the gateway's estimates; it
//     declines while its PLC is unreachable, while it is not in Execute
//     (held, stopped, aborted by a fault) and for a candy whose dispenser ran
//     empty. Awards become its jobs; job ends INFORM-DONE (with typed results:
//     an uploaded box's id, an inspection) or FAILURE (ControllerBackend).
//   - Conveyor: the conveyor of the ConveyingDomain, answering every REQUEST
//     with the segments of its belt and their transit times at the belt's
//     speed (ConveyorSegments), and nothing while it takes no work, so routes
//     avoid it; and the contractor of "transport": a product awards each
//     conveyor of its route the hop along that belt (a DIRECTEDAWARD with box,
//     from, to as conveying.hpp numbers places), which the gateway carries out
//     and reports as any job. The paper's ConveyingDomain has REQUEST and
//     INFORM only; the transport contract uses the MachiningDomain's topics.
//
// GatewayRoles composes the roles over any transport (in memory in tests);
// GatewayAgent puts them on DDS and polls the gateway from the agents' loop
// (run_agents), the single thread the MachineController contract asks for.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/executor.hpp"
#include "sf/factory/contract_net.hpp"
#include "sf/factory/gateway.hpp"
#include "sf/negotiation/agents.hpp"
#include "sf/negotiation/contractor.hpp"
#include "sf/negotiation/dds_transport.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::factory {

// A conveyor gateway's segments for the ConveyingDomain: place names as
// conveying.hpp gives them, the transit time at the belt's speed, and the
// work queued on the belt before a new transport could start.
class ConveyorSegments final : public negotiation::ConveyorBackend {
 public:
  explicit ConveyorSegments(const Gateway& gateway) : gateway_(&gateway) {}
  std::vector<negotiation::Hop> segments(const negotiation::TransportRequest& request,
                                         std::string& why_not) override;

 private:
  const Gateway* gateway_;
};

class GatewayRoles {
 public:
  // `conveying` is the conveyor role's transport, needed for (and only for) a conveyor's gateway.
  // The gateway must outlive the roles; its on_job_end is taken over.
  static Result<std::unique_ptr<GatewayRoles>> create(Gateway& gateway,
                                                      negotiation::ContractorTransport& machining,
                                                      negotiation::ConveyorTransport* conveying,
                                                      const Clock& clock);
  GatewayRoles(const GatewayRoles&) = delete;
  GatewayRoles& operator=(const GatewayRoles&) = delete;
  ~GatewayRoles() = default;

  [[nodiscard]] negotiation::Contractor& contractor() { return *contractor_; }
  [[nodiscard]] const negotiation::Contractor& contractor() const { return *contractor_; }
  [[nodiscard]] negotiation::Conveyor* conveyor() { return conveyor_ ? &*conveyor_ : nullptr; }
  [[nodiscard]] const negotiation::Conveyor* conveyor() const { return conveyor_ ? &*conveyor_ : nullptr; }

 private:
  explicit GatewayRoles(Gateway& gateway) : backend_(gateway), segments_(gateway) {}

  ControllerBackend backend_;
  ConveyorSegments segments_;
  std::optional<negotiation::Contractor> contractor_;
  std::optional<negotiation::Conveyor> conveyor_;
};

class GatewayAgent final : public negotiation::Agent {
 public:
  static Result<std::unique_ptr<GatewayAgent>> create(Gateway& gateway,
                                                      const negotiation::DdsSettings& settings,
                                                      dds::Executor& executor, const Clock& clock);
  GatewayAgent(const GatewayAgent&) = delete;
  GatewayAgent& operator=(const GatewayAgent&) = delete;
  ~GatewayAgent() override;

  // Polls the gateway when its poll is due, then the contractor's timers, batched conversation
  // ends and the liveliness of its BID writers.
  void tick() override;
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override;

  // Runs `hook` after every poll of the gateway, with the poll's time.
  void on_poll(std::function<void(Clock::time_point)> hook) { on_poll_ = std::move(hook); }

  [[nodiscard]] const GatewayRoles& roles() const { return *roles_; }
  // Its DDS participants (MachiningDomain, and ConveyingDomain for a conveyor).
  [[nodiscard]] std::vector<const dds::Participant*> participants() const;

 private:
  GatewayAgent(Gateway& gateway, const Clock& clock) : gateway_(&gateway), clock_(&clock) {}

  Gateway* gateway_;
  const Clock* clock_;
  Clock::time_point next_poll_ = Clock::time_point::min();
  std::function<void(Clock::time_point)> on_poll_;
  std::unique_ptr<negotiation::MachineEndpoints> machining_;
  std::unique_ptr<negotiation::ConveyorEndpoints> conveying_;
  std::unique_ptr<GatewayRoles> roles_;  // last: its roles use the endpoints
};

}  // namespace sf::factory
