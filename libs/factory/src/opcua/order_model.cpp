// OrderModel (order_service.hpp): the order service's counters, its latest event and the
// SubmitOrder method on its OPC UA server.
#include <array>
#include <random>

#include <fmt/format.h>

#include "opcua/model_nodes.hpp"
#include "sf/factory/order_service.hpp"
#include "sf/line/inspection.hpp"
#include "sf/opcua/node_ids.hpp"
#include "sf/opcua/server/server.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::factory {

namespace ua = sf::opcua;
namespace srv = sf::opcua::server;

namespace {

constexpr std::string_view kNamespace = "urn:smartfactory:orders";
constexpr std::array<std::string_view, 6> kCounters{"Queued", "InWork",    "Done",
                                                    "Failed", "Cancelled", "Remade"};
constexpr std::array<std::string_view, 2> kTexts{"LastEvent", "LastInspection"};
constexpr std::array<std::string_view, 2> kLeadTimes{"LeadTimeP50", "LeadTimeP99"};

ua::NodeId node(std::uint16_t ns, std::string_view path) {
  return {ns, ua::String(fmt::format("OrderService{}{}", path.empty() ? "" : ".", path))};
}

ua::Argument argument(std::string_view name, std::uint32_t type, bool array, std::string_view description) {
  ua::Argument a;
  a.name = std::string(name);
  a.data_type = ns0(type);
  a.value_rank = array ? srv::value_rank::OneDimension : srv::value_rank::Scalar;
  a.description = ua::LocalizedText("en", std::string(description));
  return a;
}

// SubmitOrder's inputs as an Order, or why they are not one.
Result<Order> order_of(const std::vector<ua::Variant>& in) {
  const auto* id = in.at(0).get_if<ua::String>();
  const auto* box = in.at(1).get_if<ua::String>();
  const auto* candy = in.at(2).array_if<ua::String>();
  if (id == nullptr || box == nullptr || candy == nullptr) {
    return make_error(Errc::invalid_argument, "SubmitOrder(Id: String, BoxType: String, Candy: String[])");
  }
  Order o{id->str(), box->str(), {}};
  for (const auto& c : *candy) {
    auto line = parse_order_line(c.view());
    if (!line) {
      return line.error();
    }
    o.lines.push_back(std::move(*line));
  }
  return o;
}

Status build(srv::AddressSpace& space, std::uint16_t ns, OrderServiceAgent& agent) {
  srv::ObjectSpec object;
  object.node_id = node(ns, "");
  object.browse_name = ua::QualifiedName(ns, "OrderService");
  object.parent = ns0(ua::id::ObjectsFolder);
  object.reference_type = ns0(ua::id::Organizes);
  object.type_definition = ns0(ua::id::BaseObjectType);
  SF_TRY(space.add_object(object));
  for (std::string_view name : kCounters) {
    auto spec = variable_spec(node(ns, name), ua::QualifiedName(ns, ua::String(name)), node(ns, ""),
                              ua::id::UInt32, false);
    spec.value = ua::DataValue(ua::Variant(std::uint32_t{0}));
    historize(spec);
    SF_TRY(space.add_variable(spec));
  }
  for (std::string_view name : kLeadTimes) {
    auto spec = variable_spec(node(ns, name), ua::QualifiedName(ns, ua::String(name)), node(ns, ""),
                              ua::id::Double, false);
    spec.value = ua::DataValue(ua::Variant(0.0));
    historize(spec);
    SF_TRY(space.add_variable(spec));
  }
  for (std::string_view name : kTexts) {
    auto text = variable_spec(node(ns, name), ua::QualifiedName(ns, ua::String(name)), node(ns, ""),
                              ua::id::String, false);
    text.value = ua::DataValue(ua::Variant(std::string()));
    historize(text);
    SF_TRY(space.add_variable(text));
  }

  srv::MethodSpec submit;
  submit.node_id = node(ns, "SubmitOrder");
  submit.browse_name = ua::QualifiedName(ns, "SubmitOrder");
  submit.parent = node(ns, "");
  submit.input_arguments = {argument("Id", ua::id::String, false, "the order's id, unique"),
                            argument("BoxType", ua::id::String, false, "a box type of the catalog"),
                            argument("Candy", ua::id::String, true, "candy type:quantity, e.g. gummy:4")};
  submit.output_arguments = {argument("OrderId", ua::id::String, false, "the accepted order's id")};
  submit.callback = [&agent](const ua::NodeId&, const std::vector<ua::Variant>& in,
                             std::vector<ua::Variant>& out) {
    auto order = order_of(in);
    if (!order) {
      return ua::StatusCode(ua::status::BadInvalidArgument);
    }
    const std::string id = order->id;
    if (auto accepted = agent.submit(std::move(*order)); !accepted) {
      return ua::StatusCode(ua::status::BadInvalidArgument);
    }
    out.emplace_back(id);
    return ua::StatusCode{};
  };
  SF_TRY(space.add_method(submit));

  srv::MethodSpec cancel;
  cancel.node_id = node(ns, "CancelOrder");
  cancel.browse_name = ua::QualifiedName(ns, "CancelOrder");
  cancel.parent = node(ns, "");
  cancel.input_arguments = {argument("Id", ua::id::String, false, "the id of an accepted order")};
  cancel.callback = [&agent](const ua::NodeId&, const std::vector<ua::Variant>& in,
                             std::vector<ua::Variant>&) {
    const auto* id = in.at(0).get_if<ua::String>();
    if (id == nullptr) {
      return ua::StatusCode(ua::status::BadInvalidArgument);
    }
    return ua::StatusCode(agent.cancel(id->str()) ? ua::status::Good : ua::status::BadNotFound);
  };
  SF_TRY(space.add_method(cancel));
  return {};
}

}  // namespace

