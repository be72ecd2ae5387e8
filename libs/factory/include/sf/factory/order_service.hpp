// The order service (paper §VII): the process the products live in, apart
// from the machines. Its OrderHost's products negotiate over DDS with the
// line's controllers: the service is one product process of the paper's
// Fig. 4 (one participant per domain; per operation an ANNOUNCE and an AWARD
// writer and a BID reader; a REQUEST writer and an INFORM reader), which all
// its products share with one manager, as negotiation::ProductAgent does.
//
// Orders come in from any thread (the OPC UA server's SubmitOrder, a file at
// start-up) and are handed to the agents' loop; the host's counters and its
// latest event and inspection are published on the service's own OPC UA server
// (OrderModel), where the cloud reads them like any machine's model.
#pragma once

#include <array>
#include <atomic>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/dds/executor.hpp"
#include "sf/factory/controller_config.hpp"
#include "sf/factory/order_host.hpp"
#include "sf/negotiation/agents.hpp"
#include "sf/negotiation/dds_transport.hpp"

namespace sf::opcua::server {
class Server;
}

namespace sf::factory {

// What the service's OPC UA model and status line show, copied out of the loop.
struct OrderServiceStatus {
  std::array<std::size_t, kOrderStates> orders{};  // by OrderState (queued, in work, done, failed, cancelled)
  std::uint64_t remade = 0;
  std::array<double, 2> lead_s{};  // lead time (accepted → done) p50 and p99, of the done orders
  [[nodiscard]] std::size_t count(OrderState state) const {
    return orders.at(static_cast<std::size_t>(state));
  }
  std::string last_event;       // "12.345 alice-1 loaded scara-robot-1 ..."
  std::string last_inspection;  // "alice-1 box 7: 53.0 g, 2 gummy, 1 toffee"
};

class OrderServiceAgent final : public negotiation::Agent {
 public:
  // `layout` must outlive the agent. `on_event` runs on the agents' loop for every order event.
  static Result<std::unique_ptr<OrderServiceAgent>> create(const negotiation::DdsSettings& settings,
                                                           const line::Layout& layout,
                                                           OrderHostOptions options, dds::Executor& executor,
                                                           const Clock& clock, OrderEventSink on_event = {});
  ~OrderServiceAgent() override;
  OrderServiceAgent(const OrderServiceAgent&) = delete;
  OrderServiceAgent& operator=(const OrderServiceAgent&) = delete;

  void tick() override;
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const override;

  // Safe from any thread: checks the order against the catalog at once and
  // hands it to the loop; the error says why it was refused.
  Status submit(Order order);
  // Safe from any thread: asks the loop to withdraw an order not yet started. An unknown id is
  // Errc::not_found at once; otherwise the answer comes as the order's next event, "cancelled"
  // or "cancel-refused" (the order was started, made or failed meanwhile).
  Status cancel(const std::string& id);
  // Safe from any thread.
  [[nodiscard]] OrderServiceStatus status() const;
  // On the loop's thread only.
  [[nodiscard]] const OrderHost& host() const { return *host_; }
  [[nodiscard]] const negotiation::ProductEndpoints& endpoints() const { return *endpoints_; }

 private:
  OrderServiceAgent(const line::Layout& layout, const Clock& clock) : layout_(&layout), clock_(&clock) {}
  void publish();
  // Every event of the host: the published status, then the owner's sink.
  void note(const OrderEvent& e);

  const line::Layout* layout_;
  const Clock* clock_;
  std::unique_ptr<negotiation::ProductEndpoints> endpoints_;
  std::unique_ptr<negotiation::Manager> manager_;
  std::unique_ptr<negotiation::RoutePlanner> planner_;
  std::unique_ptr<ContractNetDecisions> decisions_;
  std::unique_ptr<OrderHost> host_;
  OrderEventSink on_event_;
  Clock::time_point started_at_{};

