// Recording transports and message builders for the negotiation unit tests.
#pragma once

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/negotiation/messages.hpp"
#include "sf/negotiation/transport.hpp"

namespace sf::negotiation::test {

using namespace std::chrono_literals;

struct RecordingManagerTransport final : ManagerTransport, RouteTransport {
  std::vector<Announce> announces;
  std::vector<ManagerMessage> sent;
  std::vector<std::string> closed;  // conversation ids
  std::vector<TransportRequest> requests;
  std::vector<std::string> closed_requests;
  std::size_t listening = 0;  // contractors(op)
  std::size_t conveyor_count = 0;
  bool fail = false;

  Status announce(const Announce& a) override {
    if (fail) {
      return Error{Errc::io, "down"};
    }
    announces.push_back(a);
    return {};
  }
  Status send(const ManagerMessage& m) override {
    if (fail) {
      return Error{Errc::io, "down"};
    }
    sent.push_back(m);
    return {};
  }
  void close(const std::string& /*op*/, const std::string& conversation) override {
    closed.push_back(conversation);
  }
  [[nodiscard]] std::size_t contractors(const std::string& /*op*/) const override { return listening; }
  Status request(const TransportRequest& r) override {
    requests.push_back(r);
    return {};
  }
  void close(const std::string& conversation) override { closed_requests.push_back(conversation); }
  [[nodiscard]] std::size_t conveyors() const override { return conveyor_count; }

  template <typename Kind>
  [[nodiscard]] std::vector<ManagerMessage> of_kind() const {
    std::vector<ManagerMessage> out;
    std::copy_if(sent.begin(), sent.end(), std::back_inserter(out),
                 [](const ManagerMessage& m) { return std::holds_alternative<Kind>(m.body); });
    return out;
  }
};

struct RecordingContractorTransport final : ContractorTransport, ConveyorTransport {
  std::vector<ContractorMessage> sent;
  std::vector<std::string> closed;
  std::vector<TransportInform> informs;

  Status send(const ContractorMessage& m) override {
    sent.push_back(m);
    return {};
  }
  void close(const std::string& /*op*/, const std::string& conversation) override {
    closed.push_back(conversation);
  }
  Status inform(const TransportInform& i) override {
    informs.push_back(i);
    return {};
  }
  void close(const std::string& conversation) override { closed.push_back(conversation); }

  template <typename Kind>
  [[nodiscard]] std::vector<ContractorMessage> of_kind() const {
    std::vector<ContractorMessage> out;
    std::copy_if(sent.begin(), sent.end(), std::back_inserter(out),
                 [](const ContractorMessage& m) { return std::holds_alternative<Kind>(m.body); });
    return out;
  }
};

inline ContractorMessage from(const std::string& conversation, const std::string& contractor,
                              std::uint32_t round, ContractorBody body,
                              const std::string& operation = "OP1") {
  return ContractorMessage{conversation, contractor, operation, round, std::move(body)};
}

// A bid finishing `finish` from now (UTC of the clock).
inline Bid bid_at(const Clock& clock, std::chrono::milliseconds finish, double cost = 1.0,
                  std::uint32_t queue = 0) {
  return Bid{clock.utc_now(), clock.utc_now() + finish, cost, queue};
}

}  // namespace sf::negotiation::test
