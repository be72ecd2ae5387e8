#include "sf/negotiation/route.hpp"

#include <algorithm>
#include <limits>
#include <queue>
#include <tuple>

#include <fmt/format.h>

#include "support.hpp"

namespace sf::negotiation {
namespace {

using detail::random_incarnation;

struct Reach {
  std::chrono::nanoseconds time{0};
  std::size_t hops = 0;
  bool operator<(const Reach& o) const { return std::tie(time, hops) < std::tie(o.time, o.hops); }
};

}  // namespace

std::chrono::nanoseconds Route::eta() const {
  std::chrono::nanoseconds total{0};
  for (const auto& s : segments) {
    total += s.transit_time;
  }
  return total;
}

std::string Route::describe() const {
  std::string out = from;
  for (const auto& s : segments) {
    out += fmt::format(" -{}-> {}", s.conveyor, s.to);
  }
  return out + fmt::format(" ({:.3f} s)", std::chrono::duration<double>(eta()).count());
}

std::optional<Route> shortest_route(const std::vector<Segment>& segments, const std::string& from,
                                    const std::string& to) {
  if (from == to) {
    return Route{from, to, {}};
  }
  std::vector<Segment> edges = segments;
  std::sort(edges.begin(), edges.end(),
            [](const Segment& a, const Segment& b) { return a.conveyor < b.conveyor; });
  std::map<std::string, Reach> best;
  std::map<std::string, const Segment*> via;
  using Item = std::pair<Reach, std::string>;
  auto later = [](const Item& a, const Item& b) { return b.first < a.first; };
  std::priority_queue<Item, std::vector<Item>, decltype(later)> queue{later};
  best[from] = Reach{};
  queue.push({Reach{}, from});
  while (!queue.empty()) {
    const auto [reach, node] = queue.top();
    queue.pop();
    if (best[node] < reach || node == to) {
      continue;
    }
    for (const auto& e : edges) {
      if (e.from != node || e.transit_time.count() < 0) {
        continue;
      }
      const Reach next{reach.time + e.transit_time, reach.hops + 1};
      auto it = best.find(e.to);
      if (it == best.end() || next < it->second) {
        best[e.to] = next;
        via[e.to] = &e;
        queue.push({next, e.to});
      }
    }
  }
  if (!via.contains(to)) {
    return std::nullopt;
  }
  Route route{from, to, {}};
  for (std::string at = to; at != from;) {
    const Segment* s = via.at(at);
    route.segments.push_back(*s);
    at = s->from;
  }
  std::reverse(route.segments.begin(), route.segments.end());
  return route;
}

RoutePlanner::RoutePlanner(RouteTransport& transport, const Clock& clock, RouteConfig config)
    : transport_(&transport), clock_(&clock), config_(config), log_(log::get("negotiation")) {
  if (config_.incarnation == 0) {
    config_.incarnation = random_incarnation();
  }
}

Result<std::string> RoutePlanner::plan(const std::string& product, const std::string& from,
                                       const std::string& to, RouteCallback done) {
  SF_TRY(validate_name("product", product));
  SF_TRY(validate_location(from));
  SF_TRY(validate_location(to));
  auto id = fmt::format("{}/route/{:x}.{}", product, config_.incarnation, ++next_seq_);
  if (id.size() > kMaxConversation) {
    return Error{Errc::limit_exceeded,
                 fmt::format("request id '{}' is longer than {}", id, kMaxConversation)};
  }
  if (from == to) {
    done(Route{from, to, {}});
    return id;
  }
  Pending& p = requests_[id];
  p.product = product;
  p.from = from;
  p.to = to;
  p.done = std::move(done);
  send_request(id, p);
  return id;
}

void RoutePlanner::send_request(const std::string& id, Pending& p) {
  ++p.attempts;
  p.segments.clear();
  p.missing.clear();
  p.complete = 0;
  p.waiting_retry = false;
  p.deadline = clock_->now() + config_.collect_window;
  if (auto st = transport_->request({id, p.product, p.from, p.to, clock_->utc_now()}); !st) {
    log_->warn("{}: REQUEST failed: {}", id, st.error().describe());
    p.waiting_retry = true;
    p.deadline = clock_->now() + config_.retry_delay;
  }
}

void RoutePlanner::on_inform(const TransportInform& i) {
  auto it = requests_.find(i.conversation);
  if (it == requests_.end()) {
    ++ignored_;
    log_->debug("ignored INFORM {} from {}: unknown or finished request", i.conversation, i.conveyor);
    return;
  }
  Pending& p = it->second;
  if (p.waiting_retry) {
    ignore(i, "arrived after the collection window");
    return;
  }
  if (i.from.empty() || i.to.empty() || i.from == i.to || i.transit_time.count() < 0 || i.hops == 0) {
    ignore(i, "malformed segment");
    return;
  }
  const bool known = std::any_of(p.segments.begin(), p.segments.end(), [&](const Segment& s) {
    return s.conveyor == i.conveyor && s.from == i.from && s.to == i.to;
  });
  auto [missing, first] = p.missing.try_emplace(i.conveyor, i.hops);
  if (known || missing->second == 0) {
    ignore(i, "duplicate INFORM");
    return;
  }
  p.segments.push_back(Segment{i.conveyor, i.from, i.to, i.transit_time});
  // A conveyor has answered once every segment it announced (hops) arrived.
  if (--missing->second == 0) {
    ++p.complete;
  }
  const std::size_t expected = transport_->conveyors();
  if (expected > 0 && p.complete >= expected) {
    compose(i.conversation);
  }
}

void RoutePlanner::compose(const std::string& id) {
  auto it = requests_.find(id);
  Pending& p = it->second;
  const std::vector<Segment> segments = p.segments;
  auto route = shortest_route(segments, p.from, p.to);
  transport_->close(id);
  if (route || (config_.max_attempts != 0 && p.attempts >= config_.max_attempts)) {
    auto node = requests_.extract(it);
    if (route) {
      node.mapped().done(*route);
    } else {
      node.mapped().done(
          Error{Errc::not_found, fmt::format("no conveyor route from {} to {} ({} segments offered)", p.from,
                                             p.to, segments.size())});
    }
    return;
  }
  log_->info("{}: no route from {} to {} among {} segments; asking again", id, p.from, p.to, segments.size());
  // A new request id, so conveyors answer afresh.
  auto node = requests_.extract(it);
  node.key() = fmt::format("{}/route/{:x}.{}", node.mapped().product, config_.incarnation, ++next_seq_);
  node.mapped().waiting_retry = true;
  node.mapped().deadline = clock_->now() + config_.retry_delay;
  requests_.insert(std::move(node));
}

void RoutePlanner::tick() {
  const auto now = clock_->now();
  std::vector<std::string> due;
  for (const auto& [id, p] : requests_) {
    if (p.deadline <= now) {
      due.push_back(id);
    }
  }
  for (const auto& id : due) {
    auto it = requests_.find(id);
    if (it == requests_.end()) {
      continue;
    }
    if (it->second.waiting_retry) {
      send_request(id, it->second);
    } else {
      compose(id);
    }
  }
}

std::optional<Clock::time_point> RoutePlanner::next_deadline() const {
  std::optional<Clock::time_point> next;
  for (const auto& [id, p] : requests_) {
    if (!next || p.deadline < *next) {
      next = p.deadline;
    }
  }
  return next;
}

void RoutePlanner::ignore(const TransportInform& i, std::string_view reason) {
  ++ignored_;
  log_->info("ignored INFORM {} from {}: {}", i.conversation, i.conveyor, reason);
}

Result<Conveyor> Conveyor::create(ConveyorTransport& transport, const Clock& clock, ConveyorConfig config) {
  SF_TRY(validate_name("conveyor", config.name));
  if (config.backend != nullptr) {
    return Conveyor{transport, clock, std::move(config)};  // the backend names the segments
  }
  SF_TRY(validate_location(config.from));
  SF_TRY(validate_location(config.to));
  if (config.from == config.to) {
    return Error{Errc::invalid_argument,
                 fmt::format("conveyor {} goes from {} to itself", config.name, config.from)};
  }
  if (config.transit_time.count() < 0) {
    return Error{Errc::invalid_argument, "negative transit time"};
  }
  return Conveyor{transport, clock, std::move(config)};
}

Conveyor::Conveyor(ConveyorTransport& transport, const Clock& clock, ConveyorConfig config)
    : transport_(&transport), clock_(&clock), config_(std::move(config)), log_(log::get("negotiation")) {}

void Conveyor::on_request(const TransportRequest& r) {
  if (r.from.empty() || r.to.empty() || r.conversation.empty()) {
    ++ignored_;
    log_->info("{} ignored REQUEST {}: missing from/to", config_.name, r.conversation);
    return;
  }
  if (!answered_.insert(r.conversation).second) {
    ++ignored_;
    log_->info("{} ignored REQUEST {}: duplicate", config_.name, r.conversation);
    return;
  }
  const auto offered = hops(r);
  if (offered.empty()) {
    ++silent_;
    answered_.erase(r.conversation);
    return;
  }
  const auto now = clock_->utc_now();
  for (const Hop& h : offered) {
    const auto start =
        std::max(r.earliest_start, now + std::chrono::duration_cast<UtcTime::duration>(h.start_in));
    const TransportInform inform{r.conversation,
                                 config_.name,
                                 h.from,
                                 h.to,
                                 h.transit_time,
                                 start + std::chrono::duration_cast<UtcTime::duration>(h.transit_time),
                                 static_cast<std::uint16_t>(offered.size())};
    if (auto st = transport_->inform(inform); !st) {
      log_->warn("{}: INFORM {} failed: {}", config_.name, r.conversation, st.error().describe());
      return;  // the product composes without the rest when its window closes
    }
    ++informs_;
  }
}

std::vector<Hop> Conveyor::hops(const TransportRequest& r) {
  if (config_.backend == nullptr) {
    return {Hop{config_.from, config_.to, config_.transit_time, {}}};
  }
  std::string why_not;
  auto offered = config_.backend->segments(r, why_not);
  // A segment that cannot travel on the wire is left out, with the reason.
  std::erase_if(offered, [&](const Hop& h) {
    auto st = validate_location(h.from);
    if (st) {
      st = validate_location(h.to);
    }
    if (!st) {
      log_->warn("{}: segment {} -> {} left out: {}", config_.name, h.from, h.to, st.error().message);
    }
    return !st || h.from == h.to || h.transit_time.count() < 0;
  });
  if (offered.size() > std::numeric_limits<std::uint16_t>::max()) {
    offered.resize(std::numeric_limits<std::uint16_t>::max());
  }
  if (offered.empty()) {
    log_->info("{} does not answer REQUEST {}: {}", config_.name, r.conversation,
               why_not.empty() ? "no segment to offer" : why_not);
  }
  return offered;
}

void Conveyor::on_request_closed(const std::string& conversation) {
  if (answered_.erase(conversation) > 0) {
    transport_->close(conversation);
  }
}

}  // namespace sf::negotiation
