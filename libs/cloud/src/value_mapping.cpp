#include "sf/cloud/value_mapping.hpp"

#include <type_traits>

namespace sf::cloud {

namespace {

namespace ua = sf::opcua;
using historian::DataType;

constexpr std::int64_t kTicksPerMicro = 10;

}  // namespace

historian::Timestamp to_timestamp(ua::DateTime time) {
  if (time.is_min()) {
    return historian::from_micros(-ua::DateTime::kUnixEpochTicks / kTicksPerMicro);
  }
  return historian::from_micros((time.ticks() - ua::DateTime::kUnixEpochTicks) / kTicksPerMicro);
}

ua::DateTime to_date_time(historian::Timestamp time) {
  const std::int64_t ticks = historian::to_micros(time) * kTicksPerMicro + ua::DateTime::kUnixEpochTicks;
  return ticks <= 0 ? ua::DateTime::min() : ua::DateTime(ticks);
}

std::optional<DataType> historian_type(const ua::NodeId& data_type) {
  if (data_type.namespace_index != 0 || !data_type.is_numeric()) {
    return std::nullopt;
  }
  switch (static_cast<ua::BuiltinType>(data_type.numeric())) {
    case ua::BuiltinType::Boolean:
      return DataType::boolean;
    case ua::BuiltinType::SByte:
    case ua::BuiltinType::Int16:
    case ua::BuiltinType::Int32:
    case ua::BuiltinType::Int64:
      return DataType::int64;
    case ua::BuiltinType::Byte:
    case ua::BuiltinType::UInt16:
    case ua::BuiltinType::UInt32:
    case ua::BuiltinType::UInt64:
      return DataType::uint64;
    case ua::BuiltinType::Float:
    case ua::BuiltinType::Double:
      return DataType::float64;
    case ua::BuiltinType::String:
    case ua::BuiltinType::DateTime:
    case ua::BuiltinType::Guid:
    case ua::BuiltinType::NodeId:
    case ua::BuiltinType::QualifiedName:
    case ua::BuiltinType::LocalizedText:
      return DataType::string;
    case ua::BuiltinType::ByteString:
      return DataType::bytes;
    default:
      // Number (26), Integer (27), UInteger (28), Enumeration (29) and the like: numbers.
      return data_type.numeric() >= 26 && data_type.numeric() <= 29 ? std::optional(DataType::float64)
                                                                    : std::nullopt;
  }
}

ua::NodeId data_type_of(DataType type) {
  switch (type) {
    case DataType::boolean:
      return ua::NodeId(0, ua::id::Boolean);
    case DataType::int64:
      return ua::NodeId(0, ua::id::Int64);
    case DataType::uint64:
      return ua::NodeId(0, ua::id::UInt64);
    case DataType::float64:
      return ua::NodeId(0, ua::id::Double);
    case DataType::string:
      return ua::NodeId(0, ua::id::String);
    case DataType::bytes:
      return ua::NodeId(0, ua::id::ByteString);
    case DataType::empty:
      break;
  }
  return ua::NodeId(0, ua::id::BaseDataType);
}

historian::Value to_value(const ua::Variant& value) {
  if (value.is_empty()) {
    return std::monostate{};
  }
  if (value.is_array()) {
    return ua::to_string(value);
  }
  historian::Value out = std::monostate{};
  std::visit(
      [&out, &value](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>) {
          out = v;
        } else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) {
          out = static_cast<std::int64_t>(v);
        } else if constexpr (std::is_integral_v<T>) {
          out = static_cast<std::uint64_t>(v);
        } else if constexpr (std::is_floating_point_v<T>) {
          out = static_cast<double>(v);
        } else if constexpr (std::is_same_v<T, ua::String>) {
          out = v.str();
        } else if constexpr (std::is_same_v<T, ua::LocalizedText>) {
          out = v.text.str();
        } else if constexpr (std::is_same_v<T, ua::ByteString>) {
          out = v.bytes();
        } else if constexpr (!std::is_same_v<T, std::monostate>) {
          out = ua::to_string(value);
        }
      },
      value.storage());
  return out;
}

ua::Variant to_variant(const historian::Value& value) {
  return std::visit(
      [](const auto& v) -> ua::Variant {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return ua::Variant();
        } else if constexpr (std::is_same_v<T, Bytes>) {
          return ua::Variant(ua::ByteString(v));
        } else if constexpr (std::is_same_v<T, std::string>) {
          return ua::Variant(ua::String(v));
        } else {
          return ua::Variant(v);
        }
      },
      value);
}

historian::Sample to_sample(historian::SeriesId series, const ua::DataValue& value,
                            historian::Timestamp received) {
  historian::Sample sample;
  sample.series = series;
  sample.server_time = value.server_timestamp.is_min() ? received : to_timestamp(value.server_timestamp);
  sample.source_time =
      value.source_timestamp.is_min() ? sample.server_time : to_timestamp(value.source_timestamp);
  sample.status = value.status.value();
  sample.value = to_value(value.value);
  return sample;
}

ua::DataValue to_data_value(const historian::Sample& sample) {
  ua::DataValue value{to_variant(sample.value)};
  value.status = ua::StatusCode(sample.status);
  value.source_timestamp = to_date_time(sample.source_time);
  value.server_timestamp = to_date_time(sample.server_time);
  return value;
}

}  // namespace sf::cloud
