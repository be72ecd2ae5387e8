#include "sf/simulation/simulation.hpp"

#include <algorithm>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/slave/segment.hpp"
#include "sf/factory/contract_net.hpp"
#include "sf/factory/gateway.hpp"
#include "sf/factory/gateway_agent.hpp"
#include "sf/factory/smart_robot.hpp"
#include "sf/modbus/memory_client.hpp"
#include "sf/negotiation/manager.hpp"
#include "sf/negotiation/memory_transport.hpp"
#include "sf/negotiation/route.hpp"
#include "sf/plant/plant.hpp"
#include "sf/simulation/central_dispatcher.hpp"
#include "timed_decisions.hpp"

namespace sf::simulation {

namespace cnp = sf::negotiation;
using namespace std::chrono_literals;

namespace {

ethercat::master::MasterOptions short_drift_phase() {
  ethercat::master::MasterOptions o;
  o.dc_static_drift_frames = 200;  // an in-memory segment has no drift to measure
  return o;
}

// The smart robot's IPC: the master of its segment, the controller, its contractor.
struct SmartRobotNode {
  SmartRobotNode(ethercat::slave::Segment& segment, ManualClock& clock, factory::SmartRobotConfig config,
                 const line::Layout& layout)
      : link(segment),
        master(link, clock, short_drift_phase()),
        robot(std::move(config), layout, master, clock) {}
  ethercat::slave::SegmentLink link;
  ethercat::master::Master master;
  factory::SmartRobot robot;
  std::optional<factory::ControllerBackend> backend;
  std::optional<cnp::Contractor> contractor;
};

// A legacy machine's gateway on its PLC's in-memory Modbus face.
struct GatewayNode {
  std::unique_ptr<modbus::MemoryClient> client;
  std::unique_ptr<factory::Gateway> gateway;
  std::unique_ptr<factory::GatewayRoles> roles;
};

factory::GatewayConfig gateway_config(const std::string& machine, factory::GatewayKind kind) {
  factory::GatewayConfig c;
  c.controller.machine = machine;
  c.controller.auto_start = true;
  c.kind = kind;
  return c;
}

std::string stamp(std::chrono::nanoseconds at) {
  return fmt::format("{:.3f}", std::chrono::duration<double>(at).count());
}

}  // namespace

struct Simulation::Parts {
  Parts(line::Layout l, const SimulationOptions& o)
      : options(o),
        layout(std::move(l)),
        plant(layout, clock, plant::PlantOptions{o.seed}),
        net(clock, network_options(o.seed)),
        products(net.add_manager()),
        manager(products, clock, manager_config()),
        planner(products, clock, cnp::RouteConfig{300ms, 500ms, 5, 0x5101}),
        contract_net(manager, planner),
        dispatcher(clock),
        timed(central() ? static_cast<factory::ProductDecisions&>(dispatcher) : contract_net, clock),
        host({&layout, &timed, &clock}, o.host,
             [this](const factory::OrderEvent& e) { events.push_back(e); }),
        start(clock.now()) {
    products.bind(static_cast<cnp::ManagerInbox&>(manager));
    products.bind(static_cast<cnp::RouteInbox&>(planner));
  }

  [[nodiscard]] bool central() const { return options.decisions == Decisions::central_dispatcher; }
  // Errc::not_found unless `machine` has a controller here.
  [[nodiscard]] Status known(const std::string& machine) const;

  static cnp::MemoryNetworkOptions network_options(std::uint64_t seed) {
    cnp::MemoryNetworkOptions o;
    o.seed = seed;
    return o;
  }
  static cnp::ManagerConfig manager_config() {
    cnp::ManagerConfig c = factory::product_manager_config();
    c.incarnation = 0x5100;  // fixed: conversation ids repeat from run to run
    return c;
  }

  Status add_smart_robot(const line::RobotSpec& spec) {
    factory::SmartRobotConfig config;
    config.robot = spec.name;
    config.auto_start = true;
    robots.push_back(
        std::make_unique<SmartRobotNode>(plant.smart_robot(spec.name)->segment(), clock, config, layout));
    SmartRobotNode& n = *robots.back();
    if (auto started = n.robot.start(); !started) {
      return make_error(started.error().code, fmt::format("{}: {}", spec.name, started.error().message));
    }
    machines.push_back(&n.robot);
    if (central()) {
      dispatcher.add(n.robot);
      return {};
    }
    n.backend.emplace(n.robot);
    auto& endpoint = net.add_contractor(spec.name, n.robot.operations());
    cnp::ContractorConfig config_cnp{spec.name, n.backend->skills()};
    config_cnp.backend = &*n.backend;
    auto contractor = cnp::Contractor::create(endpoint, clock, std::move(config_cnp));
    if (!contractor) {
      return contractor.error();
    }
    n.contractor.emplace(std::move(*contractor));
    n.backend->bind(*n.contractor);
    endpoint.bind(*n.contractor);
    return {};
  }

