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
// GatewayAgent puts them on DDS. Neither polls the gateway: whoever drives it
// (a test's loop, the gateway process's ControllerThread) does, and the roles
// reach it through the controller they are given (a RemoteController from
// the DDS thread) and a function that asks it for its ConveyorOffer.
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
  // `offer` asks the gateway on the thread that drives it.
  explicit ConveyorSegments(std::function<ConveyorOffer()> offer) : offer_(std::move(offer)) {}
  std::vector<negotiation::Hop> segments(const negotiation::TransportRequest& request,
                                         std::string& why_not) override;

 private:
  std::function<ConveyorOffer()> offer_;
};

// How the roles reach a gateway: `controller` (the Gateway itself on its driving thread, or a
// RemoteController), `offer` its Gateway::conveyor_offer() the same way; the configuration is
// read-only.
struct GatewayAccess {
  const GatewayConfig* config = nullptr;
  MachineController* controller = nullptr;
  std::function<ConveyorOffer()> offer;

  // The gateway called directly (the caller's thread drives it).
  static GatewayAccess direct(Gateway& gateway);
};

class GatewayRoles {
 public:
  // `conveying` is the conveyor role's transport, needed for (and only for) a conveyor's gateway.
  // The gateway must outlive the roles; its controller's on_job_end is taken over.
  static Result<std::unique_ptr<GatewayRoles>> create(GatewayAccess gateway,
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
  explicit GatewayRoles(GatewayAccess& gateway)
      : backend_(*gateway.controller), segments_(std::move(gateway.offer)) {}

  ControllerBackend backend_;
  ConveyorSegments segments_;
  std::optional<negotiation::Contractor> contractor_;
  std::optional<negotiation::Conveyor> conveyor_;
};

class GatewayAgent final : public negotiation::Agent {
 public:
  static Result<std::unique_ptr<GatewayAgent>> create(GatewayAccess gateway,
                                                      const negotiation::DdsSettings& settings,
                                                      dds::Executor& executor, const Clock& clock);
  GatewayAgent(const GatewayAgent&) = delete;
  GatewayAgent& operator=(const GatewayAgent&) = delete;
  ~GatewayAgent() override;

  // The contractor's timers, batched conversation ends and the liveliness of its BID writers.
  void tick() override;
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override;

  [[nodiscard]] const GatewayRoles& roles() const { return *roles_; }
  // Its DDS participants (MachiningDomain, and ConveyingDomain for a conveyor).
  [[nodiscard]] std::vector<const dds::Participant*> participants() const;

 private:
  GatewayAgent() = default;

  std::unique_ptr<negotiation::MachineEndpoints> machining_;
  std::unique_ptr<negotiation::ConveyorEndpoints> conveying_;
  std::unique_ptr<GatewayRoles> roles_;  // last: its roles use the endpoints
};

}  // namespace sf::factory
