// Product: the paper's product agent (§IV.B, §VII) on top of the manager
// role. It works through its operations in order: negotiate the operation
// with the machines (CNP), then a conveyor route from where it is to the
// confirmed machine; the step ends when the machine reports INFORM-DONE and
// the route is known, and the product is then at that machine.
//
// (Physical transport and machining are simulated by the contractor's job
// timing; the factory module couples them to the real line.)
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/route.hpp"

namespace sf::negotiation {

struct ProductPlan {
  std::string name;
  std::vector<std::string> operations;
  std::string start = "Input";                         // where the product enters the conveyor graph
  bool route = true;                                   // negotiate conveyor routes between machines
  std::map<std::string, std::string> directed{};       // operation → contractor: DIRECTEDAWARD first
  std::map<std::string, std::vector<Param>> params{};  // operation → the parameters it is announced with
  // Results of a done step (INFORM-DONE) that later steps are announced with, unless their own
  // parameters set them: what the product learns about itself, e.g. the id of its uploaded box.
  std::vector<std::string> carry{"box"};
};

struct Step {
  std::string operation;
  std::string conversation;
  std::string contractor;
  std::uint32_t round = 0;
  std::uint32_t renegotiations = 0;
  std::chrono::nanoseconds negotiation_time{0};  // ANNOUNCE → confirmed AWARD
  std::optional<Route> route;
  std::string result;          // of the INFORM-DONE
  std::vector<Param> results;  // of the INFORM-DONE, typed
};

struct ProductEvents {
  std::function<void(const std::string& product, const Conversation& c)> on_award;  // confirmed award
  std::function<void(const std::string& product, const Route& route)> on_route;
  std::function<void(const std::string& product, const Step& step)> on_step_done;
  std::function<void(const std::string& product, bool ok, const std::string& why)> on_finished;
};

class Product {
 public:
  // `planner` may be null when plan.route is false. Keep the Product at a
  // fixed address while it runs (callbacks refer to it).
  Product(Manager& manager, RoutePlanner* planner, ProductPlan plan, ProductEvents events = {});
  Product(const Product&) = delete;
  Product& operator=(const Product&) = delete;

  Status start();
  [[nodiscard]] bool finished() const { return finished_; }
  [[nodiscard]] bool ok() const { return finished_ && failure_.empty(); }
  [[nodiscard]] const std::string& failure() const { return failure_; }
  [[nodiscard]] const std::vector<Step>& steps() const { return steps_; }
  [[nodiscard]] const std::string& location() const { return location_; }
  [[nodiscard]] const ProductPlan& plan() const { return plan_; }

 private:
  void begin_step();
  void on_confirmed(const Conversation& c);
  void on_route(std::uint64_t token, const Result<Route>& route);
  void on_done(const Conversation& c);
  void maybe_complete_step();
  void finish(std::string failure);
  [[nodiscard]] std::vector<Param> params_of(const std::string& operation) const;

  Manager* manager_;
  RoutePlanner* planner_;
  ProductPlan plan_;
  ProductEvents events_;
  std::size_t index_ = 0;
  std::string location_;
  Step current_;
  bool work_done_ = false;
  bool route_done_ = false;
  std::uint64_t route_token_ = 0;
  bool started_ = false;
  bool finished_ = false;
  std::string failure_;
  std::vector<Step> steps_;
  std::vector<Param> carried_;  // results named in plan_.carry, latest value each
};

}  // namespace sf::negotiation
