// An order service's inspection as triples of the ontology: the order, its lines, the box and
// its counted content (knowledge_loop.hpp lists them). Private to the knowledge loop.
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "sf/historian/types.hpp"
#include "sf/knowledge/store.hpp"
#include "sf/line/inspection.hpp"

namespace sf::cloud::detail {

// sf:<local> of the ontology and p:<local> of the line's individuals.
knowledge::TermId ontology_term(knowledge::Dictionary& dict, std::string_view local);
knowledge::TermId line_term(knowledge::Dictionary& dict, std::string_view local);

class InspectionFacts {
 public:
  // An order is due `due_after` after it was accepted (sf:dueAt); 0: no due times.
  InspectionFacts(knowledge::Dictionary& dict, std::chrono::seconds due_after)
      : dict_(dict), due_after_(due_after) {}

  // The order's own triples: the order, its lines, its due time (once per order).
  void order(const line::InspectionRecord& r, historian::Timestamp at, std::vector<knowledge::Triple>& add);
  // The box's triples (the box, its content) into `box`; order lines of candy types found but
  // not ordered (quantity 0) into `lines`.
  void box(const line::InspectionRecord& r, historian::Timestamp at, std::vector<knowledge::Triple>& box,
           std::vector<knowledge::Triple>& lines);

 private:
  void order_line(const std::string& order, const std::string& candy, int quantity,
                  std::vector<knowledge::Triple>& add);
  knowledge::TermId sf(std::string_view local) { return ontology_term(dict_, local); }
  knowledge::TermId p(std::string_view local) { return line_term(dict_, local); }
  knowledge::TermId integer(int n);
  knowledge::TermId type();

  knowledge::Dictionary& dict_;
  std::chrono::seconds due_after_;
};

}  // namespace sf::cloud::detail
