// `smartfactory orders --config FILE`: the order service, the process the products live in
// (libs/factory order_service.hpp); `smartfactory order ...`: a consumer's order handed to it
// over OPC UA (its SubmitOrder method). This file parses options and prints.
#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "opcua_security.hpp"
#include "sf/core/clock.hpp"
#include "sf/factory/order_service.hpp"
#include "sf/opcua/client/client.hpp"

namespace sf::app {
namespace {

constexpr const char* kOrdersHelp =
    "The order service (paper §VII): consumers' orders become products that negotiate their\n"
    "way through the line over DDS: a box of the order's type from the uploader, each candy\n"
    "line loaded by a robot that won it in the Contract Net, routes negotiated with the\n"
    "conveyors, the downloader's inspection checked against the order (a box whose content\n"
    "differs is made again). Orders come from the config's order file and from its OPC UA\n"
    "server's OrderService.SubmitOrder (`smartfactory order`); its counters and latest event\n"
    "are published there. Prints every order event (JSON lines with --json).\n\n"
    "order-service.yaml (configs/order-service.yaml):\n"
    "  layout: ../layouts/prototype-line.yaml   # default: the built-in layout\n"
    "  wip: 3                                    # boxes on the line at once (0: safe bound)\n"
    "  orders: orders.yaml                       # taken at start (optional)\n"
    "  opcua: {port: 4850, modes: none, anonymous: operator}\n"
    "  dds: {machining_domain: 10, conveying_domain: 11, interface: lo, partition: smartfactory}";

constexpr const char* kOrderHelp =
    "Hands one order to a running order service (`smartfactory orders`) through its OPC UA\n"
    "method OrderService.SubmitOrder, or every order of a file. The order is checked against\n"
    "the layout's catalog first: an unknown box or candy type, a quantity below 1, more candies\n"
    "than the box holds are refused with the offending line named and exit status 2.\n"
    "  smartfactory order --box small-box --candy gummy:4 --candy toffee:8\n"
    "  smartfactory order --file orders.yaml";

using nlohmann::json;
namespace fy = sf::factory;
namespace ua = sf::opcua;

struct ServiceOptions {
  std::string config;
  bool json = false;
  double status_interval_s = 10;
};

int run_service(const ServiceOptions& o) {
  auto setup = fy::load_order_service_config(o.config);
  if (!setup) {
    std::cerr << "orders: " << setup.error().message << "\n";
    return kExitUsage;
  }
  auto& clock = SteadyClock::instance();
  auto process = fy::OrderServiceProcess::create(std::move(*setup), clock);
  if (!process) {
    std::cerr << "orders: " << process.error().describe() << "\n";
    return kExitFailure;
  }
  install_stop_signals();
  const auto& c = (*process)->setup().config.service;
  if (o.json) {
    std::cout << json{{"event", "ready"},
                      {"machine", "order-service"},
                      {"opcua", (*process)->opcua_endpoint()},
                      {"opcua_security", (*process)->opcua_security()},
                      {"machining_domain", c.dds.machining_domain},
                      {"conveying_domain", c.dds.conveying_domain},
                      {"orders", (*process)->setup().orders.size()}}
                     .dump()
              << std::endl;
  } else {
    std::cout << fmt::format(
                     "order service: OPC UA {} ({}); DDS domains {}/{} on {}; {} orders from its file\n",
                     (*process)->opcua_endpoint(), (*process)->opcua_security(), c.dds.machining_domain,
                     c.dds.conveying_domain, c.dds.interface, (*process)->setup().orders.size())
              << std::flush;
  }
  const auto started = clock.now();
  (*process)->run(
      [] { return stop_requested(); },
      [&](const fy::OrderEvent& e) {
        const double t = std::chrono::duration<double>(e.at - started).count();
        if (o.json) {
          std::cout << json{{"event", "order"},     {"t", t},
                            {"order", e.order},     {"what", e.what},
                            {"machine", e.machine}, {"detail", e.detail}}
                           .dump()
                    << std::endl;
        } else {
          std::cout << fmt::format("{:9.3f} {} {} {} {}\n", t, e.order, e.what, e.machine, e.detail)
                    << std::flush;
        }
      },
      [&](const fy::OrderServiceStatus& s) {
        if (o.json) {
          std::cout << json{{"event", "status"},
                            {"queued", s.count(fy::OrderState::queued)},
                            {"in_work", s.count(fy::OrderState::in_work)},
                            {"done", s.count(fy::OrderState::done)},
                            {"failed", s.count(fy::OrderState::failed)},
                            {"remade", s.remade}}
                           .dump()
                    << std::endl;
        } else {
          std::cout << fmt::format("orders: {} queued, {} in work, {} done, {} failed ({} remade)\n",
                                   s.count(fy::OrderState::queued), s.count(fy::OrderState::in_work),
                                   s.count(fy::OrderState::done), s.count(fy::OrderState::failed), s.remade)
                    << std::flush;
        }
      },
      std::chrono::duration_cast<std::chrono::nanoseconds>(
          std::chrono::duration<double>(o.status_interval_s)));
  return kExitOk;
}

struct OrderOptions {
  std::string server = "opc.tcp://localhost:4850";
  std::string layout;
  std::string id;
  std::string box;
  std::vector<std::string> candy;
  std::string file;
  double timeout_s = 10;
  ClientSecurityOptions security;
};

// The orders the options give, checked against the layout's catalog.
Result<std::vector<fy::Order>> orders_of(const OrderOptions& o, const line::Layout& layout) {
  if (!o.file.empty()) {
    return fy::load_orders(o.file, layout.catalog);
  }
  if (o.box.empty() || o.candy.empty()) {
    return make_error(Errc::invalid_argument, "give --box and at least one --candy TYPE:QUANTITY, or --file");
  }
  fy::Order order{o.id, o.box, {}};
  if (order.id.empty()) {
    order.id = fmt::format("cli-{}", std::chrono::duration_cast<std::chrono::milliseconds>(
                                         std::chrono::system_clock::now().time_since_epoch())
                                         .count());
  }
  for (const auto& c : o.candy) {
    auto l = fy::parse_order_line(c);
    if (!l) {
      return l.error();
    }
    order.lines.push_back(*l);
  }
  SF_TRY(fy::validate(order, layout.catalog));
  return std::vector<fy::Order>{order};
}

int run_order(const OrderOptions& o) {
  auto layout = o.layout.empty() ? line::default_layout() : line::load_layout(o.layout);
  if (!layout) {
    std::cerr << "order: " << layout.error().message << "\n";
    return kExitUsage;
  }
  auto orders = orders_of(o, *layout);
  if (!orders) {
    std::cerr << "order: " << orders.error().message << "\n";
    return kExitUsage;
  }
  ua::ClientConfig config;
  config.endpoint_url = o.server;
  config.session_name = "smartfactory order";
  config.request_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.timeout_s * 1000));
  config.auto_reconnect = false;
  if (auto st = apply_client_security(o.security, config); !st) {
    std::cerr << "order: " << st.error().message << "\n";
    return kExitUsage;
  }
  ua::SyncClient client(config);
  if (auto st = client.connect(); !st) {
    std::cerr << "order: cannot connect to the order service at " << o.server << ": " << st.error().message
              << "\n";
    return kExitFailure;
  }
  auto ns = client.namespace_index("urn:smartfactory:orders");
  if (!ns) {
    std::cerr << "order: " << o.server << " is not an order service (no urn:smartfactory:orders)\n";
    return kExitFailure;
  }
  int rc = kExitOk;
  for (const auto& order : *orders) {
    std::vector<ua::String> candy;
    for (const auto& l : order.lines) {
      candy.emplace_back(fmt::format("{}:{}", l.candy, l.quantity));
    }
    auto out = client.call_method(ua::NodeId(*ns, ua::String("OrderService")),
                                  ua::NodeId(*ns, ua::String("OrderService.SubmitOrder")),
                                  {ua::Variant(order.id), ua::Variant(order.box_type), ua::Variant(candy)});
    if (!out) {
      // BadInvalidArgument: the service refused the order itself (an id it accepted before).
      const bool refused = out.error().message.find("BadInvalidArgument") != std::string::npos;
      std::cerr << fmt::format("order {}: refused by the service{}: {}\n", order.id,
                               refused ? " (is its id taken?)" : "", out.error().message);
      rc = refused ? kExitUsage : kExitFailure;
      continue;
    }
    std::cout << fmt::format("order {} accepted: {} with {} candies\n", order.id, order.box_type,
                             order.total());
  }
  client.disconnect();
  return rc;
}

}  // namespace

