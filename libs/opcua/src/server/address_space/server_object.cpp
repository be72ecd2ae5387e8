// The live values of the Server object (OPC 10000-5 §6.3.1 ServerType, §6.3.2
// ServerCapabilitiesType, §6.3.11 OperationLimitsType, §12.10 ServerStatusDataType).
#include <memory>

#include "sf/opcua/binary.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {

namespace {

struct LiveInfo {
  ServerObjectInfo info;
  const Clock* clock = nullptr;
  DateTime start_time;

  [[nodiscard]] DateTime now() const { return DateTime::from_system_clock(clock->utc_now()); }
  [[nodiscard]] ServerState state() const { return info.state ? info.state() : ServerState::Running; }
  [[nodiscard]] std::uint32_t seconds_till_shutdown() const {
    return info.seconds_till_shutdown ? info.seconds_till_shutdown() : 0U;
  }
  [[nodiscard]] LocalizedText shutdown_reason() const {
    return info.shutdown_reason ? info.shutdown_reason() : LocalizedText();
  }
  [[nodiscard]] ServerStatusDataType status() const {
    ServerStatusDataType s;
    s.start_time = start_time;
    s.current_time = now();
    s.state = state();
    s.build_info = info.build_info;
    s.seconds_till_shutdown = seconds_till_shutdown();
    s.shutdown_reason = shutdown_reason();
    return s;
  }
  // A value sampled now: its source timestamp is the current time.
  [[nodiscard]] DataValue sampled(Variant v) const {
    DataValue d(std::move(v));
    d.source_timestamp = now();
    return d;
  }
};

Array<String> strings(const std::vector<std::string>& list) {
  Array<String> out;
  out.reserve(list.size());
  for (const auto& s : list) {
    out.emplace_back(s);
  }
  return out;
}

}  // namespace

Status install_server_object_callbacks(AddressSpace& space, ServerObjectInfo info) {
  auto live = std::make_shared<LiveInfo>();
  live->clock = info.clock != nullptr ? info.clock : &SteadyClock::instance();
  live->info = std::move(info);
  live->start_time = live->info.start_time.is_min() ? live->now() : live->info.start_time;

  auto reader = [&space](std::uint32_t id, ValueReader read) {
    return space.set_value_callbacks(NodeId(0, id), std::move(read), nullptr);
  };
  auto stored = [&space](std::uint32_t id, Variant value) {
    return space.set_value(NodeId(0, id), DataValue(std::move(value)));
  };
  const LiveInfo& l = *live;
  const BuildInfo& build = l.info.build_info;

  // ServerType (OPC 10000-5 §6.3.1).
  SF_TRY(stored(id::Server_ServerArray, Variant(strings(l.info.server_uris))));
  SF_TRY(reader(id::Server_NamespaceArray,
                [&space] { return DataValue(Variant(strings(space.namespaces()))); }));
  SF_TRY(reader(id::Server_ServerStatus,
                [live] { return live->sampled(ExtensionObject::make(live->status())); }));
  SF_TRY(stored(id::Server_ServerStatus_StartTime, Variant(l.start_time)));
  SF_TRY(reader(id::Server_ServerStatus_CurrentTime, [live] { return live->sampled(Variant(live->now())); }));
  SF_TRY(reader(id::Server_ServerStatus_State,
                [live] { return live->sampled(Variant(static_cast<std::int32_t>(live->state()))); }));
  SF_TRY(reader(id::Server_ServerStatus_SecondsTillShutdown,
                [live] { return live->sampled(Variant(live->seconds_till_shutdown())); }));
  SF_TRY(reader(id::Server_ServerStatus_ShutdownReason,
                [live] { return live->sampled(Variant(live->shutdown_reason())); }));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo, Variant(ExtensionObject::make(build))));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo_ProductUri, Variant(build.product_uri)));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo_ManufacturerName, Variant(build.manufacturer_name)));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo_ProductName, Variant(build.product_name)));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo_SoftwareVersion, Variant(build.software_version)));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo_BuildNumber, Variant(build.build_number)));
  SF_TRY(stored(id::Server_ServerStatus_BuildInfo_BuildDate, Variant(build.build_date)));
  SF_TRY(reader(id::Server_ServiceLevel, [live] {
    return live->sampled(Variant(live->info.service_level ? live->info.service_level() : std::uint8_t{255}));
  }));

  // ServerCapabilitiesType (OPC 10000-5 §6.3.2).
  SF_TRY(stored(id::Server_ServerCapabilities_ServerProfileArray, Variant(strings(l.info.server_profiles))));
  SF_TRY(stored(id::Server_ServerCapabilities_LocaleIdArray, Variant(strings(l.info.locale_ids))));
  SF_TRY(stored(id::Server_ServerCapabilities_MinSupportedSampleRate,
                Variant(l.info.min_supported_sample_rate)));
  SF_TRY(stored(id::Server_ServerCapabilities_MaxBrowseContinuationPoints,
                Variant(l.info.max_browse_continuation_points)));
  SF_TRY(stored(id::Server_ServerCapabilities_MaxArrayLength, Variant(l.info.max_array_length)));
  SF_TRY(stored(id::Server_ServerCapabilities_MaxStringLength, Variant(l.info.max_string_length)));
  SF_TRY(stored(id::Server_ServerCapabilities_MaxByteStringLength, Variant(l.info.max_string_length)));

  // OperationLimitsType (OPC 10000-5 §6.3.11); 0 means no limit.
  const OperationLimits& limits = l.info.operation_limits;
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerRead,
                Variant(limits.max_nodes_per_read)));
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerWrite,
                Variant(limits.max_nodes_per_write)));
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerMethodCall,
                Variant(limits.max_nodes_per_method_call)));
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerBrowse,
                Variant(limits.max_nodes_per_browse)));
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerRegisterNodes,
                Variant(limits.max_nodes_per_register_nodes)));
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxNodesPerTranslateBrowsePathsToNodeIds,
                Variant(limits.max_nodes_per_translate_browse_paths)));
  SF_TRY(stored(id::Server_ServerCapabilities_OperationLimits_MaxMonitoredItemsPerCall,
                Variant(limits.max_monitored_items_per_call)));
  return {};
}

}  // namespace sf::opcua::server