Result<std::unique_ptr<OrderModel>> OrderModel::attach(srv::Server& server, OrderServiceAgent& agent) {
  auto m = std::unique_ptr<OrderModel>(new OrderModel());
  std::random_device random;
  for (auto& b : m->event_prefix_) {
    b = static_cast<std::uint8_t>(random());
  }
  m->server_ = &server;
  m->agent_ = &agent;
  Status built;
  server.with_address_space([&](srv::AddressSpace& space) {
    m->ns_ = space.add_namespace(kNamespace);
    built = build(space, m->ns_, agent);
  });
  if (!built) {
    return built.error();
  }
  return m;
}

void OrderModel::update() {
  const OrderServiceStatus s = agent_->status();
  const std::array<std::uint64_t, kCounters.size()> values{
      s.count(OrderState::queued), s.count(OrderState::in_work),   s.count(OrderState::done),
      s.count(OrderState::failed), s.count(OrderState::cancelled), s.remade};
  server_->with_address_space([&](srv::AddressSpace& space) {
    for (std::size_t i = 0; i < kCounters.size(); ++i) {
      (void)space.set_value(node(ns_, kCounters[i]),
                            ua::DataValue(ua::Variant(static_cast<std::uint32_t>(values[i]))));
    }
    (void)space.set_value(node(ns_, "LeadTimeP50"), ua::DataValue(ua::Variant(s.lead_s[0])));
    (void)space.set_value(node(ns_, "LeadTimeP99"), ua::DataValue(ua::Variant(s.lead_s[1])));
    (void)space.set_value(node(ns_, "LastEvent"), ua::DataValue(ua::Variant(s.last_event)));
    (void)space.set_value(node(ns_, "LastInspection"), ua::DataValue(ua::Variant(s.last_inspection)));
  });
}

void OrderModel::raise(const OrderEvent& e, Clock::utc_time at) {
  // BaseEventType's fields (OPC 10000-5 §6.4.2). EventId: unique per server (the historian keys
  // events by it): this model's random prefix and a running number.
  ua::SubscriptionService::Event event;
  event.event_type = ns0(ua::id::BaseEventType);
  const auto now = ua::DateTime::from_system_clock(at);
  Bytes id(event_prefix_.begin(), event_prefix_.end());
  for (std::uint64_t n = ++events_, i = 0; i < 8; ++i, n >>= 8U) {
    id.push_back(static_cast<std::uint8_t>(n));
  }
  event.fields["EventId"] = ua::Variant(ua::ByteString(std::move(id)));
  event.fields["EventType"] = ua::Variant(event.event_type);
  event.fields["SourceNode"] = ua::Variant(node(ns_, ""));
  event.fields["SourceName"] = ua::Variant(e.order);
  event.fields["Time"] = ua::Variant(now);
  event.fields["ReceiveTime"] = ua::Variant(now);
  event.fields["Message"] =
      ua::Variant(ua::LocalizedText("en", line::format_order_step({e.what, e.machine, e.detail})));
  const bool bad = e.what == "failed" || e.what == "rejected" || e.what == "cancel-refused";
  event.fields["Severity"] = ua::Variant(std::uint16_t{bad ? std::uint16_t{500} : std::uint16_t{100}});
  server_->raise_event(ns0(ua::id::Server), std::move(event));
}

}  // namespace sf::factory
