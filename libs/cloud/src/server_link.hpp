// The gateway's connection to one shop-floor OPC UA server: connect (retrying until it answers),
// find the Variables the subscribe rules name, register them as historian series, subscribe, and
// turn every notification into a sample for the writer and the live bus. After setup the client's
// own reconnect (session reactivation with Republish, or re-creation after a server restart)
// keeps the data coming; samples re-delivered by a re-created monitored item are dropped here.
// Every ServerConfig::rediscover the rules are matched again and Variables the server added
// since are subscribed as well (OPC 10000-3 §9.32: a model may change while a client is
// connected; browsing again finds what a change event would have announced).
#pragma once

#include <atomic>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "model_walk.hpp"
#include "sample_writer.hpp"
#include "sf/cloud/config.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/cloud/live_bus.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::cloud::detail {

class ServerLink {
 public:
  // on_series: each series once it is registered (the aggregating server adds its node).
  // client: the connection settings (endpoint, security, user) made from config.
  // clock: the receive time of samples and events that come without one.
  ServerLink(ServerConfig config, opcua::ClientConfig client, historian::Store& store, SampleWriter& writer,
             LiveBus& bus, std::function<void(const historian::Series&)> on_series, const Clock& clock);
  // The client settings of `config` before security is applied.
  static opcua::ClientConfig client_config(const ServerConfig& config);
  ~ServerLink();
  ServerLink(const ServerLink&) = delete;
  ServerLink& operator=(const ServerLink&) = delete;

  // Starts connecting in the background; returns at once.
  void start();
  void stop();
  [[nodiscard]] ServerStatus status() const;
  // Calls the method `method` (a browse name) of the Object at `object_path` (from the Root, as
  // a subscribe rule's browse_path) on the connected server: its outputs, or Errc::state while
  // not connected, not_found for a path or method the model lacks, the server's status code.
  // Paths resolved once are remembered. Any thread; blocks for the call's round trip.
  Result<std::vector<opcua::Variant>> call(const std::string& object_path, const std::string& method,
                                           std::vector<opcua::Variant> inputs);

 private:
  // Per monitored item; after its item is created only the client's loop thread touches it.
  struct SeriesState {
    historian::Series series;
    std::optional<historian::Sample> last;
  };
  struct Subscribed {
    DiscoveredVariable variable;
    SeriesState* state;
  };

  void setup();
  void rediscover();
  Status connect_with_retry();
  Status subscribe_all();
  // Discovers the Variables the rules name and subscribes those not subscribed yet; those.
  Result<std::vector<Subscribed>> subscribe_new();
  void catch_up(const std::vector<Subscribed>& added);
  Status subscribe_events(opcua::SyncClient::SubscriptionId subscription);
  void on_value(SeriesState& state, const opcua::DataValue& value);
  void on_event(const std::vector<opcua::Variant>& fields);
  void set_phase(std::string phase, std::string error = {});
  [[nodiscard]] historian::Timestamp now() const;

  ServerConfig config_;
  const Clock& clock_;
  historian::Store& store_;
  SampleWriter& writer_;
  LiveBus& bus_;
  std::function<void(const historian::Series&)> on_series_;
  std::unique_ptr<opcua::SyncClient> client_;
  // Every Variable subscribed, by its key: states never move nor go while the link lives (the
  // items' callbacks hold them). Touched by the setup thread only.
  std::map<std::string, std::unique_ptr<SeriesState>> series_;
  std::vector<std::unique_ptr<SeriesState>> retired_;  // of a setup that failed midway
  std::optional<opcua::SyncClient::SubscriptionId> subscription_;
  bool events_subscribed_ = false;
  std::vector<std::string> item_warnings_;  // items the server refused

  mutable std::mutex mutex_;
  std::condition_variable stop_wait_;
  bool stopping_ = false;
  std::string phase_ = "idle";
  std::string last_error_;
  std::vector<std::string> warnings_;
  std::atomic<std::size_t> series_count_{0};
  std::atomic<std::uint64_t> samples_{0};
  std::atomic<std::uint64_t> events_{0};
  std::atomic<int> client_state_{0};
  std::thread setup_thread_;
  std::mutex call_mutex_;
  std::map<std::string, opcua::NodeId> resolved_;  // browse path → node, of call()
};

}  // namespace sf::cloud::detail
