#include "server/subscriptions/data_change.hpp"

#include <cmath>
#include <cstddef>
#include <type_traits>
#include <variant>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::subs {
namespace {

template <typename T>
inline constexpr bool kNumber = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

// Element `index` of a numeric scalar (index 0) or array as double; nullopt when not numeric.
std::optional<double> number_at(const Variant& v, std::size_t index) {
  return std::visit(
      [index](const auto& x) -> std::optional<double> {
        using T = std::decay_t<decltype(x)>;
        if constexpr (kNumber<T>) {
          return static_cast<double>(x);
        } else if constexpr (IsArray<T>::value) {
          if constexpr (kNumber<typename IsArray<T>::Element>) {
            if (index < x.size()) {
              return static_cast<double>(x[index]);
            }
          }
          return std::nullopt;
        } else {
          return std::nullopt;
        }
      },
      v.storage());
}

bool both_nan(const Variant& a, const Variant& b) {
  const auto x = number_at(a, 0);
  const auto y = number_at(b, 0);
  return a.is_scalar() && b.is_scalar() && x && y && std::isnan(*x) && std::isnan(*y);
}

// §7.17.2: "the entire array is returned if any array element exceeds the deadband, or the
// size or dimension of the array changes"; a change of type is always reported.
bool exceeds_deadband(const Variant& last, const Variant& current, double threshold) {
  if (last.storage().index() != current.storage().index() ||
      last.array_dimensions() != current.array_dimensions() ||
      last.array_length() != current.array_length()) {
    return true;
  }
  for (std::size_t i = 0; i < current.array_length(); ++i) {
    const auto a = number_at(last, i);
    const auto b = number_at(current, i);
    if (!a || !b) {
      return !same_value(last, current);
    }
    if (std::isnan(*a) != std::isnan(*b) || std::fabs(*a - *b) > threshold) {
      return true;
    }
  }
  return false;
}

bool value_changed(const DataChangeSettings& s, const Variant& last, const Variant& current) {
  switch (s.deadband_type) {
    case DeadbandType::Absolute:
      return exceeds_deadband(last, current, s.deadband_value);
    case DeadbandType::Percent:
      return exceeds_deadband(last, current, s.deadband_value / 100.0 * s.eu_span);
    default:
      return !same_value(last, current);
  }
}

}  // namespace

bool is_numeric(const Variant& value) {
  return std::visit(
      [](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (IsArray<T>::value) {
          return kNumber<typename IsArray<T>::Element>;
        } else {
          return kNumber<T>;
        }
      },
      value.storage());
}

bool same_value(const Variant& a, const Variant& b) {
  return a == b || both_nan(a, b);
}

DataChangeCheck check_data_change_filter(const DataChangeFilter& filter, const Variant& value,
                                         const std::optional<Range>& eu_range) {
  DataChangeCheck out;
  const auto trigger = static_cast<std::int32_t>(filter.trigger);
  if (trigger < 0 || trigger > static_cast<std::int32_t>(DataChangeTrigger::StatusValueTimestamp)) {
    out.status = status::BadMonitoredItemFilterInvalid;
    return out;
  }
  out.settings.trigger = filter.trigger;
  const double dv = filter.deadband_value;
  if (filter.deadband_type > static_cast<std::uint32_t>(DeadbandType::Percent)) {
    out.status = status::BadDeadbandFilterInvalid;
    return out;
  }
  out.settings.deadband_type = static_cast<DeadbandType>(filter.deadband_type);
  if (out.settings.deadband_type == DeadbandType::None) {
    return out;
  }
  if (!(dv >= 0) || (out.settings.deadband_type == DeadbandType::Percent && dv > 100)) {
    out.status = status::BadDeadbandFilterInvalid;
    return out;
  }
  // §7.17.2: deadbands apply to numeric values only. A Null value (no sample yet) cannot be
  // judged and is accepted.
  if (!value.is_empty() && !is_numeric(value)) {
    out.status = status::BadFilterNotAllowed;
    return out;
  }
  out.settings.deadband_value = dv;
  if (out.settings.deadband_type == DeadbandType::Percent) {
    if (!eu_range) {
      out.status = status::BadMonitoredItemFilterUnsupported;
      return out;
    }
    out.settings.eu_span = std::fabs(eu_range->high - eu_range->low);
  }
  return out;
}

bool is_reportable_change(const DataChangeSettings& s, const DataValue& last, const DataValue& current) {
  if (last.status != current.status) {
    return true;
  }
  if (s.trigger == DataChangeTrigger::Status) {
    return false;
  }
  if (value_changed(s, last.value, current.value)) {
    return true;
  }
  return s.trigger == DataChangeTrigger::StatusValueTimestamp &&
         (last.source_timestamp != current.source_timestamp ||
          last.source_picoseconds != current.source_picoseconds);
}

}  // namespace sf::opcua::subs
