#include "sf/negotiation/selection.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace sf::negotiation {

SelectionPolicy earliest_finish() {
  return {"earliest-finish", [](const RankedBid& a, const RankedBid& b) {
            if (a.bid.estimated_finish != b.bid.estimated_finish) {
              return a.bid.estimated_finish < b.bid.estimated_finish;
            }
            return a.bid.cost < b.bid.cost;
          }};
}

SelectionPolicy lowest_cost() {
  return {"lowest-cost", [](const RankedBid& a, const RankedBid& b) {
            if (a.bid.cost != b.bid.cost) {
              return a.bid.cost < b.bid.cost;
            }
            return a.bid.estimated_finish < b.bid.estimated_finish;
          }};
}

SelectionPolicy load_balance() {
  return {"load-balance", [](const RankedBid& a, const RankedBid& b) {
            if (a.bid.queue_length != b.bid.queue_length) {
              return a.bid.queue_length < b.bid.queue_length;
            }
            return a.bid.estimated_finish < b.bid.estimated_finish;
          }};
}

Result<SelectionPolicy> policy_by_name(std::string_view name) {
  for (auto make : {earliest_finish, lowest_cost, load_balance}) {
    auto p = make();
    if (p.name == name) {
      return p;
    }
  }
  return Error{
      Errc::invalid_argument,
      fmt::format("unknown selection policy '{}' (earliest-finish, lowest-cost, load-balance)", name)};
}

std::vector<RankedBid> rank(const SelectionPolicy& policy, std::vector<RankedBid> bids) {
  std::sort(bids.begin(), bids.end(), [&](const RankedBid& a, const RankedBid& b) {
    if (policy.better(a, b)) {
      return true;
    }
    if (policy.better(b, a)) {
      return false;
    }
    return a.contractor < b.contractor;
  });
  return bids;
}

}  // namespace sf::negotiation
