#include "sf/factory/order_agent.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sf/factory/conveying.hpp"
#include "sf/factory/machine.hpp"

namespace sf::factory {

namespace cnp = sf::negotiation;

bool BeltBlocks::reserve(const std::string& belt, const std::string& holder) {
  return held_.try_emplace(belt, holder).first->second == holder;
}

void BeltBlocks::release(const std::string& belt, const std::string& holder) {
  if (auto it = held_.find(belt); it != held_.end() && it->second == holder) {
    held_.erase(it);
  }
}

void BeltBlocks::release_all(const std::string& holder) {
  std::erase_if(held_, [&](const auto& h) { return h.second == holder; });
}

std::string belt_of(const std::string& place) {
  return place.substr(0, place.find('/'));
}

negotiation::ManagerConfig product_manager_config() {
  negotiation::ManagerConfig c;
  c.lost_grace = kLostGrace;
  return c;
}

std::shared_ptr<OrderAgent> OrderAgent::create(Order order, std::string product,
                                               const ProductContext& context, OrderAgentOptions options,
                                               OrderEventSink sink) {
  return std::shared_ptr<OrderAgent>(
      new OrderAgent(std::move(order), std::move(product), context, options, std::move(sink)));
}

OrderAgent::OrderAgent(Order order, std::string product, const ProductContext& context,
                       OrderAgentOptions options, OrderEventSink sink)
    : order_(std::move(order)),
      product_(std::move(product)),
      context_(context),
      layout_(context.layout),
      clock_(context.clock),
      options_(options),
      sink_(std::move(sink)) {
  const line::Layout& layout = *layout_;
  const double box_type = static_cast<double>(*layout.catalog.box_index(order_.box_type));
  steps_.push_back({std::string(kUpload), {{"box_type", box_type}}});
  for (const LoadTask& t : load_tasks(order_, layout.catalog, options_.max_per_load)) {
    steps_.push_back({std::string(kLoad),
                      {{"candy", static_cast<double>(t.candy)},
                       {"count", static_cast<double>(t.count)},
                       {"slot", static_cast<double>(t.first_slot)},
                       {"box_type", box_type}}});
  }
  steps_.push_back({std::string(kDownload), {}});
}

template <typename F>
auto OrderAgent::guarded(F f) {
  return [weak = weak_from_this(), f = std::move(f)](auto&&... args) {
    if (auto self = weak.lock(); self && !self->finished_) {
      f(*self, std::forward<decltype(args)>(args)...);
    }
  };
}

Status OrderAgent::start() {
  if (auto valid = validate(order_, layout_->catalog); !valid) {
    return valid;
  }
  begin_step();
  return {};
}

void OrderAgent::tick() {
  if (!finished_ && !waiting_for_.empty() && context_.belts->reserve(waiting_for_, product_)) {
    waiting_for_.clear();
    auto then = std::move(on_belt_);
    on_belt_ = nullptr;
    then();
  }
  if (finished_ || !retry_at_ || clock_->now() < *retry_at_) {
    return;
  }
  retry_at_.reset();
  auto again = std::move(retry_);
  retry_ = nullptr;
  again();
}

void OrderAgent::with_belt(const std::string& belt, std::function<void()> then) {
  if (context_.belts == nullptr || context_.belts->reserve(belt, product_)) {
    return then();
  }
  waiting_for_ = belt;
  on_belt_ = std::move(then);
}

void OrderAgent::begin_step() {
  const StepOp& op = steps_[step_];
  // The uploader puts the box on its belt: the belt must be this box's first.
  if (op.type == kUpload && context_.belts != nullptr &&
      !context_.belts->reserve(belt_of(layout_->uploader.station), product_)) {
    return with_belt(belt_of(layout_->uploader.station), [this] { begin_step(); });
  }
  machine_.clear();
  target_.clear();
  std::vector<cnp::Param> params = op.params;
  if (box_ != 0) {
    params.push_back({"box", static_cast<double>(box_)});
  }
  cnp::ConversationEvents events{
      guarded([](OrderAgent& a, const cnp::Conversation& c) { a.on_confirmed(c); }),
      guarded([](OrderAgent& a, const cnp::Conversation& c) { a.on_work_done(c); }),
      guarded([](OrderAgent& a, const cnp::Conversation& c) {
        a.retry(fmt::format("{} found no machine: {}", c.operation, c.failure), [&a] { a.begin_step(); });
      })};
  auto id = context_.decisions->negotiate({product_, op.type, std::move(params), {}}, std::move(events));
  if (!id) {
    finish(fmt::format("{} cannot be negotiated: {}", op.type, id.error().describe()));
  }
}

void OrderAgent::on_confirmed(const cnp::Conversation& c) {
  machine_ = c.contractor;
  target_ = station_of(machine_);
  // The Contract Net of the step in one line: the round and the bids it was awarded on (the
  // cloud shows an order's negotiation from these).
  std::vector<std::string> bids;
  for (const auto& [bidder, bid] : c.bids) {
    bids.push_back(fmt::format("{} cost {:.2f} queue {}", bidder, bid.cost, bid.queue_length));
  }
  emit("awarded", machine_,
       fmt::format("{} (round {}; bids: {})", c.operation, c.round,
                   bids.empty() ? "-" : fmt::format("{}", fmt::join(bids, ", "))));
  // The uploader puts the box where it stands; every other machine needs it brought.
  if (steps_[step_].type != kUpload && !moving_ && location_ != target_) {
    route_to_machine();
  }
}

void OrderAgent::on_work_done(const cnp::Conversation& c) {
  const std::string& type = steps_[step_].type;
  std::map<std::string, double> results;
  for (const auto& r : c.results) {
    results[r.name] = r.value;
  }
  if (type == kUpload) {
    box_ = static_cast<std::uint16_t>(results["box"]);
    location_ = layout_->uploader.station;
    emit("uploaded", c.contractor, fmt::format("box {} at {}", box_, location_));
  } else if (type == kLoad) {
    emit("loaded", c.contractor, c.result);
  } else {
    BoxInspection in{static_cast<std::uint16_t>(results["box"]), results["weight_g"], {}};
    for (const auto& candy : layout_->catalog.candy_types) {
      if (const int n = static_cast<int>(results["count." + candy.name]); n != 0) {
        in.counts[candy.name] = n;
      }
    }
    inspection_ = in;
    emit("inspected", c.contractor, c.result, in);
    // A box whose content differs from its order goes out as a reject like one given up on: the
    // attempt fails and the host makes the order again.
    if (std::string mismatch = rejected_.empty() ? verify(in) : std::string{}; !mismatch.empty()) {
      reject(std::move(mismatch));
    }
    return finish(rejected_);
  }
  ++step_;
  retries_ = 0;
  begin_step();
}

void OrderAgent::route_to_machine() {
  // One route at a time, and only to a machine that confirmed the current step. A step may end
  // while its box is on the way to another machine (its first machine, cut off, did the work after
  // all); the box then stops where its transport ends until the next step's machine confirms.
  if (moving_ || target_.empty()) {
    return;
  }
  moving_ = true;
  auto id =
      context_.decisions->plan(product_, location_, target_,
                               guarded([](OrderAgent& a, const Result<cnp::Route>& r) { a.on_route(r); }));
  if (!id) {
    moving_ = false;
    retry(fmt::format("no route request: {}", id.error().describe()), [this] { route_to_machine(); });
  }
}

void OrderAgent::on_route(const Result<cnp::Route>& route) {
  if (!route) {
    moving_ = false;
    return retry(fmt::format("no route from {} to {}: {}", location_, target_, route.error().describe()),
                 [this] { route_to_machine(); });
  }
  hops_.clear();
  // One transport per conveyor: its consecutive segments merged (conveying.hpp).
  for (const auto& s : route->segments) {
    if (!hops_.empty() && hops_.back().conveyor == s.conveyor) {
      hops_.back().to = s.to;
    } else {
      hops_.push_back({s.conveyor, s.from, s.to});
    }
  }
  emit("routed", machine_, route->describe());
  next_transport();
}

void OrderAgent::next_transport() {
  if (location_ == target_ || hops_.empty() || target_.empty()) {
    moving_ = false;
    if (location_ != target_) {  // re-awarded to another machine on the way
      route_to_machine();
    }
    return;
  }
  const Hop hop = hops_.front();
  if (belt_of(hop.to) != belt_of(location_) && context_.belts != nullptr &&
      !context_.belts->reserve(belt_of(hop.to), product_)) {
    return with_belt(belt_of(hop.to), [this] { next_transport(); });
  }
  std::vector<cnp::Param> params{{"box", static_cast<double>(box_)},
                                 {"from", static_cast<double>(*place_index(*layout_, hop.from))},
                                 {"to", static_cast<double>(*place_index(*layout_, hop.to))}};
  cnp::ConversationEvents events{
      {},
      guarded([hop](OrderAgent& a, const cnp::Conversation& c) {
        if (a.context_.belts != nullptr && belt_of(hop.to) != belt_of(hop.from)) {
          a.context_.belts->release(belt_of(hop.from), a.product_);
        }
        a.location_ = hop.to;
        a.hops_.erase(a.hops_.begin());
        a.emit("transported", c.contractor, fmt::format("box {} {} → {}", a.box_, hop.from, hop.to));
        // A machine re-awarded on the way has another station: the rest of the route is stale.
        if (!a.hops_.empty() && a.hops_.back().to != a.target_) {
          a.hops_.clear();
        }
        a.next_transport();
      }),
      guarded([hop](OrderAgent& a, const cnp::Conversation& c) {
        a.moving_ = false;
        a.retry(fmt::format("transport {} → {} on {}: {}", hop.from, hop.to, hop.conveyor, c.failure),
                [&a] { a.route_to_machine(); });
      })};
  auto id = context_.decisions->negotiate(
      {product_, std::string(kTransport), std::move(params), hop.conveyor}, std::move(events));
  if (!id) {
    moving_ = false;
    retry(fmt::format("transport cannot be negotiated: {}", id.error().describe()),
          [this] { route_to_machine(); });
  }
}

void OrderAgent::retry(std::string why, std::function<void()> again) {
  if (++retries_ > options_.max_retries) {
    return give_up(fmt::format("gave up after {} tries: {}", options_.max_retries, why));
  }
  emit("retry", machine_, why);
  retry_at_ = clock_->now() + options_.retry_delay;
  retry_ = std::move(again);
}

void OrderAgent::give_up(std::string failure) {
  // A box left on the line would stand in others' way: it goes to the downloader as a reject
  // (once; if even that fails, the box stays where it is and the order fails).
  if (box_ == 0 || !rejected_.empty() || steps_[step_].type == kDownload) {
    return finish(rejected_.empty() ? std::move(failure) : rejected_);
  }
  reject(std::move(failure));
  step_ = steps_.size() - 1;
  retries_ = 0;
  begin_step();
}

void OrderAgent::reject(std::string why) {
  rejected_ = std::move(why);
  emit("rejected", machine_, rejected_);
}

void OrderAgent::finish(std::string failure) {
  if (finished_) {
    return;
  }
  failure_ = std::move(failure);
  emit(failure_.empty() ? "done" : "failed", machine_, failure_);
  finished_ = true;
  if (context_.belts != nullptr) {
    context_.belts->release_all(product_);
  }
}

void OrderAgent::emit(std::string what, std::string machine, std::string detail,
                      std::optional<BoxInspection> inspection) {
  if (sink_) {
    sink_({clock_->now(), order_.id, std::move(what), std::move(machine), std::move(detail),
           std::move(inspection)});
  }
}

std::string OrderAgent::station_of(const std::string& machine) const {
  if (machine == layout_->uploader.name) {
    return layout_->uploader.station;
  }
  if (machine == layout_->downloader.name) {
    return layout_->downloader.station;
  }
  if (const line::RobotSpec* robot = layout_->robot(machine); robot != nullptr) {
    return robot->stations.front();
  }
  return {};
}

std::string OrderAgent::verify(const BoxInspection& inspection) const {
  if (inspection.box != box_) {
    return fmt::format("content mismatch: box {} inspected instead of box {}", inspection.box, box_);
  }
  const auto wanted = order_.counts();
  if (inspection.counts == wanted) {
    return {};
  }
  std::string diff;
  for (const auto& candy : layout_->catalog.candy_types) {
    const int want = wanted.contains(candy.name) ? wanted.at(candy.name) : 0;
    const int got = inspection.counts.contains(candy.name) ? inspection.counts.at(candy.name) : 0;
    if (want != got) {
      diff += fmt::format("{}{} {} of {}", diff.empty() ? "" : ", ", got, candy.name, want);
    }
  }
  return fmt::format("content mismatch in box {}: {}", box_, diff);
}

}  // namespace sf::factory
