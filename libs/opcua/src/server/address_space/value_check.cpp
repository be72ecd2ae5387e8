// Type checks of written values and method arguments against DataType, ValueRank and
// ArrayDimensions (OPC 10000-3 §5.6.2, OPC 10000-4 §5.10.4.1 BadTypeMismatch).
#include "server/address_space/service_util.hpp"

namespace sf::opcua::server::detail {

namespace {

using detail::ns0;

// The DataType of a structure value: its encoding's inverse HasEncoding (OPC 10000-3 §5.8.4).
const NodeId* structure_type(const AddressSpace& space, const Variant& value) {
  const auto* object = value.get_if<ExtensionObject>();
  if (object == nullptr) {
    if (const auto* array = value.array_if<ExtensionObject>(); array != nullptr && !array->empty()) {
      object = &array->front();
    }
  }
  const Node* encoding = object != nullptr ? space.find(object->type_id()) : nullptr;
  return encoding != nullptr ? encoding->inverse_target(id::HasEncoding) : nullptr;
}

bool type_matches(const AddressSpace& space, const Variant& value, const NodeId& data_type) {
  if (data_type == ns0(id::BaseDataType)) {
    return true;
  }
  const BuiltinType builtin = value.type();
  const NodeId builtin_type = builtin_data_type(builtin);
  if (builtin == BuiltinType::ExtensionObject) {
    const NodeId* structure = structure_type(space, value);
    if (structure == nullptr) {
      // An encoding this server does not describe: only abstract Structure can hold it.
      return data_type == ns0(id::Structure);
    }
    return space.is_subtype(*structure, data_type);
  }
  if (builtin == BuiltinType::Variant) {
    return false;  // an array of Variants: only BaseDataType (above)
  }
  if (builtin == BuiltinType::Int32 && space.is_subtype(data_type, ns0(id::Enumeration))) {
    return true;
  }
  // A value of the built-in type or of a subtype (Int32 for Integer/Number), or a DataType that
  // refines the built-in one without changing its encoding (Duration, UtcTime, LocaleId...).
  return space.is_subtype(builtin_type, data_type) || space.is_subtype(data_type, builtin_type);
}

bool rank_matches(const Variant& value, std::int32_t value_rank) {
  const auto rank = value.is_scalar()   ? 0
                    : value.is_matrix() ? static_cast<std::int32_t>(value.array_dimensions().size())
                                        : 1;
  switch (value_rank) {
    case value_rank::Any:
      return true;
    case value_rank::Scalar:
      return rank == 0;
    case value_rank::ScalarOrOneDimension:
      return rank <= 1;
    case value_rank::OneOrMoreDimensions:
      return rank >= 1;
    default:
      return rank == value_rank;
  }
}

bool dimensions_fit(const Variant& value, const std::vector<std::uint32_t>& array_dimensions) {
  if (array_dimensions.empty() || value.is_scalar()) {
    return true;
  }
  std::vector<std::int32_t> actual = value.array_dimensions();
  if (actual.empty()) {
    actual.push_back(static_cast<std::int32_t>(value.array_length()));
  }
  if (actual.size() != array_dimensions.size()) {
    return false;
  }
  // ArrayDimensions give maximum lengths; 0 means "any length".
  for (std::size_t i = 0; i < actual.size(); ++i) {
    if (array_dimensions[i] != 0 &&
        static_cast<std::uint32_t>(std::max(actual[i], 0)) > array_dimensions[i]) {
      return false;
    }
  }
  return true;
}

}  // namespace

StatusCode check_value(const AddressSpace& space, const Variant& value, const NodeId& data_type,
                       std::int32_t value_rank, const std::vector<std::uint32_t>& array_dimensions) {
  if (value.is_empty()) {
    // A Null value carries no type: only variables of any type may become Null.
    return data_type == ns0(id::BaseDataType) ? StatusCode() : status::BadTypeMismatch;
  }
  // OPC 10000-3 §5.6.2: a ByteString may be written to a Byte array and back.
  const bool byte_array =
      data_type == ns0(id::Byte) && value.get_if<ByteString>() != nullptr &&
      (value_rank == value_rank::OneDimension || value_rank == value_rank::OneOrMoreDimensions);
  if (byte_array) {
    return {};
  }
  if (!type_matches(space, value, data_type) || !rank_matches(value, value_rank) ||
      !dimensions_fit(value, array_dimensions)) {
    return status::BadTypeMismatch;
  }
  return {};
}

}  // namespace sf::opcua::server::detail
