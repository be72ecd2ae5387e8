// LineView (line_view.hpp): OPC UA reads of the line's order service and controllers.
#include "sf/factory/line_view.hpp"

#include <fmt/format.h>

#include "sf/factory/line_hosts.hpp"
#include "sf/line/ontology.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/client/security_setup.hpp"

namespace sf::factory {

namespace ua = sf::opcua;

namespace {

std::string endpoint(const LinePlan& plan, const LineProcess& p) {
  const ProcessHost* host = plan.host_of(p);
  return fmt::format("opc.tcp://{}:{}", host != nullptr ? host->address(HostNetworkKind::opcua) : "127.0.0.1",
                     p.opcua_port);
}

// `make` in the namespace of p's host (the client's thread and sockets are made there), or here.
Status in_host_of(const LinePlan& plan, const LineProcess& p, const std::function<void()>& make) {
  const ProcessHost* host = plan.host_of(p);
  if (host == nullptr) {
    make();
    return {};
  }
  return with_netns(host->netns, make);
}

template <class T>
T value_or_zero(const Result<ua::DataValue>& v) {
  return v && v->value.get_if<T>() != nullptr ? *v->value.get_if<T>() : T{};
}

}  // namespace

LineView::LineView(LineView&&) noexcept = default;
LineView& LineView::operator=(LineView&&) noexcept = default;
LineView::~LineView() = default;

Result<LineView> LineView::open(const LinePlan& plan) {
  for (const auto& p : plan.processes) {
    if (p.role != LineRole::orders) {
      continue;
    }
    ua::ClientConfig c;
    c.session_name = "smartfactory line view";
    c.endpoint_url = endpoint(plan, p);
    LineView view;
    view.plan_ = &plan;
    SF_TRY(in_host_of(plan, p, [&] { view.orders_ = std::make_unique<ua::SyncClient>(c); }));
    return view;
  }
  return make_error(Errc::not_found, "the line has no order service");
}

Result<OrderCounts> LineView::orders() {
  if (orders_->state() != ua::ClientState::Connected) {
    SF_TRY(orders_->connect());
    auto ns = orders_->namespace_index("urn:smartfactory:orders");
    if (!ns) {
      return ns.error();
    }
    ns_ = *ns;
  }
  const auto read = [&](std::string_view name) {
    return orders_->read_value(ua::NodeId(ns_, ua::String(fmt::format("OrderService.{}", name))));
  };
  OrderCounts c;
  for (auto [name, out] : {std::pair<const char*, std::uint32_t*>{"Queued", &c.queued},
                           {"InWork", &c.in_work},
                           {"Done", &c.done},
                           {"Failed", &c.failed},
                           {"Remade", &c.remade}}) {
    auto v = read(name);
    if (!v) {
      return v.error();
    }
    *out = value_or_zero<std::uint32_t>(v);
  }
  c.lead_p50 = value_or_zero<double>(read("LeadTimeP50"));
  c.lead_p99 = value_or_zero<double>(read("LeadTimeP99"));
  return c;
}

std::vector<WorkingTime> LineView::working_times() const {
  std::vector<WorkingTime> out;
  for (const auto& p : plan_->processes) {
    if (p.role != LineRole::machine && p.role != LineRole::gateway) {
      continue;
    }
    ua::ClientConfig c;
    c.endpoint_url = endpoint(*plan_, p);
    c.session_name = "smartfactory line view";
    c.auto_reconnect = false;
    if (!ua::configure_client_security({}, c)) {
      continue;
    }
    std::unique_ptr<ua::SyncClient> client;
    if (!in_host_of(*plan_, p, [&] {
          client = std::make_unique<ua::SyncClient>(c);
          (void)client->connect();
        })) {
      continue;
    }
    auto ns = client->state() == ua::ClientState::Connected
                  ? client->namespace_index("urn:smartfactory:machines")
                  : Result<std::uint16_t>(make_error(Errc::io, "down"));
    if (!ns) {
      continue;
    }
    auto v = client->read_value(ua::NodeId(*ns, ua::String(line::iri_name(p.name) + ".Job.WorkingTime")));
    if (v && v->value.get_if<double>() != nullptr) {
      out.push_back({p.name, *v->value.get_if<double>() / 1000.0});  // Duration: ms
    }
  }
  return out;
}

}  // namespace sf::factory
