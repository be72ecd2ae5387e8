// The View, Attribute and Method service sets over an AddressSpace (OPC 10000-4 §5.8, §5.10,
// §5.11): pure functions of (address space, request, per-call context) → response. The server
// composition decodes the request, holds its lock around the call and fills the rest of the
// ResponseHeader; these functions set responseHeader.serviceResult (BadNothingToDo,
// BadTooManyOperations, BadTimestampsToReturnInvalid, ...), requestHandle and timestamp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua::server {

// Per-request operation limits (OPC 10000-5 §6.3.11 OperationLimitsType); 0 = no limit.
struct OperationLimits {
  std::uint32_t max_nodes_per_read = 0;
  std::uint32_t max_nodes_per_write = 0;
  std::uint32_t max_nodes_per_browse = 0;
  std::uint32_t max_nodes_per_method_call = 0;
  std::uint32_t max_nodes_per_translate_browse_paths = 0;
  std::uint32_t max_nodes_per_register_nodes = 0;
  // Reported in OperationLimits; enforced by the subscriptions engine.
  std::uint32_t max_monitored_items_per_call = 0;
  // Upper bound for references per BrowseResult even when the client asks for none (0).
  std::uint32_t max_references_per_node = 1000;
};

// The user behind a request (OPC 10000-3 §5.9 roles and permissions). The default allows
// everything the node's attributes allow; the UserAccessLevel/UserWriteMask/UserExecutable
// attributes read as the node's value ANDed with these answers.
class UserContext {
 public:
  virtual ~UserContext() = default;
  [[nodiscard]] virtual bool can_read(const Node& /*node*/) const { return true; }
  [[nodiscard]] virtual bool can_write(const Node& /*node*/, AttributeId /*attribute*/) const { return true; }
  [[nodiscard]] virtual bool can_browse(const Node& /*node*/) const { return true; }
  [[nodiscard]] virtual bool can_call(const Node& /*method*/) const { return true; }
};

// The browse continuation points of one session (OPC 10000-4 §7.9): owned by the session,
// bounded (MaxBrowseContinuationPoints), released by BrowseNext (release=true, or when the last
// references are returned) or when the session closes (destroy this object). A point holds a
// snapshot of the references still to return.
class BrowseContinuations {
 public:
  explicit BrowseContinuations(std::size_t max_count = 10) : max_count_(max_count) {}

  [[nodiscard]] std::size_t max_count() const { return max_count_; }
  [[nodiscard]] std::size_t size() const { return points_.size(); }
  void clear() { points_.clear(); }

  // Internals for browse/browse_next.
  struct Pending {
    std::vector<ReferenceDescription> remaining;
    std::uint32_t max_references = 0;
  };
  // A new continuation point holding `pending`; nullopt when all max_count are in use.
  std::optional<ByteString> add(Pending pending);
  // Removes and returns the point; nullopt when unknown.
  std::optional<Pending> take(const ByteString& id);
  bool release(const ByteString& id);

 private:
  std::size_t max_count_;
  std::uint64_t next_id_ = 1;
  std::map<Bytes, Pending> points_;
};

struct ServiceContext {
  // Source of server timestamps; nullptr = SteadyClock::instance().
  const Clock* clock = nullptr;
  OperationLimits limits;
  // Browse continuation points of the session; nullptr: Browse returns no continuation points
  // (results beyond the limit end with BadNoContinuationPoints).
  BrowseContinuations* continuations = nullptr;
  // nullptr = a user allowed everything.
  const UserContext* user = nullptr;
};

// ---- Attribute Service Set (OPC 10000-4 §5.10)
ReadResponse read(AddressSpace& space, const ReadRequest& request, ServiceContext& ctx);
WriteResponse write(AddressSpace& space, const WriteRequest& request, ServiceContext& ctx);

// One Read operation (also used by the subscriptions engine to sample monitored items):
// attribute, IndexRange and DataEncoding as in Read, timestamps per `timestamps`.
DataValue read_attribute(const AddressSpace& space, const ReadValueId& item, TimestampsToReturn timestamps,
                         const ServiceContext& ctx);
// One Write operation; notifies the address space's listeners on success.
StatusCode write_attribute(AddressSpace& space, const WriteValue& item, const ServiceContext& ctx);

// ---- View Service Set (OPC 10000-4 §5.8)
BrowseResponse browse(const AddressSpace& space, const BrowseRequest& request, ServiceContext& ctx);
BrowseNextResponse browse_next(const AddressSpace& space, const BrowseNextRequest& request,
                               ServiceContext& ctx);
TranslateBrowsePathsToNodeIdsResponse translate_browse_paths(
    const AddressSpace& space, const TranslateBrowsePathsToNodeIdsRequest& request, ServiceContext& ctx);
// Resolves one BrowsePath (also for event select clauses in the subscriptions engine).
BrowsePathResult translate_browse_path(const AddressSpace& space, const BrowsePath& path);
RegisterNodesResponse register_nodes(const AddressSpace& space, const RegisterNodesRequest& request,
                                     ServiceContext& ctx);
UnregisterNodesResponse unregister_nodes(const AddressSpace& space, const UnregisterNodesRequest& request,
                                         ServiceContext& ctx);

// ---- Method Service Set (OPC 10000-4 §5.11)
CallResponse call(AddressSpace& space, const CallRequest& request, ServiceContext& ctx);

// ---- NumericRange (OPC 10000-4 §7.27), exposed for monitored items' indexRange.
struct NumericRange {
  struct Dimension {
    std::uint32_t low = 0;
    std::uint32_t high = 0;  // inclusive; low == high for a single index
  };
  std::vector<Dimension> dimensions;  // empty: the whole value
  [[nodiscard]] bool empty() const { return dimensions.empty(); }
};
// "1", "2:4", "0:1,0:1"; a null or empty string is the empty range. BadIndexRangeInvalid for
// syntax errors and low >= high.
Result<NumericRange> parse_numeric_range(const String& text);
// The sub-array/sub-string of value selected by range (OPC 10000-4 §7.27): BadIndexRangeNoData
// when it selects nothing, BadIndexRangeInvalid for a range that does not fit the value's shape.
Result<Variant> apply_numeric_range(const Variant& value, const NumericRange& range);
// value with the elements selected by range replaced by patch (same shape as the selection):
// BadIndexRangeNoData / BadIndexRangeInvalid / BadTypeMismatch.
Result<Variant> write_numeric_range(const Variant& value, const NumericRange& range, const Variant& patch);

}  // namespace sf::opcua::server
