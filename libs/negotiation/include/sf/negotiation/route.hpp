// Conveyor route negotiation in the ConveyingDomain (paper §IV.B): a product
// REQUESTs transport from A to B; every conveyor INFORMs it of the segments it
// serves (conveyors know their own from/to only; a belt with stations serves
// one segment per stretch between them) and their transit times; the product
// composes the route from the INFORMs, shortest by ETA (Dijkstra over the
// conveyor graph, transit times as weights). Carrying the product along the
// route is work awarded to each conveyor on the route ("transport", a
// contractor's operation backed by the conveyor's controller).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/core/result.hpp"
#include "sf/negotiation/messages.hpp"
#include "sf/negotiation/transport.hpp"

namespace sf::negotiation {

struct Segment {
  std::string conveyor;
  std::string from;
  std::string to;
  std::chrono::nanoseconds transit_time{0};
  friend bool operator==(const Segment&, const Segment&) = default;
};

struct Route {
  std::string from;
  std::string to;
  std::vector<Segment> segments;  // empty when from == to
  [[nodiscard]] std::chrono::nanoseconds eta() const;
  // "Input -C1-> M1 -C4-> M3 (1.500 s)"
  [[nodiscard]] std::string describe() const;
};

// The route with the smallest total transit time, or nullopt if `to` cannot
// be reached. Ties go to fewer segments, then to conveyor names in order.
std::optional<Route> shortest_route(const std::vector<Segment>& segments, const std::string& from,
                                    const std::string& to);

struct RouteConfig {
  std::chrono::nanoseconds collect_window{std::chrono::milliseconds{300}};  // REQUEST → compose
  std::chrono::nanoseconds retry_delay{std::chrono::milliseconds{500}};     // after "no route"
  std::uint32_t max_attempts = 5;                                           // 0 = unlimited
  std::uint32_t incarnation = 0;                                            // 0 = random
};

using RouteCallback = std::function<void(const Result<Route>& route)>;

class RoutePlanner final : public RouteInbox {
 public:
  RoutePlanner(RouteTransport& transport, const Clock& clock, RouteConfig config = {});

  // Asks for transport; `done` is called exactly once (from tick() or
  // on_inform(), or at once if from == to). Returns the request's id.
  Result<std::string> plan(const std::string& product, const std::string& from, const std::string& to,
                           RouteCallback done);

  void on_inform(const TransportInform& inform) override;
  void tick();
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const;
  [[nodiscard]] std::size_t active() const { return requests_.size(); }
  [[nodiscard]] std::uint64_t ignored() const { return ignored_; }

 private:
  struct Pending {
    std::string product;
    std::string from;
    std::string to;
    std::uint32_t attempts = 0;
    std::vector<Segment> segments;
    std::map<std::string, std::uint16_t> missing;  // by conveyor: hops still to come
    std::size_t complete = 0;                      // conveyors whose every hop arrived
    Clock::time_point deadline{};
    bool waiting_retry = false;
    RouteCallback done;
  };

  void send_request(const std::string& id, Pending& p);
  void compose(const std::string& id);
  void ignore(const TransportInform& inform, std::string_view reason);

  RouteTransport* transport_;
  const Clock* clock_;
  RouteConfig config_;
  std::uint64_t next_seq_ = 0;
  std::map<std::string, Pending> requests_;
  std::uint64_t ignored_ = 0;
  log::Logger log_;
};

// A segment a conveyor offers for a REQUEST (ConveyorBackend).
struct Hop {
  std::string from;
  std::string to;
  std::chrono::nanoseconds transit_time{0};
  std::chrono::nanoseconds start_in{0};  // until the belt is free for it (work queued before)
};

// Where a conveyor's segments come from when a real controller stands behind
// it (a legacy conveyor's gateway, the factory module), as WorkBackend is for a
// contractor. Without one, the conveyor offers its configured segment. Called
// from the conveyor's thread.
class ConveyorBackend {
 public:
  virtual ~ConveyorBackend() = default;
  // The segments the belt serves now; none (why_not says why: faulted, held,
  // its PLC unreachable) and the conveyor does not answer, so routes avoid it.
  virtual std::vector<Hop> segments(const TransportRequest& request, std::string& why_not) = 0;
};

// The conveyor role: answers every REQUEST with its segments.
struct ConveyorConfig {
  std::string name;
  std::string from;  // the one segment, without a backend
  std::string to;
  std::chrono::nanoseconds transit_time{std::chrono::seconds{1}};
  ConveyorBackend* backend = nullptr;  // real segments; must outlive the conveyor
};

class Conveyor final : public ConveyorInbox {
 public:
  static Result<Conveyor> create(ConveyorTransport& transport, const Clock& clock, ConveyorConfig config);

  void on_request(const TransportRequest& request) override;
  void on_request_closed(const std::string& conversation) override;
  [[nodiscard]] const ConveyorConfig& config() const { return config_; }
  [[nodiscard]] std::uint64_t informs() const { return informs_; }
  [[nodiscard]] std::uint64_t ignored() const { return ignored_; }
  [[nodiscard]] std::uint64_t silent() const { return silent_; }  // REQUESTs its backend had nothing for

 private:
  Conveyor(ConveyorTransport& transport, const Clock& clock, ConveyorConfig config);
  [[nodiscard]] std::vector<Hop> hops(const TransportRequest& request);

  ConveyorTransport* transport_;
  const Clock* clock_;
  ConveyorConfig config_;
  std::set<std::string> answered_;
  std::uint64_t informs_ = 0;
  std::uint64_t ignored_ = 0;
  std::uint64_t silent_ = 0;
  log::Logger log_;
};

}  // namespace sf::negotiation
