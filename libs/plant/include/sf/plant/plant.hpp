// Plant: the whole simulated line — the world and every hardware face of it:
// a Modbus device per legacy controller (a conveyor PLC per belt, the
// uploader and downloader PLCs, a controller per legacy robot) and an
// EtherCAT segment per smart robot. Everything above these faces (masters,
// gateways, agents, the cloud) is real control software and meets the plant
// only through EtherCAT frames and Modbus requests.
//
// Time: advance() moves the plant in fixed steps of kWorldStep; each step
// first runs every controller's program (scan), then the world's physics.
// On a ManualClock the plant is deterministic for a layout and seed.
//
// Threads: the plant is guarded by lock(). Modbus servers and EtherCAT
// segment runners may serve the faces from other threads: the devices and
// segments have their own locks, always taken after the plant's.
#pragma once

#include <chrono>
#include <memory>
#include <mutex>
#include <span>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/line/layout.hpp"
#include "sf/plant/faults.hpp"
#include "sf/plant/plc.hpp"
#include "sf/plant/smart_robot.hpp"
#include "sf/plant/snapshot.hpp"
#include "sf/plant/world.hpp"

namespace sf::plant {

struct PlantOptions {
  std::uint64_t seed = 1;
  std::uint32_t first_serial = 1001;  // EtherCAT serial numbers of the smart robots' slaves
};

class Plant {
 public:
  static constexpr std::size_t kMaxScheduledFaults = 1000;
  Plant(Layout layout, const Clock& clock, PlantOptions options = {});

  [[nodiscard]] std::unique_lock<std::mutex> lock() const { return std::unique_lock(mutex_); }
  [[nodiscard]] World& world() { return world_; }
  [[nodiscard]] const World& world() const { return world_; }
  [[nodiscard]] const Layout& layout() const { return world_.layout(); }

  void advance(std::chrono::nanoseconds dt);
  // Advances by the clock time since the last call (or since construction).
  void advance_to(Clock::time_point now);

  [[nodiscard]] std::span<const std::unique_ptr<PlcDevice>> plcs() const { return plcs_; }
  [[nodiscard]] PlcDevice* plc(std::string_view name) const;
  [[nodiscard]] std::span<const std::unique_ptr<SmartRobotCell>> smart_robots() const {
    return smart_robots_;
  }
  [[nodiscard]] SmartRobotCell* smart_robot(std::string_view name) const;

  // Now, or at fault.at (simulated time) when set; cleared after
  // fault.duration when set. Errors name an unknown target.
  Status inject(const FaultSpec& fault);
  Status clear(const FaultSpec& fault);
  [[nodiscard]] const std::vector<FaultSpec>& active_faults() const { return active_; }

  [[nodiscard]] Snapshot snapshot() const;

 private:
  void step();
  Status check(const FaultSpec& fault) const;
  Status apply(const FaultSpec& fault, bool on);
  void run_schedule();

  World world_;
  const Clock* clock_;
  Clock::time_point last_;
  std::chrono::nanoseconds pending_{0};
  std::vector<std::unique_ptr<PlcDevice>> plcs_;
  std::vector<std::unique_ptr<SmartRobotCell>> smart_robots_;
  std::vector<FaultSpec> active_;
  struct Scheduled {
    std::chrono::nanoseconds at;
    FaultSpec fault;
    bool inject;
  };
  std::vector<Scheduled> schedule_;
  mutable std::mutex mutex_;
};

}  // namespace sf::plant
