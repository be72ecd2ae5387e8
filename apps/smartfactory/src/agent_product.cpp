// `smartfactory agent product`: a product (manager) that negotiates each of its operations with
// the machines and a conveyor route to the winner (paper §IV.B).
#include "agent_common.hpp"

#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "sf/core/clock.hpp"

namespace sf::app::agents {
namespace {

using namespace std::chrono_literals;

struct ProductCliOptions {
  DdsCliOptions dds;
  std::string name;
  std::string ops;
  unsigned count = 1;
  unsigned parallel = 0;
  std::string start = "Input";
  bool no_route = false;
  std::string policy = "earliest-finish";
  std::vector<std::string> direct;
  std::vector<std::string> params;
  unsigned bid_ms = 500;
  unsigned confirm_ms = 500;
  unsigned max_rounds = 10;
  unsigned discovery_ms = 5000;
  double timeout_s = 0;
};

json route_json(const cnp::Route& r) {
  json segments = json::array();
  for (const auto& s : r.segments) {
    segments.push_back({{"conveyor", s.conveyor}, {"from", s.from}, {"to", s.to}});
  }
  return segments;
}

cnp::ProductEvents product_events(bool as_json) {
  cnp::ProductEvents ev;
  ev.on_award = [as_json](const std::string& p, const cnp::Conversation& c) {
    const auto us = std::chrono::duration<double, std::micro>(c.confirmed_at - c.started_at).count();
    as_json ? emit(json{{"event", "award"},
                        {"product", p},
                        {"operation", c.operation},
                        {"conversation", c.id},
                        {"contractor", c.contractor},
                        {"award", c.last_award},
                        {"round", c.round},
                        {"renegotiations", c.renegotiations},
                        {"latency_us", us}})
            : say(fmt::format("{}: {} awarded to {} (round {}, award {}, {:.3f} ms)", p, c.operation,
                              c.contractor, c.round, c.last_award, us / 1000.0));
  };
  ev.on_route = [as_json](const std::string& p, const cnp::Route& r) {
    as_json ? emit(json{{"event", "route"},
                        {"product", p},
                        {"from", r.from},
                        {"to", r.to},
                        {"segments", route_json(r)},
                        {"eta_ms", std::chrono::duration<double, std::milli>(r.eta()).count()}})
            : say(fmt::format("{}: route {}", p, r.describe()));
  };
  ev.on_step_done = [as_json](const std::string& p, const cnp::Step& s) {
    if (!as_json) {
      return;
    }
    json results = json::object();
    for (const auto& r : s.results) {
      results[r.name] = r.value;
    }
    emit(json{{"event", "done"},
              {"product", p},
              {"operation", s.operation},
              {"conversation", s.conversation},
              {"contractor", s.contractor},
              {"result", s.result},
              {"results", results}});
  };
  ev.on_finished = [as_json](const std::string& p, bool ok, const std::string& why) {
    as_json ? emit(json{{"event", "finished"}, {"product", p}, {"ok", ok}, {"error", why}})
            : say(ok ? fmt::format("{}: finished", p) : fmt::format("{}: FAILED: {}", p, why));
  };
  return ev;
}

// "OP.NAME=VALUE": a parameter OP is announced with.
Result<std::pair<std::string, cnp::Param>> parse_param(const std::string& text) {
  const auto dot = text.find('.');
  const auto eq = text.find('=');
  if (dot == std::string::npos || eq == std::string::npos || dot == 0 || eq < dot + 2 ||
      eq + 1 == text.size()) {
    return Error{Errc::invalid_argument, fmt::format("--param '{}': expected OP.NAME=VALUE", text)};
  }
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text.substr(eq + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() - eq - 1) {
    return Error{Errc::invalid_argument, fmt::format("--param '{}': the value is not a number", text)};
  }
  return std::pair{text.substr(0, dot), cnp::Param{text.substr(dot + 1, eq - dot - 1), value}};
}

Result<cnp::ProductAgentConfig> product_config(const ProductCliOptions& o) {
  auto ops = cnp::parse_operations(o.ops);
  if (!ops) {
    return ops.error();
  }
  auto policy = cnp::policy_by_name(o.policy);
  if (!policy) {
    return policy.error();
  }
  cnp::ProductAgentConfig c;
  c.name = o.name;
  c.operations = std::move(*ops);
  c.count = o.count;
  c.parallel = o.parallel;
  c.start = o.start;
  c.route = !o.no_route;
  c.policy = std::move(*policy);
  c.manager.bid_window = std::chrono::milliseconds{o.bid_ms};
  c.manager.confirm_window = std::chrono::milliseconds{o.confirm_ms};
  c.manager.confirm_grace = std::chrono::milliseconds{o.confirm_ms / 2};
  c.manager.max_rounds = o.max_rounds;
  c.discovery_timeout = std::chrono::milliseconds{o.discovery_ms};
  for (const auto& text : o.params) {
    auto param = parse_param(text);
    if (!param) {
      return param.error();
    }
    c.params[param->first].push_back(param->second);
  }
  for (const auto& d : o.direct) {
    const auto eq = d.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == d.size()) {
      return Error{Errc::invalid_argument, fmt::format("--direct '{}': expected OP=MACHINE", d)};
    }
    c.directed[d.substr(0, eq)] = d.substr(eq + 1);
  }
  return c;
}

int run_product(const ProductCliOptions& o) {
  exit_with_parent(o.dds);
  auto cfg = product_config(o);
  if (!cfg) {
    std::cerr << "agent product: " << cfg.error().message << "\n";
    return kExitUsage;
  }
  dds::Executor ex;
  ex.set_spin(std::chrono::microseconds{o.dds.spin_us});
  auto& clock = SteadyClock::instance();
  auto agent = cnp::ProductAgent::create(dds_settings(o.dds), *cfg, product_events(o.dds.json), ex, clock);
  if (!agent) {
    std::cerr << "agent product: " << agent.error().describe() << "\n";
    return agent.error().code == Errc::invalid_argument ? kExitUsage : kExitFailure;
  }
  if (o.dds.layout) {
    std::vector<const dds::Participant*> parts{&(*agent)->endpoints().machining()};
    if (const auto* c = (*agent)->endpoints().conveying()) {
      parts.push_back(c);
    }
    print_layout(parts, o.dds.json);
  }
  install_stop_signals();
  const auto deadline = o.timeout_s > 0 ? clock.now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                            std::chrono::duration<double>(o.timeout_s))
                                        : Clock::time_point::max();
  cnp::run_agents(
      ex, clock, {agent->get()}, [&] { return stop_requested() || clock.now() > deadline; },
      run_options(o.dds));
  const auto& a = **agent;
  if (o.dds.json) {
    emit(json{{"event", "summary"},
              {"succeeded", a.succeeded()},
              {"failed", a.failed()},
              {"unfinished", a.products().size() - a.succeeded() - a.failed()}});
  } else {
    say(fmt::format("{} of {} products finished, {} failed", a.succeeded(), a.products().size(), a.failed()));
  }
  return a.succeeded() == a.products().size() ? kExitOk : kExitFailure;
}

}  // namespace

