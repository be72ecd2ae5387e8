// The line's individuals for the candy-factory ontology
// (ontology/candy-factory.ttl), derived from its layout: the product catalog
// (candy and box types), the machines with their controllers, gateways and —
// for a smart robot — its EtherCAT slave, axes and IO channels, the
// conveyors and how they connect. ontology/prototype-line.ttl is this
// function's output for the default layout (a test keeps them equal), so the
// layout and the ontology describe one line; live values (temperatures,
// states, positions) come on top, from the line itself.
#pragma once

#include <string>
#include <string_view>

#include "sf/line/layout.hpp"

namespace sf::line {

inline constexpr std::string_view kOntologyNamespace = "http://smartfactory.example/ontology/candy#";
inline constexpr std::string_view kLineNamespace = "http://smartfactory.example/prototype/";

// The local name of a layout name in the ontology: "scara-robot-1" →
// "ScaraRobot1", "conveyor2" → "Conveyor2", "small-box" → "SmallBox".
std::string iri_name(std::string_view name);

// Turtle text; `source` names the layout file in its header comment.
std::string line_turtle(const Layout& layout, std::string_view source);

}  // namespace sf::line
