// What the `machine` and `gateway` commands print about their controller in a status line: the
// JSON fields and the text both share (PackML state and counters, job, queue, the Contract Net).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "sf/factory/machine.hpp"
#include "sf/negotiation/contractor.hpp"

namespace sf::app {

// {"event":"status","machine",...,"state","mode","fault","job","queued","produced","defective",
//  "bids","declines","done","failures"[,"stop_reason"]}; the caller adds its own fields.
nlohmann::json controller_status_json(const std::string& machine, const factory::ControllerStatus& status,
                                      const negotiation::ContractorStats& contract_net);

// "<machine>: <state>, job <job>, queue <n>; <b> bids, <d> done, <f> failed"
std::string controller_status_text(const std::string& machine, const factory::ControllerStatus& status,
                                   const negotiation::ContractorStats& contract_net);

}  // namespace sf::app
