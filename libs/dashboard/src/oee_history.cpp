// Reading a machine's PackML series from the historian (oee_history.hpp).
#include "sf/dashboard/oee_history.hpp"

#include <cmath>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "sf/line/ontology.hpp"

namespace sf::dashboard {

namespace {

using historian::Sample;
using historian::SeriesId;
using historian::Store;

constexpr std::string_view kMachinesFolder = "/Objects/Machines/";
constexpr std::size_t kPage = 100'000;
// Where the search for the sample before a range gives up: no historian sample is older than
// the Unix epoch (the gateway maps OPC UA DateTimes before it to the minimum).
constexpr Timestamp kOldest{};
constexpr Micros kFirstLookBack = std::chrono::minutes{1};
// Counters are Int32 in the model; any whole number a double holds exactly (2^53) is taken.
constexpr double kLargestExactCount = 9'007'199'254'740'992.0;

// A whole number in [0, max] from a good sample, else nothing.
std::optional<std::uint64_t> whole(const Sample& s, double max) {
  if (historian::is_bad(s.status)) {
    return std::nullopt;
  }
  const auto v = historian::numeric(s.value);
  if (!v || !(*v >= 0.0 && *v <= max) || std::floor(*v) != *v) {
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(*v);
}

// The samples of [from, to), page by page (read_raw gives at most `limit`, oldest first).
Result<std::vector<Sample>> read_range(Store& store, SeriesId id, TimeRange range) {
  std::vector<Sample> out;
  Timestamp at = range.from;
  while (true) {
    auto page = store.read_raw(id, at, range.to, kPage);
    if (!page) {
      return page.error();
    }
    const bool full = page->size() == kPage;
    for (Sample& s : *page) {
      // A page starts again at the last time of the one before: skip what that one held.
      if (!out.empty() && s.source_time == out.back().source_time && s.seq <= out.back().seq) {
        continue;
      }
      out.push_back(std::move(s));
    }
    if (out.size() > kMaxSamplesPerSeries) {
      return make_error(Errc::limit_exceeded,
                        fmt::format("more than {} samples in the range: narrow it", kMaxSamplesPerSeries));
    }
    if (!full) {
      return out;
    }
    if (out.back().source_time == at) {
      return make_error(Errc::limit_exceeded,
                        fmt::format("more than {} samples share one source time", kPage));
    }
    at = out.back().source_time;
  }
}

// The newest sample before `t`: the latest one if it is older, else a look back over growing
// windows (the store has no "last before" query).
Result<std::optional<Sample>> last_before(Store& store, SeriesId id, Timestamp t) {
  auto latest = store.latest(id);
  if (!latest || !*latest || (*latest)->source_time < t) {
    return latest;
  }
  for (Micros back = kFirstLookBack;; back *= 4) {
    const Timestamp from = t - kOldest > back ? t - back : kOldest;
    auto window = read_range(store, id, {from, t});
    if (!window) {
      return window.error();
    }
    if (!window->empty()) {
      return std::optional(window->back());
    }
    if (from == kOldest) {
      return std::optional<Sample>{};
    }
  }
}

// The series' samples over the range, led by the last one before it.
Result<std::vector<Sample>> read_series(Store& store, SeriesId id, TimeRange range) {
  auto before = last_before(store, id, range.from);
  if (!before) {
    return before.error();
  }
  auto in_range = read_range(store, id, range);
  if (!in_range) {
    return in_range.error();
  }
  if (*before) {
    in_range->insert(in_range->begin(), **before);
  }
  return in_range;
}

std::vector<StateChange> states_of(const std::vector<Sample>& samples) {
  std::vector<StateChange> out;
  out.reserve(samples.size());
  for (const Sample& s : samples) {
    const auto n = whole(s, static_cast<double>(factory::kPackMLStates - 1));
    out.push_back({s.source_time, n ? std::optional(static_cast<factory::PackMLState>(*n)) : std::nullopt});
  }
  return out;
}

std::vector<ModeChange> modes_of(const std::vector<Sample>& samples) {
  std::vector<ModeChange> out;
  out.reserve(samples.size());
  for (const Sample& s : samples) {
    const auto n = whole(s, std::numeric_limits<std::int32_t>::max());
    const bool known = n && *n >= 1 && *n <= 3;  // PackMLMode; others follow the state (oee.hpp)
    out.push_back(
        {s.source_time, known ? std::optional(static_cast<factory::PackMLMode>(*n)) : std::nullopt});
  }
  return out;
}

std::vector<CounterSample> counters_of(const std::vector<Sample>& samples) {
  std::vector<CounterSample> out;
  out.reserve(samples.size());
  for (const Sample& s : samples) {
    if (auto n = whole(s, kLargestExactCount)) {
      out.push_back({s.source_time, *n});
    }
  }
  return out;
}

// The series with this browse path; nullopt when there is none.
Result<std::optional<SeriesId>> series_of(const std::vector<historian::Series>& all,
                                          const std::string& path) {
  std::optional<SeriesId> found;
  std::vector<std::string> servers;
  for (const auto& s : all) {
    if (s.info.browse_path == path) {
      found = s.id;
      servers.push_back(s.info.server);
    }
  }
  if (servers.size() > 1) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{} is a series of several servers: {}", path, fmt::join(servers, ", ")));
  }
  return found;
}

template <typename Out, typename Convert>
Status read_into(Store& store, const std::vector<historian::Series>& all, std::string_view machine,
                 std::string_view variable, TimeRange range, Out& out, Convert convert) {
  auto id = series_of(all, machine_series_path(machine, variable));
  if (!id) {
    return id.error();
  }
  if (!*id) {
    return {};
  }
  auto samples = read_series(store, **id, range);
  if (!samples) {
    return samples.error().with_context(machine_series_path(machine, variable));
  }
  out = convert(*samples);
  return {};
}

Result<std::vector<MachineHistory>> read_histories(Store& store, const std::vector<std::string>& machines,
                                                   TimeRange range) {
  std::vector<std::string> names = machines;
  if (names.empty()) {
    auto found = oee_machines(store);
    if (!found) {
      return found.error();
    }
    names = std::move(*found);
  }
  std::vector<MachineHistory> out;
  out.reserve(names.size());
  for (const std::string& name : names) {
    auto h = read_machine_history(store, name, range);
    if (!h) {
      return h.error();
    }
    out.push_back(std::move(*h));
  }
  return out;
}

}  // namespace

std::string machine_series_path(std::string_view machine, std::string_view variable) {
  return fmt::format("{}{}/{}", kMachinesFolder, line::iri_name(machine), variable);
}

Result<std::vector<std::string>> oee_machines(Store& store) {
  auto all = store.list_series();
  if (!all) {
    return all.error();
  }
  const std::string suffix = fmt::format("/{}", kStateCurrent);
  std::set<std::string> names;
  for (const auto& s : *all) {
    std::string_view path = s.info.browse_path;
    if (!path.starts_with(kMachinesFolder) || !path.ends_with(suffix)) {
      continue;
    }
    path.remove_prefix(kMachinesFolder.size());
    path.remove_suffix(suffix.size());
    if (!path.empty() && path.find('/') == std::string_view::npos) {
      names.emplace(path);
    }
  }
  return std::vector<std::string>(names.begin(), names.end());
}

Result<MachineHistory> read_machine_history(Store& store, std::string_view machine, TimeRange range) {
  auto all = store.list_series();
  if (!all) {
    return all.error();
  }
  MachineHistory h;
  h.machine = line::iri_name(machine);
  auto state = series_of(*all, machine_series_path(machine, kStateCurrent));
  if (!state) {
    return state.error();
  }
  if (!*state) {
    return make_error(Errc::not_found, fmt::format("no series {} in the historian",
                                                   machine_series_path(machine, kStateCurrent)));
  }
  SF_TRY(read_into(store, *all, machine, kStateCurrent, range, h.states, states_of));
  SF_TRY(read_into(store, *all, machine, kUnitModeCurrent, range, h.modes, modes_of));
  SF_TRY(read_into(store, *all, machine, kProdProcessedCount, range, h.processed, counters_of));
  SF_TRY(read_into(store, *all, machine, kProdDefectiveCount, range, h.defective, counters_of));
  return h;
}

Result<MachineOee> machine_oee(Store& store, std::string_view machine, TimeRange range,
                               const IdealCycleTimes& ideal) {
  auto h = read_machine_history(store, machine, range);
  if (!h) {
    return h.error();
  }
  return machine_oee(*h, range, ideal_cycle_of(ideal, machine));
}

Result<std::vector<MachineOee>> machine_oee_trend(Store& store, std::string_view machine, TimeRange range,
                                                  Micros bucket, const IdealCycleTimes& ideal) {
  SF_TRY(buckets(range, bucket));  // a bad request fails before anything is read
  auto h = read_machine_history(store, machine, range);
  if (!h) {
    return h.error();
  }
  return machine_oee_trend(*h, range, bucket, ideal_cycle_of(ideal, machine));
}

Result<LineOee> line_oee(Store& store, const std::vector<std::string>& machines, TimeRange range,
                         const IdealCycleTimes& ideal, std::string_view constraint) {
  auto histories = read_histories(store, machines, range);
  if (!histories) {
    return histories.error();
  }
  std::vector<MachineOee> each;
  each.reserve(histories->size());
  for (const MachineHistory& h : *histories) {
    each.push_back(machine_oee(h, range, ideal_cycle_of(ideal, h.machine)));
  }
  auto line = line_oee(std::move(each), constraint);
  if (line) {
    line->range = range;
  }
  return line;
}

Result<std::vector<LineOee>> line_oee_trend(Store& store, const std::vector<std::string>& machines,
                                            TimeRange range, Micros bucket, const IdealCycleTimes& ideal,
                                            std::string_view constraint) {
  SF_TRY(buckets(range, bucket));
  auto histories = read_histories(store, machines, range);
  if (!histories) {
    return histories.error();
  }
  return line_oee_trend(*histories, range, bucket, ideal, constraint);
}

}  // namespace sf::dashboard
