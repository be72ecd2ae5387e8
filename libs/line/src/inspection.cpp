// The inspection record's text form (inspection.hpp).
#include "sf/line/inspection.hpp"

#include <charconv>
#include <optional>

#include <fmt/format.h>

#include "sf/core/text.hpp"

namespace sf::line {

namespace {

constexpr std::size_t kMaxCandyTypes = 64;  // more than any catalog; bounds a malicious text

std::string counts_text(const std::map<std::string, int>& counts) {
  std::string out;
  for (const auto& [candy, n] : counts) {
    out += fmt::format("{}{}:{}", out.empty() ? "" : ",", candy, n);
  }
  return out;
}

Error bad(std::string_view token, std::string_view why) {
  return make_error(Errc::invalid_argument, fmt::format("inspection '{}': {}", token, why));
}

template <class T>
std::optional<T> number(std::string_view text) {
  T v{};
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || ptr != text.data() + text.size() || text.empty()) {
    return std::nullopt;
  }
  return v;
}

Result<std::map<std::string, int>> counts_of(std::string_view token, std::string_view text) {
  std::map<std::string, int> counts;
  for (auto item : split(text, ',')) {
    const auto colon = item.find(':');
    const auto n = colon == std::string_view::npos ? std::nullopt : number<int>(item.substr(colon + 1));
    if (!n || colon == 0 || *n < 0) {
      return bad(token, fmt::format("'{}' is not CANDY:COUNT", item));
    }
    if (!counts.emplace(std::string(item.substr(0, colon)), *n).second) {
      return bad(token, fmt::format("candy '{}' twice", item.substr(0, colon)));
    }
    if (counts.size() > kMaxCandyTypes) {
      return bad(token, fmt::format("more than {} candy types", kMaxCandyTypes));
    }
  }
  return counts;
}

Status set_field(InspectionRecord& r, std::string_view token, std::string_view key, std::string_view value) {
  if (key == "box") {
    auto n = number<std::uint32_t>(value);
    if (!n) {
      return bad(token, "the box is not a number");
    }
    r.box = *n;
  } else if (key == "type") {
    r.box_type = std::string(value);
  } else if (key == "ordered" || key == "counted") {
    auto counts = counts_of(token, value);
    if (!counts) {
      return counts.error();
    }
    (key == "ordered" ? r.ordered : r.counted) = std::move(*counts);
  } else if (key == "weight_g" || key == "lead_s") {
    auto v = number<double>(value);
    if (!v || !(*v >= 0.0)) {
      return bad(token, "not a number of zero or more");
    }
    (key == "weight_g" ? r.weight_g : r.lead_s) = *v;
  }
  return {};
}

}  // namespace

std::string format_inspection(const InspectionRecord& r) {
  return fmt::format("{} box={} type={} ordered={} counted={} weight_g={:.1f} lead_s={:.3f}", r.order, r.box,
                     r.box_type, counts_text(r.ordered), counts_text(r.counted), r.weight_g, r.lead_s);
}

Result<InspectionRecord> parse_inspection(std::string_view text) {
  auto tokens = split(trim(text), ' ');
  if (tokens.empty() || tokens.front().empty() || tokens.front().find('=') != std::string_view::npos) {
    return make_error(Errc::invalid_argument, "an inspection starts with the order id");
  }
  InspectionRecord r;
  r.order = std::string(tokens.front());
  bool box = false;
  bool type = false;
  bool ordered = false;
  for (std::size_t i = 1; i < tokens.size(); ++i) {
    const auto eq = tokens[i].find('=');
    if (eq == std::string_view::npos || eq == 0) {
      return bad(tokens[i], "not KEY=VALUE");
    }
    const auto key = tokens[i].substr(0, eq);
    SF_TRY(set_field(r, tokens[i], key, tokens[i].substr(eq + 1)));
    box = box || key == "box";
    type = type || key == "type";
    ordered = ordered || key == "ordered";
  }
  if (!box || !type || !ordered || r.box_type.empty() || r.ordered.empty()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("inspection of '{}': box=, type= and ordered= are required", r.order));
  }
  return r;
}

std::string format_order_step(const OrderStep& step) {
  std::string text = step.what + ' ' + (step.machine.empty() ? std::string("-") : step.machine);
  if (!step.detail.empty()) {
    text += ' ' + step.detail;
  }
  return text;
}

Result<OrderStep> parse_order_step(std::string_view text) {
  const auto first = text.find(' ');
  if (first == 0 || first == std::string_view::npos) {
    return make_error(Errc::malformed, fmt::format("order step '{}': expected '<what> <machine> <detail>'",
                                                   text.substr(0, 80)));
  }
  OrderStep step;
  step.what = std::string(text.substr(0, first));
  const std::string_view rest = text.substr(first + 1);
  const auto second = rest.find(' ');
  const std::string_view machine = rest.substr(0, second);
  if (machine.empty()) {
    return make_error(Errc::malformed,
                      fmt::format("order step '{}': no machine ('-' for none)", text.substr(0, 80)));
  }
  step.machine = machine == "-" ? std::string() : std::string(machine);
  if (second != std::string_view::npos) {
    step.detail = std::string(rest.substr(second + 1));
  }
  return step;
}

}  // namespace sf::line
