// Historical Access (OPC 10000-11) for the server: HistoryRead of raw values (OPC 10000-4
// §5.10.3 with ReadRawModifiedDetails, OPC 10000-11 §6.4.3) answered by a HistoryDatabase
// plug-in, in the manner of open62541's historydatabase plugin. The server checks the request
// and the node (a Variable whose AccessLevel has HistoryRead); the database returns the values.
//
// Continuation points are the database's own opaque cursors (e.g. "continue after this time and
// sequence"): the server hands them to the client and back, so they cost the server no state and
// survive nothing they should not; a database must reject a cursor it did not make
// (BadContinuationPointInvalid).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "sf/opcua/server/services.hpp"

namespace sf::opcua::server {

struct HistoryRawQuery {
  NodeId node;
  // OPC 10000-11 §6.4.3.2: start > end reads backwards; a null bound (DateTime::min()) is open
  // and then max_values is not 0.
  DateTime start;
  DateTime end;
  std::uint32_t max_values = 0;  // 0 = all in the interval
  bool return_bounds = false;
  ByteString continuation_point;  // null for a first request
};

struct HistoryRawResult {
  StatusCode status;              // Good, GoodNoData, GoodMoreData, or a Bad code for this node
  std::vector<DataValue> values;  // source and server timestamps as stored
  ByteString continuation_point;  // null when there is no more
};

class HistoryDatabase {
 public:
  virtual ~HistoryDatabase() = default;
  // Runs on the server's loop thread: keep it short (a bounded database query).
  virtual HistoryRawResult read_raw(const HistoryRawQuery& query) = 0;
};

// ---- Building blocks for databases

// Where a raw read continues: after the values at `time` of which `skip` were returned already
// (several values may share a source timestamp).
struct HistoryCursor {
  DateTime time;
  std::uint32_t skip = 0;
};
// The cursor as a continuation point bound to its node: a cursor of another node, or bytes that
// are not a cursor, decode to BadContinuationPointInvalid.
ByteString encode_history_cursor(const NodeId& node, const HistoryCursor& cursor);
Result<HistoryCursor> decode_history_cursor(const NodeId& node, const ByteString& continuation_point);

// Answers `query` from values sorted by source timestamp (oldest first), as OPC 10000-11
// §6.4.3.2 reads raw data: start <= t < end forwards (start == end: the values at that time),
// end < t <= start backwards (start > end, or only end given: t <= end), newest first; at most
// max_values per call with a continuation point when more remain; with return_bounds the value
// before and the value after the interval (BadBoundNotFound at the bound's time when there is
// none). With one bound open, max_values is the number of values wanted and no continuation
// point is given. GoodNoData when nothing is in the interval.
HistoryRawResult read_raw_sorted(const HistoryRawQuery& query, std::span<const DataValue> sorted);

// A HistoryDatabase in memory: the last `depth` values of each recorded Variable. attach() records
// every value written to Variables whose Historizing attribute is true (set_value and Write);
// record() adds values from elsewhere.
class MemoryHistory final : public HistoryDatabase {
 public:
  explicit MemoryHistory(std::size_t depth = 10'000) : depth_(depth) {}
  // Listens to `space` (which must outlive the listener: detach() or destroy both together).
  void attach(AddressSpace& space);
  void detach();
  void record(const NodeId& node, DataValue value);
  HistoryRawResult read_raw(const HistoryRawQuery& query) override;

 private:
  std::size_t depth_;
  // Oldest first; trimmed to depth_ in batches so that recording stays O(1) amortized.
  std::unordered_map<NodeId, std::vector<DataValue>> values_;
  AddressSpace* space_ = nullptr;
  std::size_t listener_ = 0;
};

// The HistoryRead service over an address space and a database (nullptr: every node answers
// BadHistoryOperationUnsupported).
HistoryReadResponse history_read(const AddressSpace& space, const HistoryReadRequest& request,
                                 ServiceContext& ctx, HistoryDatabase* database);

}  // namespace sf::opcua::server
