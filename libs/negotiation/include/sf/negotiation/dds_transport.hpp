// The Contract Net transports over DDS, laid out as the paper's Fig. 4:
//
//   MachiningDomain                          ConveyingDomain
//   product  per required OPx: writer OPx_ANNOUNCE, writer OPx_AWARD,
//            reader OPx_BID                  writer REQUEST, reader INFORM
//   machine  per supported OPx: reader OPx_ANNOUNCE, reader OPx_AWARD,
//            writer OPx_BID                  —
//   conveyor —                               reader REQUEST, writer INFORM
//
// A product has one participant per domain, machines and conveyors one each.
// All endpoints are RELIABLE, TRANSIENT_LOCAL with KEEP_LAST(history_depth):
// a contractor that starts late still sees the open calls, and a message sent
// before discovery completed still arrives. Each conversation is an instance
// (keyed by its id), disposed and unregistered when it ends, so writer
// histories hold live conversations only. Ends leave in batches, one flush
// per writer: close() queues the end, flush_ended() sends the queue once its
// oldest end waited 50 ms (the agents call it on every turn of their loop and
// wake at ends_due()), a full queue leaves at once. Readers in the same
// process see the end when it leaves. A machine's OPx_BID writer has
// MANUAL_BY_TOPIC liveliness with a short lease, asserted by its BIDs and by
// the machine's agent loop (assert_liveliness()): when the machine dies or its
// agent stops, every product's OPx_BID reader sees LIVELINESS_CHANGED for that
// writer and the manager renegotiates what the machine had confirmed.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/config.hpp"
#include "sf/dds/executor.hpp"
#include "sf/dds/participant.hpp"
#include "sf/negotiation/transport.hpp"

namespace sf::negotiation {

struct DdsSettings {
  dds::DomainId machining_domain = 10;
  dds::DomainId conveying_domain = 11;
  std::string partition = "smartfactory";  // separates plants (and test runs) on one network
  dds::NetworkConfig network = dds::loopback_network();
  std::chrono::nanoseconds liveliness_lease{std::chrono::seconds{1}};
  std::int32_t history_depth = 16;
};

// Settings from what a configuration file or command line gives: the domains,
// the partition, a network interface by name ("lo": loopback only, else
// multicast discovery on that interface) and the liveliness lease.
DdsSettings dds_settings(dds::DomainId machining_domain, dds::DomainId conveying_domain,
                         std::string partition, const std::string& interface, std::chrono::nanoseconds lease);

class ProductEndpoints final : public ManagerTransport, public RouteTransport {
 public:
  // `conveying`: also join the ConveyingDomain (for route negotiation). `clock` times the
  // batches of conversation ends.
  static Result<std::unique_ptr<ProductEndpoints>> create(const DdsSettings& settings,
                                                          const std::string& name,
                                                          const std::vector<std::string>& operations,
                                                          dds::Executor& executor, const Clock& clock,
                                                          bool conveying = true);
  ~ProductEndpoints() override;

  void bind(ManagerInbox& inbox);
  void bind(RouteInbox& inbox);

  Status announce(const Announce& announce) override;
  Status send(const ManagerMessage& message) override;
  void close(const std::string& operation, const std::string& conversation) override;
  // Sends the queued conversation ends once the oldest waited long enough (see above).
  void flush_ended();
  // When flush_ended() will send; nothing when no end waits.
  [[nodiscard]] std::optional<Clock::time_point> ends_due() const;
  [[nodiscard]] std::size_t contractors(const std::string& operation) const override;
  Status request(const TransportRequest& request) override;
  void close(const std::string& conversation) override;
  [[nodiscard]] std::size_t conveyors() const override;
  // Contractors whose OPx_BID writer is matched to this product's reader.
  [[nodiscard]] std::size_t bidders(const std::string& operation) const;

  [[nodiscard]] const dds::Participant& machining() const;
  [[nodiscard]] const dds::Participant* conveying() const;  // null without route negotiation

  struct Impl;

 private:
  explicit ProductEndpoints(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

class MachineEndpoints final : public ContractorTransport {
 public:
  static Result<std::unique_ptr<MachineEndpoints>> create(const DdsSettings& settings,
                                                          const std::string& name,
                                                          const std::vector<std::string>& operations,
                                                          dds::Executor& executor, const Clock& clock);
  ~MachineEndpoints() override;

  void bind(ContractorInbox& inbox);
  Status send(const ContractorMessage& message) override;
  void close(const std::string& operation, const std::string& conversation) override;
  // Sends the queued conversation ends once the oldest waited long enough (see above).
  void flush_ended();
  // When flush_ended() will send; nothing when no end waits.
  [[nodiscard]] std::optional<Clock::time_point> ends_due() const;
  // Asserts the liveliness of every OPx_BID writer that wrote nothing for a third of the lease
  // (the agents call it on every turn of their loop and wake at liveliness_due()). Cyclone does
  // not assert it by itself: a machine whose loop stops is presumed dead after the lease, like one
  // that crashed.
  void assert_liveliness();
  [[nodiscard]] std::optional<Clock::time_point> liveliness_due() const;
  [[nodiscard]] const dds::Participant& participant() const;
  // Products currently listening (matched to this machine's OPx_BID writers).
  [[nodiscard]] std::size_t managers(const std::string& operation) const;

  struct Impl;

 private:
  explicit MachineEndpoints(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

class ConveyorEndpoints final : public ConveyorTransport {
 public:
  static Result<std::unique_ptr<ConveyorEndpoints>> create(const DdsSettings& settings,
                                                           const std::string& name, dds::Executor& executor);
  ~ConveyorEndpoints() override;

  void bind(ConveyorInbox& inbox);
  Status inform(const TransportInform& inform) override;
  void close(const std::string& conversation) override;
  [[nodiscard]] const dds::Participant& participant() const;

  struct Impl;

 private:
  explicit ConveyorEndpoints(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sf::negotiation
