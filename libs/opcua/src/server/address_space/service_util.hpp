// Helpers shared by the service implementations of src/server/address_space (internal).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sf/core/log.hpp"
#include "sf/opcua/server/services.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server::detail {

inline const Clock& clock_of(const ServiceContext& ctx) {
  return ctx.clock != nullptr ? *ctx.clock : SteadyClock::instance();
}

inline DateTime now(const ServiceContext& ctx) {
  return DateTime::from_system_clock(clock_of(ctx).utc_now());
}

// A NodeId of namespace 0 (the standard's nodes, node_ids.hpp).
inline NodeId ns0(std::uint32_t id) {
  return NodeId(0, id);
}

inline sf::log::Logger& logger() {
  static sf::log::Logger log = sf::log::get("opcua");
  return log;
}

// The ResponseHeader of a service answer (OPC 10000-4 §7.33).
inline ResponseHeader response_header(const RequestHeader& request, const ServiceContext& ctx) {
  ResponseHeader h;
  h.timestamp = now(ctx);
  h.request_handle = request.request_handle;
  return h;
}

// OPC 10000-4 §5.10.2.4 etc.: BadNothingToDo for an empty list, BadTooManyOperations above the
// limit (0 = none). Sets serviceResult and returns false when the service must stop.
inline bool check_operation_count(std::string_view service, std::size_t count, std::uint32_t limit,
                                  ResponseHeader& header) {
  if (count == 0) {
    header.service_result = status::BadNothingToDo;
  } else if (limit != 0 && count > limit) {
    header.service_result = status::BadTooManyOperations;
  } else {
    return true;
  }
  logger()->debug("{}: rejected {} operations: {}", service, count, to_string(header.service_result));
  return false;
}

// The DataType NodeId of a built-in type id (OPC 10000-6 Table 1 ids equal the ns0 NodeIds).
inline NodeId builtin_data_type(BuiltinType type) {
  return NodeId(0, static_cast<std::uint32_t>(type));
}

// Checks a value against a DataType, ValueRank and ArrayDimensions (OPC 10000-3 §5.6.2;
// subtypes of the DataType match, Enumerations take Int32, structures are matched through their
// DataTypeEncoding's HasEncoding reference). Good or BadTypeMismatch.
StatusCode check_value(const AddressSpace& space, const Variant& value, const NodeId& data_type,
                       std::int32_t value_rank, const std::vector<std::uint32_t>& array_dimensions);

}  // namespace sf::opcua::server::detail