void register_product(CLI::App& group, CommandResult& result) {
  auto o = std::make_shared<ProductCliOptions>();
  auto* cmd = group.add_subcommand(
      "product",
      "A product (manager): negotiates each operation with the machines and a conveyor route to the winner; "
      "prints each award and exits when done");
  cmd->add_option("--name", o->name, "Product name (with --count K: NAME-1..NAME-K)")->required();
  cmd->add_option("--ops", o->ops, "Operations it needs, in order, comma-separated (e.g. OP1,OP2)")
      ->required();
  cmd->add_option("--count", o->count, "How many products of this kind this process manages")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--parallel", o->parallel, "Products in progress at once (0 = all)")->capture_default_str();
  cmd->add_option("--start", o->start, "Where products enter the conveyor graph")->capture_default_str();
  cmd->add_flag("--no-route", o->no_route, "Negotiate operations only, no conveyor routes");
  cmd->add_option("--policy", o->policy, "Bid selection: earliest-finish, lowest-cost or load-balance")
      ->capture_default_str();
  cmd->add_option("--direct", o->direct,
                  "OP=MACHINE: award OP to MACHINE without a call for bids (DIRECTEDAWARD); repeatable");
  cmd->add_option("--param", o->params,
                  "OP.NAME=VALUE: announce OP with this parameter; repeatable. Results of earlier operations "
                  "named 'box' (an uploaded box's id) are carried into later ones")
      ->type_name("OP.NAME=VALUE");
  cmd->add_option("--bid-ms", o->bid_ms,
                  "Bid deadline after an ANNOUNCE (earlier once every machine answered)")
      ->capture_default_str();
  cmd->add_option("--confirm-ms", o->confirm_ms, "Time an awarded machine has to CONFIRM")
      ->capture_default_str();
  cmd->add_option("--max-rounds", o->max_rounds,
                  "Announcements per operation before giving up (0 = no limit)")
      ->capture_default_str();
  cmd->add_option("--discovery-ms", o->discovery_ms,
                  "Wait up to this long for machines (and conveyors) to be discovered before announcing")
      ->capture_default_str();
  cmd->add_option("--timeout", o->timeout_s, "Give up after this many seconds (0 = never)");
  add_dds_options(*cmd, o->dds);
  add_layout_option(*cmd, o->dds);
  cmd->footer(
      "Exit status 0 when every product got all its operations done. Example:\n"
      "  smartfactory agent product --name P1 --ops OP1,OP2 --count 3");
  cmd->callback([o, &result] { result.exit_code = run_product(*o); });
}

}  // namespace sf::app::agents
