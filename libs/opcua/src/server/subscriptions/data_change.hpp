// DataChangeFilter (OPC 10000-4 §7.17.2): when a new sample of a data item is a change worth
// reporting — trigger Status / StatusValue / StatusValueTimestamp, absolute and percent
// deadband. Internal to the subscriptions engine.
#pragma once

#include <optional>

#include "sf/opcua/types.hpp"

namespace sf::opcua::subs {

struct DataChangeSettings {
  // The default without a filter is StatusValue without deadband (§7.17.2).
  DataChangeTrigger trigger = DataChangeTrigger::StatusValue;
  DeadbandType deadband_type = DeadbandType::None;
  double deadband_value = 0;
  // EURange (high - low) when deadband_type is Percent.
  double eu_span = 0;
};

// Validates a DataChangeFilter for an item whose current value is `value` and whose EURange is
// asked through `eu_range` (only for percent deadband). On success returns the settings; on
// failure the item's StatusCode: BadMonitoredItemFilterInvalid (unknown trigger),
// BadDeadbandFilterInvalid (unknown type, negative value, percent over 100),
// BadFilterNotAllowed (deadband on a non-numeric value), BadMonitoredItemFilterUnsupported
// (percent without EURange).
struct DataChangeCheck {
  StatusCode status;
  DataChangeSettings settings;
};
DataChangeCheck check_data_change_filter(const DataChangeFilter& filter, const Variant& value,
                                         const std::optional<Range>& eu_range);

// Whether a Variant holds a number or an array of numbers (SByte..Double), the values a
// deadband applies to.
bool is_numeric(const Variant& value);

// Equality of values where NaN equals NaN (a constant NaN is not a change).
bool same_value(const Variant& a, const Variant& b);

// Whether `current` is to be reported after `last` (the last reported sample).
bool is_reportable_change(const DataChangeSettings& settings, const DataValue& last,
                          const DataValue& current);

}  // namespace sf::opcua::subs
