// The line's ontology individuals from its layout (ontology.hpp).
#include "sf/line/ontology.hpp"

#include <cctype>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "sf/line/registers.hpp"
#include "sf/line/smart_robot.hpp"

namespace sf::line {

namespace {

constexpr unsigned kSmartAxes = 8;  // the smart controller's slave (paper §VII.A)
constexpr unsigned kSmartIo = 32;

std::string p(std::string_view name) {
  return "p:" + iri_name(name);
}
std::string sf(std::string_view name) {
  return "sf:" + iri_name(name);
}

// A Turtle string literal.
std::string literal(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
    }
    out += c;
  }
  return out + "\"";
}

std::string turtle_number(double v) {
  return fmt::format("\"{}\"^^xsd:double",
                     v == std::floor(v) ? fmt::format("{:.1f}", v) : fmt::format("{}", v));
}

std::string turtle_list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) {
    out += (out.empty() ? "" : " , ") + item;
  }
  return out;
}

std::string capabilities(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    out.push_back(sf(n));
  }
  return turtle_list(out);
}

void catalog(std::string& out, const Catalog& c) {
  out += "\n# --- The catalog: candy and box types a consumer can choose ------------------------------\n\n";
  for (const auto& t : c.candy_types) {
    out += fmt::format("{} a sf:CandyType , owl:NamedIndividual ; rdfs:label {} ; sf:unitWeight {} .\n",
                       sf(t.name), literal(t.label), turtle_number(t.unit_weight_g));
  }
  for (const auto& b : c.box_types) {
    out += fmt::format("{} a sf:BoxType , owl:NamedIndividual ; rdfs:label {} ; sf:capacity {} .\n",
                       sf(b.name), literal(b.label), b.capacity());
  }
}

// A closed controller (PLC or robot controller) and the gateway beside it (§VII.B).
void legacy_controller(std::string& out, const std::string& machine, const std::string& label,
                       const PlcSpec& plc, std::string_view what) {
  out += fmt::format("{}Controller a sf:LegacyPLC ; rdfs:label {} ; sf:manufacturer {}{} .\n", machine,
                     literal(fmt::format("{} {}", label, what)), literal(plc.vendor),
                     plc.model.empty() ? "" : fmt::format(" ; sf:model {}", literal(plc.model)));
  out += fmt::format(
      "{}Gateway a sf:Gateway ; rdfs:label {} ; sf:model \"Raspberry Pi\" ; sf:gatewayFor {}Controller .\n",
      machine, literal(fmt::format("gateway of the {}", label)), machine);
}

// The smart controller (IPC) and its ET1100 slave: 8 CiA 402 axes, 32 DI, 32 DO;
// the arm's axes carry their travel (degrees for revolute joints, millimetres for z).
void smart_robot(std::string& out, const RobotSpec& r) {
  const std::string m = p(r.name);
  out += fmt::format("{}Controller a sf:SmartController ; rdfs:label {} ; sf:hasComponent {}Slave .\n", m,
                     literal(fmt::format("smart controller (IPC) of the {}", r.label)), m);
  std::vector<std::string> parts;
  for (unsigned a = 1; a <= kSmartAxes; ++a) {
    parts.push_back(fmt::format("{}Axis{}", m, a));
  }
  const char* inputs[] = {"part present", "vacuum ok"};
  std::vector<std::pair<std::string, std::string>> io;  // individual, its line
  for (unsigned d = 0; d < kSmartIo; ++d) {
    std::string meaning;
    if (d < 2) {
      meaning = inputs[d];
    } else if (d - kDiBoxInPlace < r.stations.size()) {
      meaning = "box in place at " + r.stations[d - kDiBoxInPlace];
    }
    if (!meaning.empty()) {
      io.emplace_back(fmt::format("{}DI{}", m, d + 1),
                      fmt::format("a sf:DigitalInput ; sf:channel \"{}\"^^xsd:int ; rdfs:label {}", d + 1,
                                  literal(meaning)));
    }
  }
  io.emplace_back(fmt::format("{}DO1", m),
                  "a sf:DigitalOutput ; sf:channel \"1\"^^xsd:int ; rdfs:label \"vacuum gripper\"");
  for (const auto& [name, line] : io) {
    parts.push_back(name);
  }
  out += fmt::format(
      "{}Slave a sf:EtherCATSlave ; rdfs:label \"ET1100 slave\" ; sf:model \"smart controller slave\" ;\n"
      "  sf:stationAddress \"4097\"^^xsd:unsignedShort ; sf:inputCount \"{}\"^^xsd:int ; "
      "sf:outputCount \"{}\"^^xsd:int ;\n  sf:hasComponent {} .\n",
      m, kSmartIo, kSmartIo, turtle_list(parts));
  for (unsigned a = 1; a <= kSmartAxes; ++a) {
    std::string travel;
    if (a <= kArmAxes) {
      const auto& limit = r.scara.limits[a - 1];
      const double scale = a - 1 == kZAxis ? 1000.0 : 180.0 / std::numbers::pi;
      // To a tenth, rounded outwards: every position the arm may take is inside (the rule
      // axisTravel compares live positions to these), a rounding error past it too.
      travel = fmt::format(" ; sf:minPosition {} ; sf:maxPosition {}",
                           turtle_number(std::floor(limit.min * scale * 10 + 1e-6) / 10),
                           turtle_number(std::ceil(limit.max * scale * 10 - 1e-6) / 10));
    }
    out += fmt::format("{}Axis{} a sf:ServoAxis ; sf:axisIndex \"{}\"^^xsd:int{} .\n", m, a, a, travel);
  }
  for (const auto& [name, line] : io) {
    out += fmt::format("{} {} .\n", name, line);
  }
}

