// OPC UA values ↔ historian samples: the gateway's translation of a DataValue (OPC 10000-4 §7.11)
// into a Sample, and the aggregating server's way back.
#pragma once

#include <optional>

#include "sf/historian/types.hpp"
#include "sf/opcua/encoding.hpp"

namespace sf::cloud {

// OPC UA DateTime (100 ns since 1601) ↔ historian time (µs since 1970); sub-µs digits are cut.
historian::Timestamp to_timestamp(opcua::DateTime time);
opcua::DateTime to_date_time(historian::Timestamp time);

// The historian type of a namespace-0 DataType: integers collapse to int64/uint64, Float and
// Double to float64, String/LocalizedText/NodeId... to string; nullopt for types the historian
// does not keep (structures).
std::optional<historian::DataType> historian_type(const opcua::NodeId& data_type);

// The namespace-0 DataType that holds values of a historian type (int64 → Int64, float64 → Double).
opcua::NodeId data_type_of(historian::DataType type);

// The value of a scalar Variant (empty for Null; arrays, matrices and structures become their
// text form so nothing is silently dropped).
historian::Value to_value(const opcua::Variant& value);
opcua::Variant to_variant(const historian::Value& value);

// A DataValue as a sample of `series`: source time (server time, then `received` when the server
// sent neither), status and value. seq is left 0.
historian::Sample to_sample(historian::SeriesId series, const opcua::DataValue& value,
                            historian::Timestamp received);
opcua::DataValue to_data_value(const historian::Sample& sample);

}  // namespace sf::cloud
