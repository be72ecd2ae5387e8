// A shop-floor controller in the Contract Net (paper §IV.B): the contractor
// of the negotiation module asks the controller for its bids and hands it the
// work it was awarded (negotiation::WorkBackend); the controller's job ends
// become INFORM-DONE or FAILURE to the product.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sf/factory/machine.hpp"
#include "sf/negotiation/contractor.hpp"

namespace sf::factory {

// Contract Net parameters ↔ an Operation.
Operation to_operation(const std::string& type, const std::vector<negotiation::Param>& params);
// A job's typed results as INFORM-DONE carries them: those whose names fit the IDL's bound, at
// most kMaxParams of them, in name order (the result text says the rest).
std::vector<negotiation::Param> to_params(const std::map<std::string, double>& results);

// The controller's job of one award: "<conversation>#<award id>". A renegotiated conversation
// may award the same machine again while its cancelled job is still winding down (a belt
// stopping, a handshake ending): each award is a job of its own.
std::string job_id(const negotiation::Job& job);
// The conversation and award of a job id (nullopt: not one of job_id's).
std::optional<std::pair<std::string, std::uint32_t>> parse_job_id(const std::string& id);

class ControllerBackend final : public negotiation::WorkBackend {
 public:
  // The controller must outlive the backend; its on_job_end is taken over.
  explicit ControllerBackend(MachineController& controller);
  // Where job ends are reported (set once the contractor exists).
  void bind(negotiation::Contractor& contractor) { contractor_ = &contractor; }

  std::optional<negotiation::WorkEstimate> estimate(const std::string& operation,
                                                    const std::vector<negotiation::Param>& params,
                                                    std::string& why_not) override;
  Status start(const negotiation::Job& job, const std::vector<negotiation::Param>& params) override;
  void abort(const negotiation::Job& job, const std::string& why) override;

  // The skills to declare to the contractor: the controller's operations.
  [[nodiscard]] std::vector<negotiation::Skill> skills() const;

 private:
  MachineController* controller_;
  negotiation::Contractor* contractor_ = nullptr;
};

}  // namespace sf::factory
