// Gateway: the MachineController of a legacy machine (the paper's Raspberry
// Pi next to a closed PLC, §VII.B): a conveyor, the box uploader or
// downloader, or a legacy robot's controller, driven through its documented
// Modbus registers (registers.hpp) and nothing else.
//
// Poll loop (poll(now), every poll period): one read per register table into
// a mirror, then the PackML unit's work and the job in work, writing coils
// and registers as the job needs. The mirror is the machine's Tags,
// "plc.<entry>" ("robot.<entry>" for a robot controller), repeated entries
// named after their station or candy type ("plc.station_box.scara1") or
// numbered ("robot.joint3").
//
// Link: a failed read or write (no answer, connection lost, a Modbus
// exception) marks every tag Uncertain ("stale") with the reason, and Bad
// once the last good read is stale_after old; the gateway then makes no
// estimates (it stops bidding). A unit in Execute is held (stop reason
// kStopPlcUnreachable or kStopPlcException) and unheld by itself when the
// device answers again; a job in work continues where the device got to.
//
// PackML (OPC 30050): Stopped → Reset → Idle → Start → Execute by operator
// command, or by itself at start-up when the configuration says
// `start: execute`. Jobs run only in Execute. Resetting resets the device's
// latched fault (and, for a legacy robot, forgets empty dispensers). A fault
// of the machine (a jam, an axis, a lost part) aborts the unit with the
// PLC's fault code as the stop reason; a fault of one job (no box, an empty
// dispenser, a bad job) fails that job only. Admin counters: every job that
// came into work is produced, the failed ones defective.
#pragma once

#include <atomic>
#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/factory/conveying.hpp"
#include "sf/factory/gateway_config.hpp"
#include "sf/factory/job_queue.hpp"
#include "sf/factory/machine.hpp"
#include "sf/factory/packml.hpp"
#include "sf/modbus/client.hpp"
#include "sf/modbus/tcp_client.hpp"

namespace sf::factory {

namespace gateway {
class DeviceLogic;
class PlcIo;
struct JobResult;
}  // namespace gateway

// Stop reasons (PackML Admin.StopReason.ID) of a gateway besides the PLC's own
// fault codes (line::FaultCode, 1..9) and an operator's command (kStopOperator).
inline constexpr std::int32_t kStopPlcUnreachable = 101;  // no answer, connection lost
inline constexpr std::int32_t kStopPlcException = 102;    // the device answers with Modbus exceptions

// What a conveyor offers the ConveyingDomain now (Gateway::conveyor_offer): its segments, the
// work queued on the belt before a new transport could start, or why it takes no work.
struct ConveyorOffer {
  std::optional<std::string> unavailable;
  std::chrono::nanoseconds backlog{0};
  std::vector<TransportSegment> segments;
};

class Gateway final : public MachineController, private UnitWork {
 public:
  // `client` reaches the machine's device and must outlive the gateway; the
  // configuration must have been checked against `layout` (load_gateway_config).
  Gateway(GatewayConfig config, line::Layout layout, modbus::Client& client, const Clock& clock);
  ~Gateway() override;
  Gateway(const Gateway&) = delete;
  Gateway& operator=(const Gateway&) = delete;

  [[nodiscard]] const Identification& identification() const override { return identification_; }
  [[nodiscard]] std::vector<std::string> operations() const override;
  [[nodiscard]] std::optional<Estimate> estimate(const Operation& op,
                                                 std::string* why_not = nullptr) const override;
  Status submit(const std::string& job, const Operation& op) override;
  Status cancel(const std::string& job) override;
  Status command(PackMLCommand command) override;
  Clock::time_point poll(Clock::time_point now) override;
  [[nodiscard]] ControllerStatus status() const override;
  [[nodiscard]] bool working() const override { return jobs_.current() != nullptr; }

  [[nodiscard]] const GatewayConfig& config() const { return config_; }
  [[nodiscard]] const line::Layout& layout() const { return layout_; }
  // A conveyor's hops for the ConveyingDomain (conveying.hpp); none for other kinds.
  [[nodiscard]] std::vector<TransportSegment> segments() const;
  // What it offers transport REQUESTs now (unavailable(), backlog(), segments()).
  [[nodiscard]] ConveyorOffer conveyor_offer() const;
  // The device answered the last poll.
  [[nodiscard]] bool link_up() const { return link_ == Link::up; }
  // "up", "stale" (no answer, values still fresh), "lost", or "unknown" before the first poll.
  // Safe from any thread (a process's status line reads it while another thread polls).
  [[nodiscard]] std::string_view link_state() const;
  // Why the gateway takes no work now (its device unreachable, not in Execute), if it does not.
  [[nodiscard]] std::optional<std::string> unavailable() const;
  // The estimated work still ahead of a job submitted now (the job in work and the queue).
  [[nodiscard]] std::chrono::nanoseconds backlog() const;

 private:
  enum class Link : std::uint8_t { unknown, up, stale, lost };

  void read_device();
  void link_failed(const modbus::ClientError& error);
  void link_changed(Link before);
  void auto_start();
  void run_unit(std::chrono::nanoseconds dt);
  // UnitWork: the gateway's part in each PackML state (dt_: this poll's time step).
  void execute() override;  // the job handshake in work, the next job
  void wait() override;     // the device's step in progress followed
  bool wind_down() override;
  void stopped() override;
  void abort() override;  // the device halted, every job dropped
  bool reset() override;  // the device's latched fault reset
  bool clear() override;
  void run_offline();
  void work(bool go, std::chrono::nanoseconds dt);
  void end_current(gateway::JobResult result);
  void drop_all(const std::string& why);
  [[nodiscard]] std::string aborted() const;
  void flush_outcomes();
  [[nodiscard]] std::optional<std::string> refusal(const Operation& op) const;

  GatewayConfig config_;
  line::Layout layout_;
  const Clock* clock_;
  Identification identification_;
  std::unique_ptr<gateway::DeviceLogic> logic_;
  std::unique_ptr<gateway::PlcIo> io_;
  PackMLUnit unit_;
  std::atomic<Link> link_ = Link::unknown;
  std::string link_error_ = "not read yet";
  bool link_exception_ = false;
  Clock::time_point last_good_{};
  std::optional<Clock::time_point> last_poll_;
  std::chrono::nanoseconds dt_{0};
  Clock::time_point next_poll_ = Clock::time_point::min();
  bool held_by_link_ = false;
  bool auto_start_pending_ = false;
  JobQueue jobs_;  // outcomes delivered at the end of poll()
};

// The TCP client options of a checked configuration (the machine's port from the layout when
// the configuration gives none). Errc::invalid_argument when there is no port at all.
Result<modbus::TcpClientOptions> tcp_options(const GatewaySetup& setup);

}  // namespace sf::factory