  mutable std::mutex mutex_;  // guards what other threads see and send
  std::deque<Order> inbox_;
  std::deque<std::string> cancels_;
  std::set<std::string> ids_;  // accepted so far, for duplicate ids refused at once
  OrderServiceStatus status_;
};

// The service's model on an OPC UA server (namespace urn:smartfactory:orders):
//   Objects/OrderService
//     Queued, InWork, Done, Failed, Remade (UInt32)   LeadTimeP50, LeadTimeP99 (Double, s)
//     LastEvent, LastInspection (String; LastInspection as sf/line/inspection.hpp writes it)
//     Queued, InWork, Done, Failed, Cancelled, Remade (UInt32)
//     SubmitOrder(Id: String, BoxType: String, Candy: String[] "type:quantity") → OrderId: String
//     CancelOrder(Id: String): withdraws an order not yet started (its next event says whether)
// SubmitOrder answers BadInvalidArgument for an order the catalog refuses or an id taken,
// CancelOrder BadNotFound for an id never accepted; both need the role operator (a viewer gets
// BadUserAccessDenied from the server's role check).
// Every order event is also an OPC UA event of the Server object (BaseEventType, OPC 10000-5
// §6.4.2): SourceName the order's id, Message "<what> <machine or -> <detail>" as
// sf/line/order_step.hpp writes it, so that a client subscribed to events misses none.
class OrderModel {
 public:
  static Result<std::unique_ptr<OrderModel>> attach(opcua::server::Server& server, OrderServiceAgent& agent);
  // Copies the agent's status into the variables (from any thread).
  void update();
  // Raises the event as an OPC UA event at `at` (from any thread).
  void raise(const OrderEvent& event, Clock::utc_time at);

 private:
  OrderModel() = default;
  opcua::server::Server* server_ = nullptr;
  OrderServiceAgent* agent_ = nullptr;
  std::uint16_t ns_ = 0;
  std::array<std::uint8_t, 8> event_prefix_{};
  std::atomic<std::uint64_t> events_{0};
};

// order-service.yaml (configs/order-service.yaml):
//   layout: ../layouts/prototype-line.yaml   # default: the built-in layout
//   wip: 3                                    # boxes on the line at once (0: the layout's safe bound)
//   max_attempts: 3                           # boxes made for one order at most
//   orders: orders.yaml                       # taken at start (optional)
//   opcua: {port: 4850, ...}                  # as a controller's (controller_config.hpp)
//   dds: {machining_domain: 10, conveying_domain: 11, interface: lo, partition: smartfactory}
struct OrderServiceConfig {
  ControllerSettings service;  // machine: "order-service"; layout, opcua, dds
  OrderHostOptions host;
  std::filesystem::path orders_file;
};

struct OrderServiceSetup {
  OrderServiceConfig config;
  line::Layout layout;
  std::vector<Order> orders;  // from orders_file, checked against the layout's catalog
};

Result<OrderServiceSetup> load_order_service_config(const std::filesystem::path& file);
Result<OrderServiceSetup> parse_order_service_config(std::string_view yaml,
                                                     std::string name = "<order-service>",
                                                     const std::filesystem::path& base = {});

// The `orders` process: the agent on DDS, its model on its own OPC UA server.
class OrderServiceProcess {
 public:
  static Result<std::unique_ptr<OrderServiceProcess>> create(OrderServiceSetup setup, Clock& clock);
  ~OrderServiceProcess();
  OrderServiceProcess(const OrderServiceProcess&) = delete;
  OrderServiceProcess& operator=(const OrderServiceProcess&) = delete;

  // Runs the agents' loop on the calling thread until stop() is true; on_event gets every order
  // event and on_report the status every `interval` and whenever an order finished, both on
  // that thread.
  void run(const std::function<bool()>& stop, const std::function<void(const OrderEvent&)>& on_event,
           const std::function<void(const OrderServiceStatus&)>& on_report,
           std::chrono::nanoseconds interval);

  [[nodiscard]] OrderServiceAgent& agent() { return *agent_; }
  [[nodiscard]] const OrderServiceSetup& setup() const { return setup_; }
  // opc.tcp://<its opcua host, or localhost>:<port>
  [[nodiscard]] std::string opcua_endpoint() const;
  [[nodiscard]] const std::string& opcua_security() const { return security_; }

 private:
  OrderServiceProcess(OrderServiceSetup setup, Clock& clock) : setup_(std::move(setup)), clock_(&clock) {}

  OrderServiceSetup setup_;
  Clock* clock_;
  std::function<void(const OrderEvent&)> on_event_;
  dds::Executor executor_;
  std::unique_ptr<OrderServiceAgent> agent_;
  std::unique_ptr<opcua::server::Server> server_;
  std::unique_ptr<OrderModel> model_;
  std::string security_;
};

}  // namespace sf::factory