void register_orders(CLI::App& app, CommandResult& result) {
  auto s = std::make_shared<ServiceOptions>();
  auto* service =
      app.add_subcommand("orders", "The order service: orders become products negotiating over DDS");
  service->add_option("--config", s->config, "The service's YAML file (layout, wip, orders, OPC UA, DDS)")
      ->required();
  service->add_flag("--json", s->json,
                    "Events as JSON lines on stdout: ready, status, and every order event "
                    "(t: seconds since the start, order, what, machine, detail)");
  service->add_option("--status-interval", s->status_interval_s, "Seconds between status lines")
      ->capture_default_str();
  service->footer(kOrdersHelp);
  service->callback([s, &result] { result.exit_code = run_service(*s); });

  auto o = std::make_shared<OrderOptions>();
  auto* order =
      app.add_subcommand("order", "Hand an order to the running order service (OPC UA SubmitOrder)");
  order->add_option("--server", o->server, "The order service's OPC UA endpoint")->capture_default_str();
  order->add_option("--layout", o->layout,
                    "Layout whose catalog orders are checked against (default: built-in)");
  order->add_option("--id", o->id, "The order's id (default: cli-<milliseconds>)");
  order->add_option("--box", o->box, "Box type, e.g. small-box");
  order->add_option("--candy", o->candy, "TYPE:QUANTITY, repeated, e.g. --candy gummy:4 --candy toffee:8");
  order->add_option("--file", o->file, "An order file (orders: [{id, box, candy: {TYPE: N}}])");
  order->add_option("--timeout", o->timeout_s, "Seconds to wait for the service")->capture_default_str();
  add_client_security_options(*order, o->security);
  order->footer(kOrderHelp);
  order->callback([o, &result] { result.exit_code = run_order(*o); });
}

}  // namespace sf::app
