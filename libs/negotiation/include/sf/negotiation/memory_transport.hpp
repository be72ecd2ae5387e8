// MemoryNetwork: the transports in memory, for unit tests and the in-memory
// benchmark. It delivers like DDS does for the paper's topics (an ANNOUNCE or
// AWARD reaches every contractor of that operation, a contractor's message
// every manager), with injectable faults: latency and jitter, reordering,
// duplicates, contractors that die (their traffic stops; managers are told
// after the liveliness lease, as DDS would) and contractors cut off the
// network for a while (their traffic waits; see cut_off()).
//
// Nothing happens on its own: deliver() hands over every message that is due
// by the clock; tests advance a ManualClock between calls.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/negotiation/transport.hpp"

namespace sf::negotiation {

struct MemoryNetworkOptions {
  std::chrono::nanoseconds latency{0};  // every delivery
  std::chrono::nanoseconds jitter{0};   // plus up to this much, at random
  bool keep_order = true;               // FIFO per sender and topic, like a reliable DDS writer
  double duplicate_probability = 0.0;   // a message is delivered twice
  std::chrono::nanoseconds lease{std::chrono::seconds{1}};  // death → "lost" at managers
  std::uint64_t seed = 1;
};

class MemoryNetwork;
class MemoryManagerEndpoint;
class MemoryContractorEndpoint;
class MemoryConveyorEndpoint;

class MemoryManagerEndpoint final : public ManagerTransport, public RouteTransport {
 public:
  void bind(ManagerInbox& inbox) { inbox_ = &inbox; }
  void bind(RouteInbox& inbox) { route_inbox_ = &inbox; }
  Status announce(const Announce& announce) override;
  Status send(const ManagerMessage& message) override;
  void close(const std::string& operation, const std::string& conversation) override;
  [[nodiscard]] std::size_t contractors(const std::string& operation) const override;
  Status request(const TransportRequest& request) override;
  void close(const std::string& conversation) override;
  [[nodiscard]] std::size_t conveyors() const override;

 private:
  friend class MemoryNetwork;
  friend class MemoryContractorEndpoint;
  friend class MemoryConveyorEndpoint;
  MemoryManagerEndpoint(MemoryNetwork& net, std::size_t id) : net_(&net), id_(id) {}
  MemoryNetwork* net_;
  std::size_t id_;
  ManagerInbox* inbox_ = nullptr;
  RouteInbox* route_inbox_ = nullptr;
};

class MemoryContractorEndpoint final : public ContractorTransport {
 public:
  void bind(ContractorInbox& inbox) { inbox_ = &inbox; }
  Status send(const ContractorMessage& message) override;
  void close(const std::string& operation, const std::string& conversation) override;
  [[nodiscard]] bool alive() const { return alive_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] std::uint64_t closed() const { return closed_; }

 private:
  friend class MemoryNetwork;
  friend class MemoryManagerEndpoint;
  friend class MemoryConveyorEndpoint;
  MemoryContractorEndpoint(MemoryNetwork& net, std::string name, std::vector<std::string> operations)
      : net_(&net), name_(std::move(name)), operations_(std::move(operations)) {}
  [[nodiscard]] bool serves(const std::string& operation) const;
  MemoryNetwork* net_;
  std::string name_;
  std::vector<std::string> operations_;
  ContractorInbox* inbox_ = nullptr;
  bool alive_ = true;
  bool reported_lost_ = false;
  bool cut_off_ = false;
  std::uint64_t cuts_ = 0;  // which cut a liveliness expiry belongs to
  // While cut off: what waits to be sent again (deliveries to it, its own messages), in order.
  std::vector<std::function<void()>> held_;
  std::uint64_t closed_ = 0;
};

class MemoryConveyorEndpoint final : public ConveyorTransport {
 public:
  void bind(ConveyorInbox& inbox) { inbox_ = &inbox; }
  Status inform(const TransportInform& inform) override;
  void close(const std::string& conversation) override;

