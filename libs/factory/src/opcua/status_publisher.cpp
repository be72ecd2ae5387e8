// StatusPublisher (machine_model.hpp): a controller's status as the values of its OPC UA model,
// and only what changed since the last publication.
#include <algorithm>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "opcua/model_layout.hpp"
#include "sf/factory/machine_model.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::factory {

namespace ua = sf::opcua;
using S = PackMLState;

namespace model {

NestedStates nested_states(PackMLState state) {
  switch (state) {
    case S::Aborting:
    case S::Aborted:
      return {to_string(state), "", ""};
    case S::Clearing:
    case S::Stopped:
    case S::Stopping:
      return {"Cleared", to_string(state), ""};
    case S::Undefined:
      return {"", "", ""};
    default:
      return {"Cleared", "Running", to_string(state)};
  }
}

}  // namespace model

ua::StatusCode status_of(Tag::Quality quality) {
  switch (quality) {
    case Tag::Quality::good:
      return ua::StatusCode{};
    case Tag::Quality::uncertain:
      return ua::status::UncertainLastUsableValue;  // OPC 10000-8 §6.3.2 (Part 4 §7.39)
    case Tag::Quality::bad:
      return ua::status::BadNoCommunication;
  }
  return ua::status::BadNoCommunication;
}

namespace {

std::int32_t count32(std::uint64_t count) {
  return static_cast<std::int32_t>(std::min<std::uint64_t>(count, std::numeric_limits<std::int32_t>::max()));
}

// Milliseconds (Duration, OPC 10000-3 §8.13) rounded down to whole steps of `resolution`.
double duration_ms(std::chrono::nanoseconds d, std::chrono::milliseconds resolution) {
  const auto step = std::max<std::int64_t>(resolution.count(), 1);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
  return static_cast<double>(ms - ms % step);
}

ua::Variant tag_variant(const Tag& tag) {
  return std::visit([](const auto& v) { return ua::Variant(v); }, tag.value);
}

// "box=1, candy=3, count=2" in the order of the names.
std::string parameters_text(const std::optional<Operation>& op) {
  std::string text;
  if (!op) {
    return text;
  }
  for (const auto& [name, value] : op->params) {
    text += fmt::format("{}{}={}", text.empty() ? "" : ", ", name, value);
  }
  return text;
}

ua::LocalizedText state_text(std::string_view name) {
  return {ua::String(), ua::String(name)};
}

}  // namespace

std::vector<ModelValue> StatusPublisher::values(const ControllerStatus& status, Clock::utc_time utc) {
  const PackMLStatus& p = status.packml;
  std::vector<double> cumulative;
  cumulative.reserve(p.time_in_state.size());
  for (const auto& t : p.time_in_state) {
    cumulative.push_back(duration_ms(t, resolution_));
  }
  const StopReason none{};
  const StopReason& why = p.stop_reason ? *p.stop_reason : none;
  const auto nested = model::nested_states(p.state);
  const std::pair<std::string_view, ua::Variant> fixed[] = {
      {"PackML.Status.StateCurrent", static_cast<std::int32_t>(p.state)},
      {"PackML.Status.UnitModeCurrent", static_cast<std::int32_t>(p.mode)},
      {"PackML.Admin.ProdProcessedCount", count32(p.produced)},
      {"PackML.Admin.ProdDefectiveCount", count32(p.defective)},
      {"PackML.Admin.StateCurrentTime", duration_ms(p.state_current_time, resolution_)},
      {"PackML.Admin.StateCumulativeTime", ua::Variant(std::move(cumulative))},
      {"PackML.Admin.StopReason.ID", why.id},
      {"PackML.Admin.StopReason.Message", why.message},
      {"PackML.Admin.StopReason.DateTime",
       p.stop_reason ? ua::DateTime::from_system_clock(why.at) : ua::DateTime::min()},
      {"PackML.BaseStateMachine.CurrentState", state_text(nested.base)},
      {"PackML.BaseStateMachine.MachineState.CurrentState", state_text(nested.machine)},
      {"PackML.BaseStateMachine.MachineState.ExecuteState.CurrentState", state_text(nested.execute)},
      {"Job.JobId", status.job.value_or("")},
      {"Job.Operation", status.operation ? status.operation->type : std::string()},
      {"Job.Parameters", parameters_text(status.operation)},
      {"Job.Queued", status.queued},
      {"Job.WorkingTime", duration_ms(status.working_time, resolution_)},
      {"Fault", status.fault},
  };
  static_assert(sizeof(fixed) / sizeof(fixed[0]) == model::kVariables.size(), "a value for every variable");
  const auto stamp = ua::DateTime::from_system_clock(utc);
  std::vector<ModelValue> out;
  out.reserve(std::size(fixed) + 2 * status.tags.size());
  auto add = [&](ModelValue::Kind kind, std::string name, ua::Variant value, ua::StatusCode code = {}) {
    ua::DataValue dv(std::move(value));
    dv.status = code;
    dv.source_timestamp = stamp;
    out.push_back({kind, std::move(name), std::move(dv)});
  };
  for (const auto& [path, value] : fixed) {
    add(ModelValue::Kind::fixed, std::string(path), value);
  }
  for (const Tag& tag : status.tags) {
    add(ModelValue::Kind::tag, tag.name, tag_variant(tag), status_of(tag.quality));
    out.back().unit = tag.unit;
    add(ModelValue::Kind::tag_reason, tag.name,
        tag.quality == Tag::Quality::good ? std::string() : tag.reason);
  }
  return out;
}

std::vector<ModelValue> StatusPublisher::changes(const ControllerStatus& status, Clock::utc_time utc) {
  std::vector<ModelValue> changed;
  std::set<std::pair<ModelValue::Kind, std::string>> seen;
  for (ModelValue& v : values(status, utc)) {
    auto key = std::make_pair(v.kind, v.name);
    seen.insert(key);
    auto [it, added] = last_.try_emplace(std::move(key), v.value);
    if (!added && it->second.value == v.value.value && it->second.status == v.value.status) {
      continue;
    }
    it->second = v.value;
    changed.push_back(std::move(v));
  }
  for (auto it = last_.begin(); it != last_.end();) {
    if (seen.contains(it->first)) {
      ++it;
      continue;
    }
    if (it->first.first == ModelValue::Kind::tag) {
      ua::DataValue gone;
      gone.status = ua::status::BadNotFound;
      gone.source_timestamp = ua::DateTime::from_system_clock(utc);
      changed.push_back({ModelValue::Kind::tag, it->first.second, std::move(gone)});
    }
    it = last_.erase(it);
  }
  return changed;
}

}  // namespace sf::factory
