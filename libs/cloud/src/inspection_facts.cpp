// An inspection as triples of the ontology (inspection_facts.hpp).
#include "inspection_facts.hpp"

#include <cctype>
#include <map>

#include <fmt/chrono.h>
#include <fmt/format.h>

#include "sf/knowledge/vocab.hpp"
#include "sf/line/ontology.hpp"

namespace sf::cloud::detail {

namespace vocab = sf::knowledge::vocab;

namespace {

// An order id as part of an IRI: letters, digits, '-', '.' and '_' stay, anything else is
// percent-encoded (RFC 3987 iunreserved), so every id gives its own valid IRI.
std::string iri_part(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) != 0 || c == '-' || c == '.' || c == '_') {
      out += c;
    } else {
      out += fmt::format("%{:02X}", u);
    }
  }
  return out;
}

std::string xsd_date_time(historian::Timestamp t) {
  return fmt::format("{:%Y-%m-%dT%H:%M:%S}Z", std::chrono::floor<std::chrono::milliseconds>(t));
}

}  // namespace

knowledge::TermId ontology_term(knowledge::Dictionary& dict, std::string_view local) {
  return dict.iri(fmt::format("{}{}", vocab::kSf, local));
}

knowledge::TermId line_term(knowledge::Dictionary& dict, std::string_view local) {
  return dict.iri(fmt::format("{}{}", line::kLineNamespace, local));
}

knowledge::TermId InspectionFacts::integer(int n) {
  return dict_.literal(std::to_string(n), vocab::kXsdInteger);
}

knowledge::TermId InspectionFacts::type() {
  return dict_.iri(vocab::kRdfType);
}

void InspectionFacts::order(const line::InspectionRecord& r, historian::Timestamp at,
                            std::vector<knowledge::Triple>& add) {
  const knowledge::TermId o = p("Order_" + iri_part(r.order));
  add.push_back({o, type(), sf("Order")});
  add.push_back({o, sf("orderCode"), dict_.literal(r.order)});
  add.push_back({o, sf("boxType"), sf(line::iri_name(r.box_type))});
  for (const auto& [candy, n] : r.ordered) {
    order_line(r.order, candy, n, add);
  }
  if (due_after_.count() > 0) {
    // Accepted lead_s before this inspection, due due_after after that.
    const auto accepted =
        at - std::chrono::duration_cast<historian::Micros>(std::chrono::duration<double>(r.lead_s));
    add.push_back({o, sf("dueAt"), dict_.literal(xsd_date_time(accepted + due_after_), vocab::kXsdDateTime)});
  }
}

void InspectionFacts::order_line(const std::string& order, const std::string& candy, int quantity,
                                 std::vector<knowledge::Triple>& add) {
  const knowledge::TermId l = p(fmt::format("Order_{}_{}", iri_part(order), line::iri_name(candy)));
  add.push_back({l, type(), sf("OrderLine")});
  add.push_back({l, sf("forOrder"), p("Order_" + iri_part(order))});
  add.push_back({l, sf("candyType"), sf(line::iri_name(candy))});
  add.push_back({l, sf("quantity"), integer(quantity)});
}

void InspectionFacts::box(const line::InspectionRecord& r, historian::Timestamp at,
                          std::vector<knowledge::Triple>& add, std::vector<knowledge::Triple>& lines) {
  const std::string name = fmt::format("Box_{}_{}", iri_part(r.order), r.box);
  const knowledge::TermId subject = p(name);
  add.push_back({subject, type(), sf("CandyBox")});
  add.push_back({subject, sf("forOrder"), p("Order_" + iri_part(r.order))});
  add.push_back({subject, sf("completedAt"), dict_.literal(xsd_date_time(at), vocab::kXsdDateTime)});
  int total = 0;
  // Every candy type ordered or found: a type the box lacks altogether is a count of 0.
  std::map<std::string, int> content = r.counted;
  for (const auto& [candy, n] : r.ordered) {
    content.emplace(candy, 0);
  }
  // A type the order does not name is one it asks none of: its line says 0, so contentMismatch
  // reports it ("chocolate: ordered 0, the box holds 2") without a rule of negation, whose
  // result would hang on the order in which a forward engine meets the facts.
  for (const auto& [candy, n] : r.counted) {
    if (!r.ordered.contains(candy)) {
      order_line(r.order, candy, 0, lines);
    }
  }
  for (const auto& [candy, n] : content) {
    const knowledge::TermId c = p(fmt::format("{}_{}", name, line::iri_name(candy)));
    add.push_back({subject, sf("hasContent"), c});
    add.push_back({c, type(), sf("BoxContent")});
    add.push_back({c, sf("candyType"), sf(line::iri_name(candy))});
    add.push_back({c, sf("count"), integer(n)});
    total += n;
  }
  add.push_back({subject, sf("candyCount"), integer(total)});
}

}  // namespace sf::cloud::detail