  Status add_gateway(const std::string& machine, factory::GatewayKind kind) {
    GatewayNode n;
    modbus::MemoryClientOptions client_options;
    client_options.clock = &clock;
    n.client = std::make_unique<modbus::MemoryClient>(*plant.plc(machine), client_options);
    n.gateway = std::make_unique<factory::Gateway>(gateway_config(machine, kind), layout, *n.client, clock);
    machines.push_back(n.gateway.get());
    if (central()) {
      std::function<factory::ConveyorOffer()> offer;
      if (kind == factory::GatewayKind::conveyor) {
        offer = [g = n.gateway.get()] { return g->conveyor_offer(); };
      }
      dispatcher.add(*n.gateway, std::move(offer));
      gateways.push_back(std::move(n));
      return {};
    }
    auto& machining = net.add_contractor(machine, n.gateway->operations());
    cnp::MemoryConveyorEndpoint* conveying =
        kind == factory::GatewayKind::conveyor ? &net.add_conveyor(machine) : nullptr;
    auto roles = factory::GatewayRoles::create(factory::GatewayAccess::direct(*n.gateway), machining,
                                               conveying, clock);
    if (!roles) {
      return roles.error();
    }
    n.roles = std::move(*roles);
    machining.bind(n.roles->contractor());
    if (conveying != nullptr) {
      conveying->bind(*n.roles->conveyor());
    }
    gateways.push_back(std::move(n));
    return {};
  }

  Status build() {
    for (const auto& belt : layout.belts) {
      SF_TRY(add_gateway(belt.name, factory::GatewayKind::conveyor));
    }
    SF_TRY(add_gateway(layout.uploader.name, factory::GatewayKind::uploader));
    SF_TRY(add_gateway(layout.downloader.name, factory::GatewayKind::downloader));
    for (const auto& robot : layout.robots) {
      if (robot.kind == line::RobotKind::smart_scara) {
        SF_TRY(add_smart_robot(robot));
      } else {
        SF_TRY(add_gateway(robot.name, factory::GatewayKind::legacy_robot));
      }
    }
    return can_make_every_candy();
  }

  // A layout whose operations no machine can do is refused before anything runs.
  Status can_make_every_candy() const {
    for (const auto& candy : layout.catalog.candy_types) {
      const bool someone =
          std::any_of(layout.robots.begin(), layout.robots.end(), [&](const line::RobotSpec& r) {
            return std::any_of(r.dispensers.begin(), r.dispensers.end(), [&](const std::string& d) {
              const line::DispenserSpec* spec = layout.dispenser(d);
              return spec != nullptr && spec->candy == candy.name;
            });
          });
      if (!someone) {
        return make_error(Errc::invalid_argument,
                          fmt::format("no robot of layout '{}' can load {}: it has no dispenser of it",
                                      layout.line, candy.name));
      }
    }
    return {};
  }

  // The shift's routine: an operator tops a dispenser up once it is down to a quarter, before
  // it runs empty (an empty one would stop its robot bidding for that candy until a Reset).
  void refill() {
    for (std::size_t d = 0; d < layout.dispensers.size(); ++d) {
      const int capacity = layout.dispensers[d].capacity;
      if (plant.world().stock(d) < capacity / 4) {
        auto lock = plant.lock();
        plant.world().set_stock(d, capacity);
      }
    }
  }

  void step() {
    clock.advance(1ms);
    const auto now = clock.now();
    if (now.time_since_epoch() % 1s == 0ns) {
      refill();
    }
    for (auto& r : robots) {
      if (!dead.contains(r->robot.identification().name)) {
        (void)r->robot.poll(now);
      }
    }
    plant.advance_to(now);
    for (auto& g : gateways) {
      if (!dead.contains(g.gateway->config().controller.machine)) {
        (void)g.gateway->poll(now);
      }
    }
    net.deliver();
    manager.tick();
    planner.tick();
    dispatcher.tick();
    for (auto& r : robots) {
      if (r->contractor && !dead.contains(r->robot.identification().name)) {
        r->contractor->tick();
      }
    }
    for (auto& g : gateways) {
      if (g.roles && !dead.contains(g.gateway->config().controller.machine)) {
        g.roles->contractor().tick();
      }
    }
    host.tick();
    measure();
  }

  // Utilisation and time on the line, one step's worth.
  void measure() {
    working.resize(machines.size());
    for (std::size_t i = 0; i < machines.size(); ++i) {
      if (machines[i]->working()) {
        working[i] += 1ms;
      }
    }
    on_line += static_cast<std::int64_t>(host.active()) * 1ms;
  }

