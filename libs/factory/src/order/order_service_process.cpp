// The `orders` process (order_service.hpp): its configuration, the agent on DDS and its model on
// its own OPC UA server.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sf/core/config.hpp"
#include "sf/factory/controller_process.hpp"
#include "sf/factory/order_service.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::factory {

namespace {

Result<OrderServiceSetup> order_service_from(const Result<config::Node>& root,
                                             const std::filesystem::path& base) {
  if (!root) {
    return root.error();
  }
  SF_TRY(root->only_keys({"layout", "wip", "max_attempts", "orders", "opcua", "dds"}));
  OrderServiceSetup s;
  s.config.service.machine = "order-service";
  s.config.service.opcua_port = 4850;
  SF_TRY(parse_controller_settings(*root, s.config.service, base));
  SF_TRY(root->read("wip", s.config.host.wip));
  SF_TRY(root->read("max_attempts", s.config.host.max_attempts));
  if (s.config.host.max_attempts == 0) {
    return root->child("max_attempts")->error("at least 1");
  }
  auto layout = load_settings_layout(*root, s.config.service, base);
  if (!layout) {
    return layout.error();
  }
  s.layout = std::move(*layout);
  std::string orders;
  SF_TRY(root->read("orders", orders));
  if (!orders.empty()) {
    const std::filesystem::path file(orders);
    s.config.orders_file = file.is_absolute() ? file : base / file;
    auto list = load_orders(s.config.orders_file, s.layout.catalog);
    if (!list) {
      return list.error();
    }
    s.orders = std::move(*list);
  }
  return s;
}

}  // namespace

Result<OrderServiceSetup> load_order_service_config(const std::filesystem::path& file) {
  return order_service_from(config::load_file(file), file.parent_path());
}

Result<OrderServiceSetup> parse_order_service_config(std::string_view yaml, std::string name,
                                                     const std::filesystem::path& base) {
  return order_service_from(config::load_string(yaml, std::move(name)), base);
}

Result<std::unique_ptr<OrderServiceProcess>> OrderServiceProcess::create(OrderServiceSetup setup,
                                                                         Clock& clock) {
  auto p = std::unique_ptr<OrderServiceProcess>(new OrderServiceProcess(std::move(setup), clock));
  const ControllerSettings& c = p->setup_.config.service;
  auto agent = OrderServiceAgent::create(dds_settings(c.dds), p->setup_.layout, p->setup_.config.host,
                                         p->executor_, clock, [raw = p.get()](const OrderEvent& e) {
                                           // Every event reaches the model, so the cloud sees each step.
                                           if (raw->model_) {
                                             raw->model_->update();
                                             raw->model_->raise(e, raw->clock_->utc_now());
                                           }
                                           if (raw->on_event_) {
                                             raw->on_event_(e);
                                           }
                                         });
  if (!agent) {
    return Error(agent.error()).with_context("DDS");
  }
  p->agent_ = std::move(*agent);
  for (auto& o : p->setup_.orders) {
    SF_TRY(p->agent_->submit(o));
  }
  auto server = settings_server(c, clock, p->security_);
  if (!server) {
    return server.error();
  }
  p->server_ = std::move(*server);
  auto model = OrderModel::attach(*p->server_, *p->agent_);
  if (!model) {
    return model.error();
  }
  p->model_ = std::move(*model);
  if (auto started = p->server_->start(); !started) {
    return Error(started.error()).with_context(fmt::format("OPC UA server on port {}", c.opcua_port));
  }
  return p;
}

OrderServiceProcess::~OrderServiceProcess() {
  model_.reset();
  if (server_) {
    server_->stop();
  }
}

std::string OrderServiceProcess::opcua_endpoint() const {
  return settings_endpoint(setup_.config.service.opcua_host, server_->port());
}

void OrderServiceProcess::run(const std::function<bool()>& stop,
                              const std::function<void(const OrderEvent&)>& on_event,
                              const std::function<void(const OrderServiceStatus&)>& on_report,
                              std::chrono::nanoseconds interval) {
  on_event_ = on_event;
  StatusReporter reporter(
      *clock_,
      [this] {
        const auto s = agent_->status();
        return fmt::format("{}", fmt::join(s.orders, " "));
      },
      [&] {
        model_->update();
        if (on_report) {
          on_report(agent_->status());
        }
      },
      interval);
  negotiation::run_agents(executor_, *clock_, {agent_.get(), &reporter}, stop);
  on_event_ = nullptr;
}

}  // namespace sf::factory
