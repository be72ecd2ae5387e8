#include "sf/factory/order_service.hpp"

#include <fmt/format.h>

#include "sf/factory/machine.hpp"
#include "sf/line/inspection.hpp"

namespace sf::factory {

namespace cnp = sf::negotiation;

Result<std::unique_ptr<OrderServiceAgent>> OrderServiceAgent::create(
    const cnp::DdsSettings& settings, const line::Layout& layout, OrderHostOptions options,
    dds::Executor& executor, const Clock& clock, OrderEventSink on_event) {
  const std::vector<std::string> operations{std::string(kUpload), std::string(kLoad), std::string(kDownload),
                                            std::string(kTransport)};
  auto endpoints = cnp::ProductEndpoints::create(settings, "order-service", operations, executor, clock);
  if (!endpoints) {
    return endpoints.error();
  }
  auto a = std::unique_ptr<OrderServiceAgent>(new OrderServiceAgent(layout, clock));
  a->endpoints_ = std::move(*endpoints);
  a->manager_ = std::make_unique<cnp::Manager>(*a->endpoints_, clock, product_manager_config());
  a->planner_ = std::make_unique<cnp::RoutePlanner>(*a->endpoints_, clock);
  a->endpoints_->bind(static_cast<cnp::ManagerInbox&>(*a->manager_));
  a->endpoints_->bind(static_cast<cnp::RouteInbox&>(*a->planner_));
  a->decisions_ = std::make_unique<ContractNetDecisions>(*a->manager_, *a->planner_);
  a->on_event_ = std::move(on_event);
  a->started_at_ = clock.now();
  auto* self = a.get();
  a->host_ = std::make_unique<OrderHost>(ProductContext{&layout, a->decisions_.get(), &clock}, options,
                                         [self](const OrderEvent& e) { self->note(e); });
  return a;
}

void OrderServiceAgent::note(const OrderEvent& e) {
  {
    std::lock_guard lock(mutex_);
    status_.last_event =
        fmt::format("{:.3f} {} {} {} {}", std::chrono::duration<double>(e.at - started_at_).count(), e.order,
                    e.what, e.machine, e.detail);
    // Its own variable: an inspection and the order's end come in one turn of the loop,
    // faster than a client samples.
    if (e.what == "inspected" && e.inspection) {
      status_.last_inspection = line::format_inspection(inspection_record(e, host_->records().at(e.order)));
    }
  }
  if (on_event_) {
    on_event_(e);
  }
}

OrderServiceAgent::~OrderServiceAgent() = default;

Status OrderServiceAgent::submit(Order order) {
  if (auto valid = validate(order, layout_->catalog); !valid) {
    return make_error(Errc::invalid_argument, fmt::format("order '{}': {}", order.id, valid.error().message));
  }
  std::lock_guard lock(mutex_);
  if (!ids_.insert(order.id).second) {
    return make_error(Errc::invalid_argument, fmt::format("order '{}' was accepted before", order.id));
  }
  inbox_.push_back(std::move(order));
  return {};
}

Status OrderServiceAgent::cancel(const std::string& id) {
  std::lock_guard lock(mutex_);
  if (!ids_.contains(id)) {
    return make_error(Errc::not_found, fmt::format("no order '{}'", id));
  }
  cancels_.push_back(id);
  return {};
}

void OrderServiceAgent::tick() {
  std::deque<Order> arrived;
  std::deque<std::string> cancels;
  {
    std::lock_guard lock(mutex_);
    arrived.swap(inbox_);
    cancels.swap(cancels_);
  }
  for (auto& o : arrived) {
    (void)host_->submit(std::move(o));  // checked in submit(); ids are unique there
  }
  // Before the host admits queued orders: an order still queued when the request came is
  // withdrawn, not started.
  for (const auto& id : cancels) {
    if (auto cancelled = host_->cancel(id); !cancelled) {
      note({clock_->now(), id, "cancel-refused", {}, cancelled.error().message, std::nullopt});
    }
  }
  manager_->tick();
  planner_->tick();
  host_->tick();
  endpoints_->flush_ended();
  publish();
}

std::optional<Clock::time_point> OrderServiceAgent::next_deadline() const {
  // The products' retries and belt waits are checked every few milliseconds; orders handed in
  // from other threads are picked up as soon.
  const auto soon = clock_->now() + std::chrono::milliseconds{10};
  return sf::earliest(soon, sf::earliest(manager_->next_deadline(),
                                         sf::earliest(planner_->next_deadline(), endpoints_->ends_due())));
}

void OrderServiceAgent::publish() {
  std::lock_guard lock(mutex_);
  const std::size_t done_before = status_.count(OrderState::done);
  for (std::size_t state = 0; state < kOrderStates; ++state) {
    status_.orders.at(state) = host_->count(static_cast<OrderState>(state));
  }
  status_.remade = host_->remade();
  if (status_.count(OrderState::done) != done_before) {  // lead times change only when one is done
    status_.lead_s = {std::chrono::duration<double>(host_->lead_time(0.5)).count(),
                      std::chrono::duration<double>(host_->lead_time(0.99)).count()};
  }
}

OrderServiceStatus OrderServiceAgent::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

}  // namespace sf::factory
