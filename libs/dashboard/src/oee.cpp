// OEE from PackML states and Admin counters (oee.hpp).
#include "sf/dashboard/oee.hpp"

#include <algorithm>
#include <tuple>

#include <fmt/format.h>

#include "sf/line/ontology.hpp"

namespace sf::dashboard {

namespace {

using factory::PackMLMode;
using factory::PackMLState;

// The entry in force at `t`: the last with time <= t, or nullptr.
template <typename Change>
const Change* in_force(const std::vector<Change>& changes, Timestamp t) {
  auto after = std::upper_bound(changes.begin(), changes.end(), t,
                                [](Timestamp at, const Change& c) { return at < c.time; });
  return after == changes.begin() ? nullptr : &*std::prev(after);
}

// The first change after `t` of either series, or `to`.
template <typename Change>
Timestamp next_change(const std::vector<Change>& changes, Timestamp t, Timestamp to) {
  auto after = std::upper_bound(changes.begin(), changes.end(), t,
                                [](Timestamp at, const Change& c) { return at < c.time; });
  return after == changes.end() ? to : std::min(after->time, to);
}

std::optional<PackMLState> state_at(const MachineHistory& h, Timestamp t) {
  const StateChange* c = in_force(h.states, t);
  return c == nullptr ? std::nullopt : c->state;
}

// No mode data: the default mode (Production); a machine publishes its mode with its state.
std::optional<PackMLMode> mode_at(const MachineHistory& h, Timestamp t) {
  if (h.modes.empty()) {
    return PackMLMode::Production;
  }
  const ModeChange* c = in_force(h.modes, t);
  return c == nullptr ? std::optional(PackMLMode::Production) : c->mode;
}

void add_time(MachineOee& out, std::optional<PackMLState> state, std::optional<PackMLMode> mode, Micros d) {
  const TimeElement element = time_element(state, mode);
  if (element == TimeElement::unknown) {
    out.unknown_time += d;
    return;
  }
  out.time_in_state[static_cast<std::size_t>(*state)] += d;
  switch (element) {
    case TimeElement::production:
      out.actual_production_time += d;
      out.planned_busy_time += d;
      break;
    case TimeElement::busy_not_producing:
      out.busy_not_producing += d;
      out.planned_busy_time += d;
      break;
    case TimeElement::planned_downtime:
      out.planned_downtime += d;
      break;
    case TimeElement::unknown:
      break;
  }
}

// Walks the range segment by segment between state and mode changes.
void state_times(const MachineHistory& h, TimeRange range, MachineOee& out) {
  Timestamp at = range.from;
  while (at < range.to) {
    const Timestamp end = std::min(next_change(h.states, at, range.to), next_change(h.modes, at, range.to));
    add_time(out, state_at(h, at), mode_at(h, at), end - at);
    at = end;
  }
}

std::optional<double> ratio(double numerator, double denominator) {
  return denominator > 0.0 ? std::optional(numerator / denominator) : std::nullopt;
}

double seconds(Micros d) {
  return std::chrono::duration<double>(d).count();
}

void quantities(const MachineHistory& h, TimeRange range, MachineOee& out) {
  out.produced = counter_increments(h.processed, range);
  if (!out.produced) {
    return;
  }
  // A machine that never counted a defective product may not have published the counter yet.
  out.defective = counter_increments(h.defective, range).value_or(0);
  out.good = *out.produced - std::min(*out.produced, *out.defective);
}

// ISO 22400-2: availability, effectiveness (performance), quality ratio and the OEE index.
void kpis(MachineOee& out) {
  out.availability = ratio(seconds(out.actual_production_time), seconds(out.planned_busy_time));
  if (out.produced && out.ideal_cycle_s && *out.ideal_cycle_s > 0.0) {
    out.performance_measured =
        ratio(*out.ideal_cycle_s * static_cast<double>(*out.produced), seconds(out.actual_production_time));
  }
  if (out.performance_measured) {
    out.performance = std::min(*out.performance_measured, kPerformanceLimit);
  }
  if (out.produced) {
    out.quality = ratio(static_cast<double>(*out.good), static_cast<double>(*out.produced));
  }
  const auto zero = [](const std::optional<double>& f) { return f && *f == 0.0; };
  if (out.availability && out.performance && out.quality) {
    out.oee = *out.availability * *out.performance * *out.quality;
  } else if (zero(out.availability) || zero(out.performance)) {
    out.oee = 0.0;
  }
}

}  // namespace

std::string_view to_string(TimeElement element) {
  switch (element) {
    case TimeElement::production:
      return "production";
    case TimeElement::busy_not_producing:
      return "busy_not_producing";
    case TimeElement::planned_downtime:
      return "planned_downtime";
    case TimeElement::unknown:
      return "unknown";
  }
  return "unknown";
}

TimeElement time_element(std::optional<PackMLState> state, std::optional<PackMLMode> mode) {
  if (!state || *state == PackMLState::Undefined) {
    return TimeElement::unknown;
  }
  if (mode == PackMLMode::Maintenance) {
    return TimeElement::planned_downtime;  // OPC 30050 §6.5.2, OPC 30060 §11.8: planned maintenance
  }
  switch (*state) {
    case PackMLState::Execute:
      return mode == PackMLMode::Manual ? TimeElement::busy_not_producing : TimeElement::production;
    case PackMLState::Stopped:
    case PackMLState::Idle:
    case PackMLState::Complete:
      return mode == PackMLMode::Manual ? TimeElement::busy_not_producing : TimeElement::planned_downtime;
    default:
      return TimeElement::busy_not_producing;
  }
}

std::optional<std::uint64_t> counter_increments(const std::vector<CounterSample>& samples, TimeRange range) {
  auto first = std::lower_bound(samples.begin(), samples.end(), range.from,
                                [](const CounterSample& s, Timestamp t) { return s.time < t; });
  auto end = std::lower_bound(first, samples.end(), range.to,
                              [](const CounterSample& s, Timestamp t) { return s.time < t; });
  if (first == samples.begin() && first == end) {
    return std::nullopt;  // nothing before the range and nothing in it
  }
  std::uint64_t total = 0;
  auto previous = first == samples.begin() ? first++ : std::prev(first);
  for (auto it = first; it != end; previous = it++) {
    total += it->value >= previous->value ? it->value - previous->value : it->value;
  }
  return total;
}

MachineOee machine_oee(const MachineHistory& history, TimeRange range, std::optional<double> ideal_cycle_s) {
  MachineOee out;
  out.machine = history.machine;
  out.range = range;
  out.ideal_cycle_s = ideal_cycle_s;
  if (range.to <= range.from) {
    return out;
  }
  state_times(history, range, out);
  out.no_data = out.unknown_time == range.length();
  if (out.no_data) {
    out.unknown_time = Micros{0};
    return out;
  }
  quantities(history, range, out);
  kpis(out);
  return out;
}

IdealCycleTimes ideal_cycle_times(const line::Layout& layout) {
  IdealCycleTimes out;
  for (const line::TransferSpec* t : {&layout.uploader, &layout.downloader}) {
    if (!t->name.empty() && t->cycle_s > 0.0) {
      out[line::iri_name(t->name)] = t->cycle_s;
    }
  }
  return out;
}

std::optional<double> ideal_cycle_of(const IdealCycleTimes& ideal, std::string_view machine) {
  const auto it = ideal.find(line::iri_name(machine));
  return it == ideal.end() ? std::nullopt : std::optional(it->second);
}

Result<LineOee> line_oee(std::vector<MachineOee> machines, std::string_view constraint) {
  LineOee out;
  out.machines = std::move(machines);
  const MachineOee* pick = nullptr;
  for (const MachineOee& m : out.machines) {
    if (!constraint.empty()) {
      if (line::iri_name(m.machine) == line::iri_name(constraint)) {
        pick = &m;
      }
      continue;
    }
    if (!m.ideal_cycle_s) {
      continue;
    }
    const bool slower = pick == nullptr || *m.ideal_cycle_s > *pick->ideal_cycle_s;
    const bool tie_worse = pick != nullptr && *m.ideal_cycle_s == *pick->ideal_cycle_s &&
                           m.oee.value_or(2.0) < pick->oee.value_or(2.0);
    if (slower || tie_worse) {
      pick = &m;
    }
  }
  if (!constraint.empty() && pick == nullptr) {
    return make_error(Errc::not_found,
                      fmt::format("the constraint '{}' is none of the line's machines", constraint));
  }
  if (!out.machines.empty()) {
    out.range = out.machines.front().range;
  }
  if (pick != nullptr) {
    out.constraint = pick->machine;
    std::tie(out.availability, out.performance, out.quality, out.oee) =
        std::tie(pick->availability, pick->performance, pick->quality, pick->oee);
  }
  return out;
}

Result<std::vector<TimeRange>> buckets(TimeRange range, Micros bucket) {
  if (range.to <= range.from) {
    return make_error(Errc::invalid_argument, "the range is empty (from must be before to)");
  }
  if (bucket <= Micros{0}) {
    return make_error(Errc::invalid_argument, "the bucket must be longer than 0");
  }
  const auto count = (range.length() + bucket - Micros{1}) / bucket;
  if (count > static_cast<std::int64_t>(kMaxBuckets)) {
    return make_error(Errc::limit_exceeded,
                      fmt::format("{} buckets, more than the {} allowed", count, kMaxBuckets));
  }
  std::vector<TimeRange> out;
  out.reserve(static_cast<std::size_t>(count));
  for (Timestamp at = range.from; at < range.to; at += bucket) {
    out.push_back({at, std::min(at + bucket, range.to)});
  }
  return out;
}

Result<std::vector<MachineOee>> machine_oee_trend(const MachineHistory& history, TimeRange range,
                                                  Micros bucket, std::optional<double> ideal_cycle_s) {
  auto ranges = buckets(range, bucket);
  if (!ranges) {
    return ranges.error();
  }
  std::vector<MachineOee> out;
  out.reserve(ranges->size());
  for (const TimeRange& r : *ranges) {
    out.push_back(machine_oee(history, r, ideal_cycle_s));
  }
  return out;
}

Result<std::vector<LineOee>> line_oee_trend(const std::vector<MachineHistory>& histories, TimeRange range,
                                            Micros bucket, const IdealCycleTimes& ideal,
                                            std::string_view constraint) {
  auto ranges = buckets(range, bucket);
  if (!ranges) {
    return ranges.error();
  }
  std::vector<LineOee> out;
  out.reserve(ranges->size());
  for (const TimeRange& r : *ranges) {
    std::vector<MachineOee> machines;
    machines.reserve(histories.size());
    for (const MachineHistory& h : histories) {
      machines.push_back(machine_oee(h, r, ideal_cycle_of(ideal, h.machine)));
    }
    auto line = line_oee(std::move(machines), constraint);
    if (!line) {
      return line.error();
    }
    line->range = r;
    out.push_back(std::move(*line));
  }
  return out;
}

}  // namespace sf::dashboard
