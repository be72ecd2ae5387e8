// Generated data for the candy factory of ontology/candy-factory.ttl, at any scale: production
// lines as in the paper's prototype (§VII: a SCARA robot with the smart controller and an
// EtherCAT slave of 8 servo axes, 32 inputs and 32 outputs; a DENSO 6-axis arm and a TOSHIBA
// SCARA behind gateways; box uploader and downloader on Mitsubishi PLCs; five conveyors on
// Siemens PLCs), orders with order lines, the boxes being filled with their counted content,
// the operations awarded to machines, alarms, and live values of which a small share violates
// the requirements of rules/candy-factory.rules. The same options give the same data.
#pragma once

#include <cstdint>
#include <vector>

#include "sf/knowledge/store.hpp"

namespace sf::examples {

using knowledge::Dictionary;
using knowledge::Triple;

struct FactoryDataOptions {
  std::size_t target_triples = 100'000;  // lines are added until at least this many triples
  std::uint32_t seed = 1;
  std::uint32_t orders_per_line = 20;
  double violation_rate = 0.02;  // share of live values and assignments that break a requirement
};

inline constexpr std::string_view kFactoryDataNamespace = "http://smartfactory.example/factory/";

std::vector<Triple> generate_factory_data(Dictionary& dict, const FactoryDataOptions& options);

}  // namespace sf::examples
