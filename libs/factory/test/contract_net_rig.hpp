// The gateways of a GatewayRig in the Contract Net over the in-memory
// transport, and a product's side of it that a test drives step by step (the
// negotiation module's manager role and route planner): an operation
// negotiated until its conversation ends, a route composed from the conveyors'
// INFORMs, a box carried along a route by awarding each conveyor its hop.
#pragma once

#include <list>
#include <memory>
#include <string>
#include <vector>

#include "gateway_rig.hpp"
#include "sf/factory/gateway_agent.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/memory_transport.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::factory::testing {

namespace cnp = sf::negotiation;

// What the product heard from the contractors, on its way to the manager.
struct ProductInbox final : cnp::ManagerInbox {
  explicit ProductInbox(cnp::Manager& m) : manager(&m) {}
  void on_contractor_message(const cnp::ContractorMessage& m) override {
    heard.push_back(m);
    manager->on_contractor_message(m);
  }
  void on_contractor_lost(const std::string& operation, const std::string& contractor) override {
    manager->on_contractor_lost(operation, contractor);
  }
  // The reasons `contractor` gave in messages of kind Body (Refuse, Failure).
  template <typename Body>
  std::vector<std::string> reasons(const std::string& contractor) const {
    std::vector<std::string> out;
    for (const auto& m : heard) {
      if (const auto* b = std::get_if<Body>(&m.body); b != nullptr && m.contractor == contractor) {
        out.push_back(b->reason);
      }
    }
    return out;
  }
  cnp::Manager* manager;
  std::vector<cnp::ContractorMessage> heard;
};

struct Negotiated {
  bool ok = false;
  std::string contractor;
  std::string failure;
  std::map<std::string, double> results;
};

class ContractNetRig {
 public:
  explicit ContractNetRig(GatewayRig& rig)
      : rig_(&rig),
        net_(rig.clock()),
        product_(net_.add_manager()),
        manager_(product_, rig.clock(), manager_config()),
        planner_(product_, rig.clock(), cnp::RouteConfig{300ms, 200ms, 2, 0xf}),
        inbox_(manager_) {
    product_.bind(static_cast<cnp::ManagerInbox&>(inbox_));
    product_.bind(static_cast<cnp::RouteInbox&>(planner_));
    rig.after_step([this] {
      net_.deliver();
      manager_.tick();
      planner_.tick();
      for (auto& r : roles_) {
        r->contractor().tick();
      }
    });
  }

  // A gateway of the rig with its roles on the in-memory network.
  Gateway& add(const std::string& machine, std::string_view kind) {
    Gateway& g = rig_->add(machine, kind);
    auto& machining = net_.add_contractor(machine, g.operations());
    cnp::MemoryConveyorEndpoint* conveying =
        g.config().kind == GatewayKind::conveyor ? &net_.add_conveyor(machine) : nullptr;
    auto roles = GatewayRoles::create(GatewayAccess::direct(g), machining, conveying, rig_->clock());
    EXPECT_TRUE(roles) << roles.error().describe();
    roles_.push_back(std::move(*roles));
    machining.bind(roles_.back()->contractor());
    if (conveying != nullptr) {
      conveying->bind(*roles_.back()->conveyor());
    }
    return g;
  }

  // Negotiates `operation` and runs until its conversation ends.
  Negotiated negotiate(const std::string& operation, std::vector<cnp::Param> params,
                       const std::string& directed = {}) {
    auto outcome = std::make_shared<std::optional<Negotiated>>();
    auto end = [outcome](const cnp::Conversation& c, bool ok) {
      Negotiated n{ok, c.contractor, c.failure, {}};
      for (const auto& r : c.results) {
        n.results[r.name] = r.value;
      }
      *outcome = n;
    };
    auto id = manager_.negotiate({"box-1", operation, std::move(params), directed},
                                 {{},
                                  [end](const cnp::Conversation& c) { end(c, true); },
                                  [end](const cnp::Conversation& c) { end(c, false); }});
    EXPECT_TRUE(id) << id.error().describe();
    EXPECT_TRUE(rig_->run_until([&] { return outcome->has_value(); }, 120s)) << operation << " did not end";
    return outcome->value_or(Negotiated{false, {}, "did not end", {}});
  }

  // The route the conveyors' INFORMs give from `from` to `to`.
  Result<cnp::Route> route(const std::string& from, const std::string& to) {
    auto route = std::make_shared<std::optional<Result<cnp::Route>>>();
    auto id = planner_.plan("box-1", from, to, [route](const Result<cnp::Route>& r) { *route = r; });
    EXPECT_TRUE(id) << id.error().describe();
    EXPECT_TRUE(rig_->run_until([&] { return route->has_value(); }, 10s));
    return route->value_or(make_error(Errc::timeout, "no route composed"));
  }

  // Carries `box` along `route`: each conveyor's consecutive hops as one transport, awarded to it.
  Negotiated carry(std::uint16_t box, const cnp::Route& route) {
    Negotiated last{true, {}, {}, {}};
    for (std::size_t i = 0; i < route.segments.size() && last.ok;) {
      const auto& first = route.segments[i];
      std::size_t j = i;
      while (j + 1 < route.segments.size() && route.segments[j + 1].conveyor == first.conveyor) {
        ++j;
      }
      last = negotiate(std::string(kTransport),
                       {{"box", static_cast<double>(box)},
                        {"from", static_cast<double>(rig_->place(first.from))},
                        {"to", static_cast<double>(rig_->place(route.segments[j].to))}},
                       first.conveyor);
      i = j + 1;
    }
    return last;
  }

  [[nodiscard]] const ProductInbox& heard() const { return inbox_; }
  [[nodiscard]] const cnp::Manager& manager() const { return manager_; }

 private:
  static cnp::ManagerConfig manager_config() {
    cnp::ManagerConfig c;
    c.max_rounds = 2;
    c.incarnation = 0xb0;
    return c;
  }

  GatewayRig* rig_;
  cnp::MemoryNetwork net_;
  cnp::MemoryManagerEndpoint& product_;
  cnp::Manager manager_;
  cnp::RoutePlanner planner_;
  ProductInbox inbox_;
  std::vector<std::unique_ptr<GatewayRoles>> roles_;
};

}  // namespace sf::factory::testing