 private:
  friend class MemoryNetwork;
  friend class MemoryManagerEndpoint;
  friend class MemoryContractorEndpoint;
  MemoryConveyorEndpoint(MemoryNetwork& net, std::string name) : net_(&net), name_(std::move(name)) {}
  MemoryNetwork* net_;
  std::string name_;
  ConveyorInbox* inbox_ = nullptr;
};

struct MemoryNetworkStats {
  std::uint64_t sent = 0;
  std::uint64_t delivered = 0;
  std::uint64_t duplicated = 0;
  std::uint64_t dropped = 0;  // addressed to a dead contractor
};

class MemoryNetwork {
 public:
  explicit MemoryNetwork(const Clock& clock, MemoryNetworkOptions options = {});
  MemoryNetwork(const MemoryNetwork&) = delete;
  MemoryNetwork& operator=(const MemoryNetwork&) = delete;

  // Endpoints live as long as the network; bind each to its state machine.
  MemoryManagerEndpoint& add_manager();
  MemoryContractorEndpoint& add_contractor(std::string name, std::vector<std::string> operations);
  MemoryConveyorEndpoint& add_conveyor(std::string name);

  // The contractor's process dies: it neither sends nor receives from now on;
  // every manager gets on_contractor_lost for each of its operations after the lease.
  void kill(const std::string& contractor);
  // The contractor's link to the network is cut (a network partition shorter than the DDS
  // participants' lease, 10 s): it goes on working, but what it sends and what is sent to it waits;
  // every manager gets on_contractor_lost after the liveliness lease. reconnect() ends the cut:
  // managers get on_contractor_alive, then everything that waited is delivered in its order, as
  // reliable DDS writers send it again once their readers acknowledge.
  void cut_off(const std::string& contractor);
  void reconnect(const std::string& contractor);

  // Delivers every message due by now (in due order, including messages that
  // deliveries send with no latency). Returns how many were delivered.
  std::size_t deliver();
  [[nodiscard]] std::optional<Clock::time_point> next_delivery() const;
  [[nodiscard]] std::size_t in_flight() const { return queue_.size(); }
  [[nodiscard]] const MemoryNetworkStats& stats() const { return stats_; }
  void set_options(const MemoryNetworkOptions& options) { options_ = options; }

 private:
  friend class MemoryManagerEndpoint;
  friend class MemoryContractorEndpoint;
  friend class MemoryConveyorEndpoint;

  // `channel` names the sender and topic; with keep_order, a channel's
  // messages are delivered in the order sent.
  void post(const std::string& channel, std::function<void()> deliver);
  // A delivery to a contractor on `channel`: dropped when it is dead, held while it is cut off.
  void post_to(MemoryContractorEndpoint* to, const std::string& channel,
               std::function<void(ContractorInbox&)> deliver);
  // Every manager's inbox is told `what` for each operation of `contractor`.
  void tell_managers(const MemoryContractorEndpoint& contractor,
                     void (ManagerInbox::*what)(const std::string&, const std::string&));
  [[nodiscard]] Clock::time_point due_time(const std::string& channel);
  [[nodiscard]] std::size_t live_contractors(const std::string& operation) const;

  const Clock* clock_;
  MemoryNetworkOptions options_;
  std::mt19937_64 rng_;
  std::vector<std::unique_ptr<MemoryManagerEndpoint>> managers_;
  std::vector<std::unique_ptr<MemoryContractorEndpoint>> contractors_;
  std::vector<std::unique_ptr<MemoryConveyorEndpoint>> conveyors_;
  std::multimap<std::pair<Clock::time_point, std::uint64_t>, std::function<void()>> queue_;
  std::map<std::string, Clock::time_point> channel_due_;
  std::uint64_t seq_ = 0;
  MemoryNetworkStats stats_;
};

}  // namespace sf::negotiation
