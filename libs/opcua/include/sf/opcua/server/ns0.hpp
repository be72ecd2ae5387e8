// Namespace 0: the standard nodes generic clients expect (OPC 10000-3, OPC 10000-5), generated
// at build time from libs/opcua/schema/ns0.txt by tools/opcua_ns0_gen.py, and the live values
// of the Server object (i=2253) that the server composition installs as callbacks.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/server/address_space.hpp"
#include "sf/opcua/server/services.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua::server {

// Adds every namespace-0 node of ns0.txt with its references to an address space that has no
// namespace-0 nodes yet (BadNodeIdExists otherwise). Values of the Server object are static
// placeholders until install_server_object_callbacks.
Status build_namespace0(AddressSpace& space);

// Number of nodes build_namespace0 adds (for tests and logs).
std::size_t namespace0_node_count();

// The built-in type values of `data_type` have on the wire (OPC 10000-6 §5.1.2): the type itself
// for a built-in DataType of namespace 0; for a subtype of one, that built-in type, found up the
// HasSubtype hierarchy of `space` (OPC 10000-3 §5.8.3: Duration → Double, UtcTime → DateTime, a
// server's own subtype of Int32 → Int32); Int32 for enumerations. Null for structures, abstract
// types (Number, ...) and types `space` does not know.
BuiltinType builtin_type_of(const AddressSpace& space, const NodeId& data_type);
// The same against namespace 0 alone (built once per process): what a client knows of a server's
// data types without browsing them.
BuiltinType builtin_type_of(const NodeId& data_type);

// What the Server object shows (OPC 10000-5 §6.3.1 ServerType, §12.10 ServerStatusDataType).
struct ServerObjectInfo {
  // ServerArray: the server's own ApplicationUri first (OPC 10000-5 §6.3.1).
  std::vector<std::string> server_uris;
  BuildInfo build_info;
  // nullptr = SteadyClock::instance(); CurrentTime reads clock->utc_now().
  const Clock* clock = nullptr;
  // StartTime; min() = the time install_server_object_callbacks runs.
  DateTime start_time = DateTime::min();
  // State, SecondsTillShutdown and ShutdownReason are read through these when set.
  std::function<ServerState()> state;
  std::function<std::uint32_t()> seconds_till_shutdown;
  std::function<LocalizedText()> shutdown_reason;
  std::function<std::uint8_t()> service_level;  // default 255 (OPC 10000-5 §6.3.1)
  // ServerCapabilities (OPC 10000-5 §6.3.2).
  std::vector<std::string> server_profiles = {"http://opcfoundation.org/UA-Profile/Server/EmbeddedUA2017",
                                              "http://opcfoundation.org/UA-Profile/Server/Methods"};
  std::vector<std::string> locale_ids = {"en"};
  double min_supported_sample_rate = 0.0;  // ms
  std::uint16_t max_browse_continuation_points = 10;
  std::uint32_t max_array_length = 0;   // 0 = no limit
  std::uint32_t max_string_length = 0;  // 0 = no limit
  OperationLimits operation_limits;
};

// Installs the read callbacks of the Server object's variables: ServerArray, NamespaceArray
// (AddressSpace::namespaces()), ServerStatus (an ExtensionObject of ServerStatusDataType) and
// each of its children, ServiceLevel, ServerCapabilities and OperationLimits. The callbacks
// capture `space` by reference: the AddressSpace must outlive them (it owns them).
Status install_server_object_callbacks(AddressSpace& space, ServerObjectInfo info);

}  // namespace sf::opcua::server
