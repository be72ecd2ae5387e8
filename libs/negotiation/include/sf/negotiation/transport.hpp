// The seam between the Contract Net state machines and the network. The state
// machines talk to these interfaces only; the DDS implementation
// (dds_transport.hpp) maps them onto the paper's topics, the in-memory one
// (memory_transport.hpp) lets unit tests drive everything with a ManualClock.
//
// Outbound calls go through a *Transport; inbound messages arrive at the
// matching *Inbox, which the state machine implements and the transport is
// bound to. Transports deliver inbound messages on the application's thread.
#pragma once

#include <cstddef>
#include <string>

#include "sf/core/result.hpp"
#include "sf/negotiation/messages.hpp"

namespace sf::negotiation {

// --- MachiningDomain, manager (product) side --------------------------------
class ManagerInbox {
 public:
  virtual ~ManagerInbox() = default;
  virtual void on_contractor_message(const ContractorMessage& message) = 0;
  // The contractor's OPx_BID writer lost its liveliness (DDS LIVELINESS_CHANGED):
  // the contractor is presumed dead.
  virtual void on_contractor_lost(const std::string& operation, const std::string& contractor) = 0;
  // The same writer asserts its liveliness again (LIVELINESS_CHANGED, alive_count up).
  virtual void on_contractor_alive(const std::string& /*operation*/, const std::string& /*contractor*/) {}
};

class ManagerTransport {
 public:
  virtual ~ManagerTransport() = default;
  virtual Status announce(const Announce& announce) = 0;
  virtual Status send(const ManagerMessage& message) = 0;
  // The conversation is over: dispose its ANNOUNCE and AWARD instances.
  virtual void close(const std::string& operation, const std::string& conversation) = 0;
  // How many contractors currently listen for `operation` (DDS: readers
  // matched to OPx_ANNOUNCE). The manager closes bidding early once all answered.
  [[nodiscard]] virtual std::size_t contractors(const std::string& operation) const = 0;
};

// --- MachiningDomain, contractor (machine) side -----------------------------
class ContractorInbox {
 public:
  virtual ~ContractorInbox() = default;
  virtual void on_announce(const Announce& announce) = 0;
  virtual void on_manager_message(const ManagerMessage& message) = 0;
  // The manager disposed the conversation (or its writers are gone).
  virtual void on_conversation_closed(const std::string& operation, const std::string& conversation) = 0;
};

class ContractorTransport {
 public:
  virtual ~ContractorTransport() = default;
  virtual Status send(const ContractorMessage& message) = 0;
  // This contractor is done with the conversation: dispose its OPx_BID instance.
  virtual void close(const std::string& operation, const std::string& conversation) = 0;
};

// --- ConveyingDomain ----------------------------------------------------------
class RouteInbox {
 public:
  virtual ~RouteInbox() = default;
  virtual void on_inform(const TransportInform& inform) = 0;
};

class RouteTransport {
 public:
  virtual ~RouteTransport() = default;
  virtual Status request(const TransportRequest& request) = 0;
  virtual void close(const std::string& conversation) = 0;
  // Conveyors currently listening (DDS: readers matched to REQUEST).
  [[nodiscard]] virtual std::size_t conveyors() const = 0;
};

class ConveyorInbox {
 public:
  virtual ~ConveyorInbox() = default;
  virtual void on_request(const TransportRequest& request) = 0;
  virtual void on_request_closed(const std::string& conversation) = 0;
};

class ConveyorTransport {
 public:
  virtual ~ConveyorTransport() = default;
  virtual Status inform(const TransportInform& inform) = 0;
  virtual void close(const std::string& conversation) = 0;
};

}  // namespace sf::negotiation