  SimulationOptions options;
  ManualClock clock;
  line::Layout layout;
  plant::Plant plant;
  cnp::MemoryNetwork net;
  cnp::MemoryManagerEndpoint& products;
  cnp::Manager manager;
  cnp::RoutePlanner planner;
  factory::ContractNetDecisions contract_net;
  CentralDispatcher dispatcher;
  TimedDecisions timed;
  std::vector<factory::OrderEvent> events;
  factory::OrderHost host;
  Clock::time_point start;
  std::set<std::string> dead;  // controllers whose process was killed
  std::vector<std::unique_ptr<SmartRobotNode>> robots;
  std::vector<GatewayNode> gateways;
  std::vector<factory::MachineController*> machines;  // in the order they were built
  std::vector<std::chrono::nanoseconds> working;
  std::chrono::nanoseconds on_line{0};
};

Result<std::unique_ptr<Simulation>> Simulation::create(line::Layout layout, SimulationOptions options) {
  auto parts = std::make_unique<Parts>(std::move(layout), options);
  if (auto built = parts->build(); !built) {
    return built.error();
  }
  return std::unique_ptr<Simulation>(new Simulation(std::move(parts)));
}

Simulation::Simulation(std::unique_ptr<Parts> parts) : parts_(std::move(parts)) {}
Simulation::~Simulation() = default;

Status Simulation::submit(factory::Order order) {
  return parts_->host.submit(std::move(order));
}

void Simulation::step() {
  parts_->step();
}

bool Simulation::run_until(const std::function<bool()>& done, std::chrono::nanoseconds limit) {
  const auto end = parts_->clock.now() + limit;
  while (!done()) {
    if (parts_->clock.now() >= end) {
      return false;
    }
    step();
  }
  return true;
}

Clock::time_point Simulation::now() const {
  return parts_->clock.now();
}
const factory::OrderHost& Simulation::host() const {
  return parts_->host;
}
const plant::Plant& Simulation::plant() const {
  return parts_->plant;
}
const std::vector<factory::OrderEvent>& Simulation::order_events() const {
  return parts_->events;
}
Status Simulation::Parts::known(const std::string& machine) const {
  const bool found = std::any_of(robots.begin(), robots.end(),
                                 [&](const auto& r) { return r->robot.identification().name == machine; }) ||
                     std::any_of(gateways.begin(), gateways.end(), [&](const GatewayNode& g) {
                       return g.gateway->config().controller.machine == machine;
                     });
  return found ? Status{} : make_error(Errc::not_found, fmt::format("no controller '{}'", machine));
}

Status Simulation::kill(const std::string& machine) {
  SF_TRY(parts_->known(machine));
  parts_->dead.insert(machine);
  parts_->net.kill(machine);
  return {};
}

Status Simulation::cut_off(const std::string& machine) {
  SF_TRY(parts_->known(machine));
  parts_->net.cut_off(machine);
  return {};
}

Status Simulation::reconnect(const std::string& machine) {
  SF_TRY(parts_->known(machine));
  parts_->net.reconnect(machine);
  return {};
}

Status Simulation::inject(std::string_view fault) {
  auto spec = plant::parse_fault(fault);
  if (!spec) {
    return spec.error();
  }
  return parts_->plant.inject(*spec);
}

Status Simulation::clear(std::string_view fault) {
  auto spec = plant::parse_fault(fault);
  if (!spec) {
    return spec.error();
  }
  return parts_->plant.clear(*spec);
}

std::uint64_t Simulation::messages() const {
  return parts_->net.stats().sent;
}

std::vector<MachineLoad> Simulation::loads() const {
  std::vector<MachineLoad> out;
  for (std::size_t i = 0; i < parts_->machines.size(); ++i) {
    out.push_back({parts_->machines[i]->identification().name,
                   i < parts_->working.size() ? parts_->working[i] : std::chrono::nanoseconds{0}});
  }
  return out;
}
std::chrono::nanoseconds Simulation::deciding() const {
  return parts_->timed.waited();
}
std::chrono::nanoseconds Simulation::on_line() const {
  return parts_->on_line;
}

std::vector<LogLine> Simulation::log() const {
  std::vector<LogLine> out;
  for (const auto& e : parts_->events) {
    const auto at = e.at - parts_->start;
    out.push_back({at, fmt::format("{} {} {} {} {}", stamp(at), e.order, e.what, e.machine, e.detail)});
  }
  for (const auto& e : parts_->plant.world().events().entries()) {
    out.push_back({e.at, plant::format(e)});
  }
  std::stable_sort(out.begin(), out.end(), [](const LogLine& a, const LogLine& b) { return a.at < b.at; });
  return out;
}

}  // namespace sf::simulation