void robots(std::string& out, const Layout& layout) {
  out += "\n# --- Robots: smart (§VII.A) and legacy behind gateways (§VII.B) ---------------------------\n";
  for (const auto& r : layout.robots) {
    const std::string m = p(r.name);
    const char* type = r.kind == RobotKind::legacy_articulated ? "sf:ArticulatedRobot" : "sf:ScaraRobot";
    // A legacy controller reports its drives' temperature (robot_controller::kTemperature).
    const std::string limit = r.legacy() ? fmt::format(" ;\n  sf:maxTemperature {}",
                                                       turtle_number(robot_controller::kMaxTemperature))
                                         : "";
    out += fmt::format(
        "\n{} a {} , owl:NamedIndividual ; rdfs:label {} ;\n  sf:manufacturer {} ; sf:model {} ; "
        "sf:canPerform {} ;\n  sf:controlledBy {}Controller ; sf:hasComponent {}Controller{} .\n",
        m, type, literal(r.label), literal(r.vendor), literal(r.model), capabilities(r.capabilities), m, m,
        limit);
    if (r.legacy()) {
      legacy_controller(out, m, r.label, r.controller, "robot controller");
    } else {
      smart_robot(out, r);
    }
  }
}

void transfer(std::string& out, const Layout& layout, const TransferSpec& t, const char* type) {
  const std::string m = p(t.name);
  const auto at = find_station(layout, t.station);
  out += fmt::format(
      "\n{} a {} , owl:NamedIndividual ; rdfs:label {} ;\n  sf:manufacturer {} ; sf:canPerform {} ;\n"
      "  sf:controlledBy {}Controller ; sf:hasComponent {}Controller ; sf:connectedTo {} .\n",
      m, type, literal(t.label), literal(t.plc.vendor), capabilities(t.capabilities), m, m,
      at ? p(layout.belts[at->belt].name) : std::string("sf:Conveyor"));
  legacy_controller(out, m, t.label, t.plc, "PLC");
}

void conveyors(std::string& out, const Layout& layout) {
  out += "\n# --- Conveyors on Siemens PLCs, and where they lead --------------------------------------\n";
  for (const auto& b : layout.belts) {
    const std::string m = p(b.name);
    std::vector<std::string> next;
    for (const auto& n : b.next) {
      next.push_back(p(n));
    }
    out += fmt::format(
        "\n{} a sf:Conveyor , owl:NamedIndividual ; rdfs:label {} ;\n  sf:canPerform {} ; sf:length {} ; "
        "sf:maxSpeed {} ;\n  sf:controlledBy {}Controller ; sf:hasComponent {}Controller{} .\n",
        m, literal(b.label), capabilities(b.capabilities),
        turtle_number(std::round(b.length() * 1000) / 1000), turtle_number(b.max_speed_mps), m, m,
        next.empty() ? "" : fmt::format(" ;\n  sf:connectedTo {}", turtle_list(next)));
    legacy_controller(out, m, b.label, b.plc, "PLC");
  }
}

}  // namespace

std::string iri_name(std::string_view name) {
  std::string out;
  bool upper = true;
  for (char c : name) {
    if (c == '-' || c == '_' || c == ' ' || c == '/') {
      upper = true;
      continue;
    }
    if (std::isalnum(static_cast<unsigned char>(c)) == 0) {
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  return out;
}

std::string line_turtle(const Layout& layout, std::string_view source) {
  std::string out = fmt::format(
      "# The line \"{}\" as individuals of ontology/candy-factory.ttl, generated from {} by\n"
      "# `smartfactory plant ontology`: edit the layout, not this file (a test checks they agree).\n"
      "# Live values (temperatures, states, positions) come on top, e.g. ontology/prototype-snapshot.ttl.\n",
      layout.label, source);
  out += fmt::format("@prefix sf:   <{}> .\n@prefix p:    <{}> .\n", kOntologyNamespace, kLineNamespace);
  out += "@prefix owl:  <http://www.w3.org/2002/07/owl#> .\n";
  out += "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n";
  out += "@prefix xsd:  <http://www.w3.org/2001/XMLSchema#> .\n";
  catalog(out, layout.catalog);
  std::vector<std::string> machines;
  for (const auto& r : layout.robots) {
    machines.push_back(p(r.name));
  }
  machines.push_back(p(layout.uploader.name));
  machines.push_back(p(layout.downloader.name));
  for (const auto& b : layout.belts) {
    machines.push_back(p(b.name));
  }
  out += fmt::format(
      "\n# --- The line ------------------------------------------------------------------------------\n\n"
      "p:Line a sf:ProductionLine , owl:NamedIndividual ; rdfs:label {} ;\n  sf:hasComponent {} .\n",
      literal(layout.label), turtle_list(machines));
  robots(out, layout);
  out += "\n# --- Box uploader and downloader on Mitsubishi PLCs ----------------------------------------\n";
  transfer(out, layout, layout.uploader, "sf:BoxUploader");
  transfer(out, layout, layout.downloader, "sf:BoxDownloader");
  conveyors(out, layout);
  return out;
}

}  // namespace sf::line
