// The inspection of a finished box as the order service publishes it (its OPC UA variable
// OrderService.LastInspection) and the cloud reads it back: one line of text, so that one
// sample carries the whole inspection and no client has to pair values of several variables.
//
//   alice-1 box=17 type=small-box ordered=gummy:4,toffee:2 counted=gummy:4,toffee:1 weight_g=18.0
//   lead_s=41.250
//
// The first token is the order id (ids have no spaces); then key=value pairs in any order.
// `ordered` is what the order asks for, `counted` what the downloader's vision check found in
// the box (zero counts left out), `lead_s` the seconds from the order's acceptance to this
// inspection. Unknown keys are ignored (a newer publisher), missing or malformed ones are errors.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::line {

struct InspectionRecord {
  std::string order;
  std::uint32_t box = 0;
  std::string box_type;
  std::map<std::string, int> ordered;  // candy type → quantity
  std::map<std::string, int> counted;  // candy type → count, zero counts left out
  double weight_g = 0.0;
  double lead_s = 0.0;
  friend bool operator==(const InspectionRecord&, const InspectionRecord&) = default;
  // True when the box holds exactly what the order asks for.
  [[nodiscard]] bool matches() const { return ordered == counted; }
};

std::string format_inspection(const InspectionRecord& record);
// Errors name the token that is wrong.
Result<InspectionRecord> parse_inspection(std::string_view text);

// One step of an order as the order service's OPC UA events carry it (Message; the order's id is
// the SourceName): "<what> <machine or -> <detail>", e.g. "loaded scara-robot-1 gummy:4 slots
// 0-3" or "accepted - small-box gummy:4,toffee:2". `what` and `machine` have no spaces; the detail
// is free text, maybe empty.
struct OrderStep {
  std::string what;     // accepted, awarded, routed, ..., done, failed, cancelled, cancel-refused
  std::string machine;  // the machine or conveyor it concerns; empty: none
  std::string detail;
  friend bool operator==(const OrderStep&, const OrderStep&) = default;
};

std::string format_order_step(const OrderStep& step);
Result<OrderStep> parse_order_step(std::string_view text);

}  // namespace sf::line
