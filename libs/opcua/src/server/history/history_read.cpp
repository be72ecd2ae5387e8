// The HistoryRead service with ReadRawModifiedDetails (OPC 10000-4 §5.10.3, OPC 10000-11
// §6.4.3): request and node checks here, the values from a HistoryDatabase.
#include "sf/opcua/server/history.hpp"

#include "server/address_space/service_util.hpp"

namespace sf::opcua::server {

namespace {

using detail::logger;

// Checks of the request as a whole (OPC 10000-4 §5.10.3.2): the details and the timestamps.
StatusCode check_request(const HistoryReadRequest& request, const ReadRawModifiedDetails*& details) {
  details = request.history_read_details.get_if<ReadRawModifiedDetails>();
  if (details == nullptr) {
    // Processed, event, at-time and annotation details are not offered (OPC 10000-11 §6.4).
    return status::BadHistoryOperationUnsupported;
  }
  if (details->is_read_modified) {
    return status::BadHistoryOperationUnsupported;
  }
  if (request.timestamps_to_return == TimestampsToReturn::Neither ||
      static_cast<std::int32_t>(request.timestamps_to_return) < 0 ||
      static_cast<std::int32_t>(request.timestamps_to_return) > 3) {
    return status::BadTimestampsToReturnInvalid;
  }
  // OPC 10000-11 §6.4.3.2: both bounds open, or one open without a value count, is invalid.
  const bool start_open = details->start_time.is_min();
  const bool end_open = details->end_time.is_min();
  if ((start_open && end_open) || ((start_open || end_open) && details->num_values_per_node == 0)) {
    return status::BadInvalidTimestampArgument;
  }
  return StatusCode{};
}

// A Variable the user may read the history of (OPC 10000-3 §8.57 AccessLevel bit HistoryRead).
StatusCode check_node(const AddressSpace& space, const HistoryReadValueId& item, const ServiceContext& ctx) {
  const Node* node = space.find(item.node_id);
  if (node == nullptr) {
    return status::BadNodeIdUnknown;
  }
  const auto* variable = node->as<VariableNode>();
  if (variable == nullptr) {
    return status::BadHistoryOperationUnsupported;
  }
  if ((variable->access_level & access_level::HistoryRead) == 0) {
    return status::BadNotReadable;
  }
  if ((variable->user_access_level & access_level::HistoryRead) == 0 ||
      (ctx.user != nullptr && !ctx.user->can_read(*node))) {
    return status::BadUserAccessDenied;
  }
  if (!item.index_range.empty()) {
    return status::BadIndexRangeInvalid;  // ranges of historical arrays are not offered
  }
  if (!item.data_encoding.name.empty()) {
    return status::BadDataEncodingUnsupported;
  }
  return StatusCode{};
}

void keep_timestamps(DataValue& value, TimestampsToReturn which) {
  if (which == TimestampsToReturn::Source) {
    value.server_timestamp = DateTime{};
    value.server_picoseconds = 0;
  } else if (which == TimestampsToReturn::Server) {
    value.source_timestamp = DateTime{};
    value.source_picoseconds = 0;
  }
}

HistoryReadResult read_one(const AddressSpace& space, const HistoryReadRequest& request,
                           const ReadRawModifiedDetails& details, const HistoryReadValueId& item,
                           const ServiceContext& ctx, HistoryDatabase* database) {
  HistoryReadResult result;
  if (database == nullptr) {
    result.status_code = status::BadHistoryOperationUnsupported;
    return result;
  }
  result.status_code = check_node(space, item, ctx);
  if (result.status_code.is_bad() || request.release_continuation_points) {
    // Cursors are the database's and hold nothing on the server: releasing is a no-op.
    return result;
  }
  HistoryRawQuery query;
  query.node = item.node_id;
  query.start = details.start_time;
  query.end = details.end_time;
  query.max_values = details.num_values_per_node;
  query.return_bounds = details.return_bounds;
  query.continuation_point = item.continuation_point;
  HistoryRawResult raw = database->read_raw(query);
  for (DataValue& value : raw.values) {
    keep_timestamps(value, request.timestamps_to_return);
  }
  result.status_code = raw.status;
  result.continuation_point = std::move(raw.continuation_point);
  HistoryData data;
  data.data_values = Array<DataValue>(std::move(raw.values));
  result.history_data = ExtensionObject::make(std::move(data));
  return result;
}

}  // namespace

HistoryReadResponse history_read(const AddressSpace& space, const HistoryReadRequest& request,
                                 ServiceContext& ctx, HistoryDatabase* database) {
  HistoryReadResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  if (!detail::check_operation_count("HistoryRead", request.nodes_to_read.size(),
                                     ctx.limits.max_nodes_per_read, response.response_header)) {
    return response;
  }
  const ReadRawModifiedDetails* details = nullptr;
  if (const StatusCode bad = check_request(request, details); bad.is_bad()) {
    logger()->debug("HistoryRead refused: {}", to_string(bad));
    response.response_header.service_result = bad;
    return response;
  }
  Array<HistoryReadResult> results;
  results.reserve(request.nodes_to_read.size());
  for (const HistoryReadValueId& item : request.nodes_to_read) {
    results.push_back(read_one(space, request, *details, item, ctx, database));
  }
  response.results = std::move(results);
  return response;
}

}  // namespace sf::opcua::server
