#include "sf/plant/faults.hpp"

#include <charconv>
#include <vector>

#include <fmt/format.h>

#include "sf/core/text.hpp"

namespace sf::plant {

namespace {

constexpr FaultKind kKinds[] = {
    FaultKind::jam,           FaultKind::dispenser_empty, FaultKind::mixup,
    FaultKind::axis_fault,    FaultKind::cable_cut,       FaultKind::plc_unreachable,
    FaultKind::plc_exception, FaultKind::overheat,        FaultKind::box_drop};
constexpr std::uint16_t kDefaultAxisError = 0x7310;  // CiA 301/402: speed (overspeed)
constexpr std::uint32_t kDefaultException = 4;       // MB AP §7: server device failure

Result<std::uint32_t> number(std::string_view text, std::string_view what, std::uint32_t max) {
  std::uint32_t v = 0;
  int base = 10;
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
    text.remove_prefix(2);
    base = 16;
  }
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v, base);
  if (ec != std::errc{} || ptr != text.data() + text.size() || text.empty() || v > max) {
    return make_error(Errc::invalid_argument,
                      fmt::format("fault {} '{}' is not a number 0..{}", what, text, max));
  }
  return v;
}

}  // namespace

std::string_view to_string(FaultKind kind) {
  switch (kind) {
    case FaultKind::jam:
      return "jam";
    case FaultKind::dispenser_empty:
      return "dispenser-empty";
    case FaultKind::mixup:
      return "mixup";
    case FaultKind::axis_fault:
      return "axis-fault";
    case FaultKind::cable_cut:
      return "cable-cut";
    case FaultKind::plc_unreachable:
      return "plc-unreachable";
    case FaultKind::plc_exception:
      return "plc-exception";
    case FaultKind::overheat:
      return "overheat";
    case FaultKind::box_drop:
      return "box-drop";
  }
  return "?";
}

Result<FaultSpec> parse_fault(std::string_view text) {
  auto parts = split(text, ':');
  if (parts.empty()) {
    parts.emplace_back();  // empty text: an unknown (empty) fault kind
  }
  FaultSpec fault;
  bool known = false;
  for (FaultKind k : kKinds) {
    if (parts[0] == to_string(k)) {
      fault.kind = k;
      known = true;
    }
  }
  if (!known) {
    std::string names;
    for (FaultKind k : kKinds) {
      names += fmt::format("{}{}", names.empty() ? "" : ", ", to_string(k));
    }
    return make_error(Errc::invalid_argument, fmt::format("unknown fault '{}' (known: {})", parts[0], names));
  }
  if (parts.size() < 2 || parts[1].empty()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("fault '{}' needs a target: {}:NAME", text, parts[0]));
  }
  fault.target = std::string(parts[1]);
  const std::size_t max_parts = fault.kind == FaultKind::axis_fault      ? 4
                                : fault.kind == FaultKind::plc_exception ? 3
                                                                         : 2;
  if (parts.size() > max_parts) {
    return make_error(Errc::invalid_argument, fmt::format("fault '{}' has too many parts", text));
  }
  if (fault.kind == FaultKind::axis_fault) {
    if (parts.size() < 3) {
      return make_error(Errc::invalid_argument,
                        fmt::format("fault '{}' needs an axis: axis-fault:ROBOT:AXIS", text));
    }
    auto axis = number(parts[2], "axis", 7);
    if (!axis) {
      return axis.error();
    }
    fault.argument = *axis;
    fault.code = kDefaultAxisError;
    if (parts.size() == 4) {
      auto code = number(parts[3], "error code", 0xFFFF);
      if (!code) {
        return code.error();
      }
      fault.code = static_cast<std::uint16_t>(*code);
    }
  }
  if (fault.kind == FaultKind::plc_exception) {
    fault.argument = kDefaultException;
    if (parts.size() == 3) {
      auto code = number(parts[2], "exception code", 0xFF);
      if (!code) {
        return code.error();
      }
      fault.argument = *code;
    }
  }
  if (fault.kind == FaultKind::box_drop) {
    auto id = number(parts[1], "box", 0xFFFFFFFF);
    if (!id) {
      return id.error();
    }
  }
  return fault;
}

std::string format(const FaultSpec& f) {
  switch (f.kind) {
    case FaultKind::axis_fault:
      return fmt::format("{}:{}:{}:0x{:04X}", to_string(f.kind), f.target, f.argument, f.code);
    case FaultKind::plc_exception:
      return fmt::format("{}:{}:{}", to_string(f.kind), f.target, f.argument);
    default:
      return fmt::format("{}:{}", to_string(f.kind), f.target);
  }
}

}  // namespace sf::plant
