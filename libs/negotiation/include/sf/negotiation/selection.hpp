// Bid selection policies: how a manager ranks the bids of one round. The
// first-ranked bidder gets the AWARD; if it refuses or does not confirm, the
// next-ranked one does. Ties are broken by contractor name, so a ranking is
// deterministic.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/negotiation/messages.hpp"

namespace sf::negotiation {

struct RankedBid {
  std::string contractor;
  Bid bid;
};

struct SelectionPolicy {
  std::string name;
  // True if a is strictly better than b.
  std::function<bool(const RankedBid& a, const RankedBid& b)> better;
};

// The bid that finishes the operation first (the paper's product wants its
// operations done soon); then lowest cost.
SelectionPolicy earliest_finish();
// The cheapest bid; then earliest finish.
SelectionPolicy lowest_cost();
// The bidder with the shortest queue (spreads work over machines); then earliest finish.
SelectionPolicy load_balance();
// "earliest-finish", "lowest-cost" or "load-balance".
Result<SelectionPolicy> policy_by_name(std::string_view name);

// Best first.
std::vector<RankedBid> rank(const SelectionPolicy& policy, std::vector<RankedBid> bids);

}  // namespace sf::negotiation
