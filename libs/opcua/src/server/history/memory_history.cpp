// MemoryHistory: the recent values of Historizing Variables kept in memory (OPC 10000-3 §5.6.2:
// "Historizing indicates whether the Server is actively collecting data for the history").
#include <algorithm>

#include "sf/opcua/server/history.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

void MemoryHistory::attach(AddressSpace& space) {
  detach();
  space_ = &space;
  listener_ = space.add_change_listener([this](const NodeChange& change) {
    if (change.kind != NodeChange::Kind::AttributeWritten || change.attribute != AttributeId::Value) {
      return;
    }
    const auto* variable = space_->find_as<VariableNode>(change.node_id);
    if (variable == nullptr || !variable->historizing) {
      return;
    }
    if (auto value = space_->value(change.node_id)) {
      record(change.node_id, std::move(*value));
    }
  });
}

void MemoryHistory::detach() {
  if (space_ != nullptr) {
    space_->remove_change_listener(listener_);
    space_ = nullptr;
  }
}

void MemoryHistory::record(const NodeId& node, DataValue value) {
  if (value.source_timestamp.is_min()) {
    value.source_timestamp = value.server_timestamp;
  }
  auto& values = values_[node];
  // Values come in time order nearly always; a late one is put in its place.
  const auto at = std::upper_bound(values.begin(), values.end(), value.source_timestamp,
                                   [](DateTime t, const DataValue& v) { return t < v.source_timestamp; });
  values.insert(at, std::move(value));
  if (values.size() >= 2 * depth_) {
    values.erase(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() - depth_));
  }
}

HistoryRawResult MemoryHistory::read_raw(const HistoryRawQuery& query) {
  const auto found = values_.find(query.node);
  if (found == values_.end()) {
    return read_raw_sorted(query, {});
  }
  std::span<const DataValue> all(found->second);
  // Only the last depth_ values count: the older ones wait for the next trim.
  return read_raw_sorted(query, all.size() > depth_ ? all.subspan(all.size() - depth_) : all);
}

}  // namespace sf::opcua::server
