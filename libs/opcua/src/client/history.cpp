// HistoryRead of raw values (OPC 10000-4 §5.10.3, OPC 10000-11 §6.4.3), following the server's
// continuation points until the node's history in the interval is complete.
#include "client_impl.hpp"

namespace sf::opcua {

namespace {

HistoryReadRequest raw_request(const NodeId& node, const HistoryRawParams& params,
                               ByteString continuation_point) {
  HistoryReadRequest request;
  ReadRawModifiedDetails details;
  details.is_read_modified = false;
  details.start_time = params.start;
  details.end_time = params.end;
  details.num_values_per_node = params.max_values;
  details.return_bounds = params.return_bounds;
  request.history_read_details = ExtensionObject::make(details);
  request.timestamps_to_return = TimestampsToReturn::Both;
  request.release_continuation_points = false;
  HistoryReadValueId item;
  item.node_id = node;
  item.continuation_point = std::move(continuation_point);
  request.nodes_to_read.push_back(std::move(item));
  return request;
}

}  // namespace

void Client::Impl::history_read_raw(NodeId node, HistoryRawParams params, std::vector<DataValue> collected,
                                    ByteString continuation_point,
                                    std::function<void(Result<std::vector<DataValue>>)> done) {
  if (auto error = check_connected("HistoryRead")) {
    fail_later(std::move(done), *error);
    return;
  }
  auto request = raw_request(node, params, std::move(continuation_point));
  send(std::move(request), [this, node = std::move(node), params, collected = std::move(collected),
                            done = std::move(done)](Result<HistoryReadResponse> response) mutable {
    if (!response) {
      done(client_detail::error_of(response));
      return;
    }
    if (response->results.size() != 1) {
      done(status_error(status::BadUnknownResponse,
                        fmt::format("HistoryRead: {} results for 1 node", response->results.size())));
      return;
    }
    HistoryReadResult& result = response->results.front();
    if (result.status_code.is_bad()) {
      done(status_error(result.status_code, fmt::format("HistoryRead {}", to_string(node))));
      return;
    }
    if (const auto* data = result.history_data.get_if<HistoryData>()) {
      collected.insert(collected.end(), data->data_values.begin(), data->data_values.end());
    }
    if (result.continuation_point.is_null() || result.continuation_point.empty()) {
      done(std::move(collected));
      return;
    }
    history_read_raw(std::move(node), params, std::move(collected), std::move(result.continuation_point),
                     std::move(done));
  });
}

}  // namespace sf::opcua
