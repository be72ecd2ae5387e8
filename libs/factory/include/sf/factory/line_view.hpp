// What the line's own servers say about it, read over OPC UA as any client of the line would:
// the order service's counters (OrderService.*) and each controller's time with a job in work
// (<Machine>.Job.WorkingTime). `smartfactory demo` shows its progress and summary from these.
// With hosts, a process's OPC UA address is only on the OPC UA network, so each client is made
// in the namespace of the process it reads.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/factory/line_supervisor.hpp"

namespace sf::opcua {
class SyncClient;
}

namespace sf::factory {

struct OrderCounts {
  std::uint32_t queued = 0, in_work = 0, done = 0, failed = 0, remade = 0;
  double lead_p50 = 0, lead_p99 = 0;  // seconds
  bool operator==(const OrderCounts&) const = default;
};

struct WorkingTime {
  std::string machine;
  double seconds = 0;
};

class LineView {
 public:
  // A view of the planned line; connects on the first read. Errc::not_found without an order
  // service in the plan.
  static Result<LineView> open(const LinePlan& plan);
  LineView(LineView&&) noexcept;
  LineView& operator=(LineView&&) noexcept;
  ~LineView();

  // The order service's counters now; an error while it does not answer (restarting).
  Result<OrderCounts> orders();
  // Seconds each controller had jobs in work (the installation's PKI, as the line's processes
  // use it); controllers that do not answer are left out.
  [[nodiscard]] std::vector<WorkingTime> working_times() const;

 private:
  LineView() = default;
  const LinePlan* plan_ = nullptr;
  std::unique_ptr<opcua::SyncClient> orders_;
  std::uint16_t ns_ = 0;
};

}  // namespace sf::factory
