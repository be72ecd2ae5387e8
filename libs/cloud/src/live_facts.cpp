// Shop-floor variables → live facts of the ontology (live_facts.hpp).
#include "live_facts.hpp"

#include <array>
#include <charconv>
#include <numbers>

#include <fmt/format.h>

namespace sf::cloud::detail {

namespace {

constexpr std::string_view kMachines = "/Objects/Machines/";
constexpr std::string_view kTags = "/Tags/";

// The kinds of quantity the ontology holds, each in one unit (ontology/candy-factory.ttl):
// sf:position in degrees (revolute axes) or millimetres (linear axes), sf:temperature in °C.
enum class Kind : std::uint8_t { angle, length, temperature };

// Units by their EngineeringUnits display name (UNECE Rec 20 symbols, as OPC 10000-8 §5.6.3
// publishes them): ontology value = published × scale + offset.
struct Unit {
  std::string_view symbol;
  Kind kind;
  double scale;
  double offset;
};
constexpr std::array kUnits = {
    Unit{"rad", Kind::angle, 180.0 / std::numbers::pi, 0.0},  // C81
    Unit{"°", Kind::angle, 1.0, 0.0},                         // DD
    Unit{"deg", Kind::angle, 1.0, 0.0},
    Unit{"m", Kind::length, 1000.0, 0.0},        // MTR
    Unit{"mm", Kind::length, 1.0, 0.0},          // MMT
    Unit{"°C", Kind::temperature, 1.0, 0.0},     // CEL
    Unit{"K", Kind::temperature, 1.0, -273.15},  // KEL
};

std::optional<double> number(const historian::Value& v) {
  if (const auto* d = std::get_if<double>(&v)) {
    return *d;
  }
  if (const auto* i = std::get_if<std::int64_t>(&v)) {
    return static_cast<double>(*i);
  }
  if (const auto* u = std::get_if<std::uint64_t>(&v)) {
    return static_cast<double>(*u);
  }
  return std::nullopt;
}

// "axis3.position" → 3.
std::optional<unsigned> axis_of(std::string_view tag) {
  constexpr std::string_view kAxis = "axis";
  constexpr std::string_view kPosition = ".position";
  if (!tag.starts_with(kAxis) || !tag.ends_with(kPosition)) {
    return std::nullopt;
  }
  const std::string_view digits = tag.substr(kAxis.size(), tag.size() - kAxis.size() - kPosition.size());
  unsigned n = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
  if (ec != std::errc{} || end != digits.data() + digits.size() || n == 0) {
    return std::nullopt;
  }
  return n;
}

bool is_temperature(std::string_view tag) {
  return tag == "temperature" || tag.ends_with(".temperature");
}

Result<double> convert(double v, std::string_view unit, std::initializer_list<Kind> kinds,
                       std::string_view what) {
  for (const Unit& u : kUnits) {
    if (u.symbol != unit) {
      continue;
    }
    for (const Kind k : kinds) {
      if (u.kind == k) {
        return v * u.scale + u.offset;
      }
    }
    return make_error(Errc::invalid_argument,
                      fmt::format("a {} in '{}' is not a unit of its kind", what, unit));
  }
  return make_error(Errc::invalid_argument, unit.empty()
                                                ? fmt::format("a {} without EngineeringUnits", what)
                                                : fmt::format("a {} in an unknown unit '{}'", what, unit));
}

}  // namespace

std::optional<std::string_view> machine_of(std::string_view path, std::string_view leaf) {
  const auto at = path.find(kMachines);
  if (at == std::string_view::npos || path.size() < leaf.size() + 1 || !path.ends_with(leaf) ||
      path[path.size() - leaf.size() - 1] != '/') {
    return std::nullopt;
  }
  auto machine = path.substr(at + kMachines.size());
  machine.remove_suffix(leaf.size() + 1);
  if (machine.empty() || machine.find('/') != std::string_view::npos) {
    return std::nullopt;
  }
  return machine;
}

std::optional<Result<LiveQuantity>> live_quantity(std::string_view browse_path, std::string_view unit,
                                                  const historian::Value& value) {
  const auto tags = browse_path.rfind(kTags);
  if (tags == std::string_view::npos) {
    return std::nullopt;
  }
  const std::string_view tag = browse_path.substr(tags + kTags.size());
  const auto machine = machine_of(browse_path.substr(0, tags + kTags.size() - 1), "Tags");
  const auto axis = axis_of(tag);
  if (!machine || (!axis && !is_temperature(tag))) {
    return std::nullopt;
  }
  const std::string_view what = axis ? "position" : "temperature";
  const auto v = number(value);
  if (!v) {
    return Result<LiveQuantity>(make_error(Errc::invalid_argument, fmt::format("a {} is a number", what)));
  }
  auto converted = axis ? convert(*v, unit, {Kind::angle, Kind::length}, what)
                        : convert(*v, unit, {Kind::temperature}, what);
  if (!converted) {
    return Result<LiveQuantity>(converted.error());
  }
  LiveQuantity q;
  q.individual = axis ? fmt::format("{}Axis{}", *machine, *axis) : std::string(*machine);
  q.property = what;
  q.value = *converted;
  return Result<LiveQuantity>(std::move(q));
}

}  // namespace sf::cloud::detail
