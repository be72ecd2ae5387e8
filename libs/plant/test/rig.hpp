// Test rigs: the plant on a ManualClock, its Modbus faces through
// MemoryClients (the PLC servers' own request path) and a smart robot
// through our EtherCAT master on the segment's in-memory link. Every step is
// one millisecond: the master's cycle (when an arm is attached), then the
// plant.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "sf/ethercat/master/cia402.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/modbus/memory_client.hpp"
#include "sf/motion/scara.hpp"
#include "sf/plant/plant.hpp"

namespace sf::plant::testing {

using namespace std::chrono_literals;

class Rig {
 public:
  explicit Rig(std::uint64_t seed = 1, Layout layout = *default_layout())
      : plant_(std::make_unique<Plant>(std::move(layout), clock_, PlantOptions{seed})) {
    for (const auto& plc : plant_->plcs()) {
      modbus::MemoryClientOptions options;
      options.clock = &clock_;
      clients_[plc->name()] = std::make_unique<modbus::MemoryClient>(*plc, options);
    }
  }

  ManualClock& clock() { return clock_; }
  Plant& plant() { return *plant_; }
  World& world() { return plant_->world(); }
  modbus::Client& plc(const std::string& name) { return *clients_.at(name); }
  void on_cycle(std::function<void()> f) { cycle_ = std::move(f); }

  void step() {
    clock_.advance(1ms);
    if (cycle_) {
      cycle_();
    }
    plant_->advance_to(clock_.now());
  }
  template <typename F>
  bool run_until(F done, std::chrono::milliseconds limit) {
    for (auto t = 0ms; t < limit; t += 1ms) {
      if (done()) {
        return true;
      }
      step();
    }
    return done();
  }
  void run_for(std::chrono::milliseconds d) {
    for (auto t = 0ms; t < d; t += 1ms) {
      step();
    }
  }

  bool di(const std::string& name, std::uint16_t address) {
    auto v = plc(name).read_discrete_inputs(address, 1);
    EXPECT_TRUE(v) << name << ": " << v.error().describe();
    return v && (*v)[0];
  }
  std::uint16_t ir(const std::string& name, std::uint16_t address) {
    auto v = plc(name).read_input_registers(address, 1);
    EXPECT_TRUE(v) << name << ": " << v.error().describe();
    return v ? (*v)[0] : 0;
  }
  void coil(const std::string& name, std::uint16_t address, bool on) {
    auto s = plc(name).write_single_coil(address, on);
    EXPECT_TRUE(s) << name << ": " << s.error().describe();
  }
  void hr(const std::string& name, std::uint16_t address, std::uint16_t value) {
    auto s = plc(name).write_single_register(address, value);
    EXPECT_TRUE(s) << name << ": " << s.error().describe();
  }

  // A rising and a falling edge on a coil, one step apart (fault_reset).
  void pulse(const std::string& name, std::uint16_t address) {
    coil(name, address, true);
    step();
    coil(name, address, false);
    step();
  }

  // The handshake of registers.hpp: start, wait for done or fault, clear start.
  FaultCode run_job(const std::string& name, std::chrono::milliseconds limit = 30s) {
    coil(name, transfer_plc::kStart, true);
    const bool ended =
        run_until([&] { return di(name, transfer_plc::kDone) || di(name, transfer_plc::kFault); }, limit);
    EXPECT_TRUE(ended) << name << ": job did not end";
    const auto code = static_cast<FaultCode>(
        ir(name, name == world().layout().uploader.name || name == world().layout().downloader.name
                     ? transfer_plc::kFaultCode
                     : robot_controller::kFaultCode));
    coil(name, transfer_plc::kStart, false);
    step();
    return code;
  }

  // Belt by belt: the conveyor PLCs carry the box standing at `from` (a
  // station of `belts.front()`) to station `to_station` of belts.back(),
  // raising that stopper and setting each diverter on the way.
  void convey(const std::vector<std::string>& belts, std::size_t to_station) {
    const Layout& layout = world().layout();
    for (std::size_t i = 0; i + 1 < belts.size(); ++i) {
      const auto& next = layout.belt(belts[i])->next;
      const bool divert = next.size() > 1 && next[1] == belts[i + 1];
      coil(belts[i], conveyor_plc::kDivert, divert);
    }
    for (const auto& b : belts) {
      for (std::size_t k = 0; k < layout.belt(b)->stations.size(); ++k) {
        coil(b, static_cast<std::uint16_t>(conveyor_plc::kStopper + k), b == belts.back() && k == to_station);
      }
      coil(b, conveyor_plc::kMotorRun, true);
    }
    const auto eye = static_cast<std::uint16_t>(conveyor_plc::kStationBox + to_station);
    EXPECT_TRUE(run_until([&] { return ir(belts.back(), eye) != 0; }, 60s))
        << "box did not reach " << belts.back();
    run_for(10ms);
    for (const auto& b : belts) {
      coil(b, conveyor_plc::kMotorRun, false);
    }
  }

 private:
  ManualClock clock_;
  std::unique_ptr<Plant> plant_;
  std::map<std::string, std::unique_ptr<modbus::MemoryClient>> clients_;
  std::function<void()> cycle_;
};

// A smart robot driven the way its controller will drive it: our EtherCAT
// master in OP, four CiA 402 axes in CSP following joint trajectories, the
// gripper on DO 0.
class SmartArm {
 public:
  SmartArm(Rig& rig, const std::string& robot)
      : rig_(rig),
        cell_(*rig.plant().smart_robot(robot)),
        spec_(*rig.world().layout().robot(robot)),
        link_(cell_.segment()),
        master_(link_, rig.clock(), options()) {
    auto up = master_.bring_up(ethercat::AlState::Op);
    EXPECT_TRUE(up) << up.error().describe();
    for (unsigned a = 0; a < kArmAxes; ++a) {
      auto axis = ethercat::master::Cia402Axis::attach(master_, 0, a);
      EXPECT_TRUE(axis) << axis.error().describe();
      axes_.push_back(std::move(*axis));
    }
    auto out = master_.slave(0).entry(0x7000, 0);
    auto in = master_.slave(0).entry(0x6000, 0);
    EXPECT_TRUE(out && in);
    do_ = *out;
    di_ = *in;
    rig_.on_cycle([this] { cycle(); });
    rig_.step();
    for (auto& axis : axes_) {
      axis.set_target_position(axis.actual_position());
      axis.enable();
    }
    EXPECT_TRUE(rig_.run_until([&] { return enabled(); }, 500ms));
  }
  ~SmartArm() { rig_.on_cycle(nullptr); }

  bool enabled() const {
    return std::all_of(axes_.begin(), axes_.end(), [](const auto& a) { return a.enabled(); });
  }
  ethercat::master::Master& master() { return master_; }
  ethercat::master::Cia402Axis& axis(unsigned a) { return axes_.at(a); }
  std::uint32_t inputs() { return master_.slave(0).get<std::uint32_t>(di_); }
  void gripper(bool on) {
    outputs_ = on ? (outputs_ | kDoGripper) : (outputs_ & ~kDoGripper);
    rig_.run_for(20ms);
  }

  // A straight line in joint space to the tool pose, at most `step` counts
  // per cycle on the longest axis; waits until the drives have settled.
  void move_to(const motion::Vec3& point, std::int32_t step = 150) {
    std::array<double, kArmAxes> now{};
    for (unsigned a = 0; a < kArmAxes; ++a) {
      now[a] = axes_[a].target_position();
    }
    auto q = motion::scara_inverse_nearest(spec_.scara, {point, 0.0}, joints_from_counts(now));
    ASSERT_TRUE(q) << q.error().describe();
    const auto target = counts_from_joints(*q);
    std::int64_t longest = 1;
    for (unsigned a = 0; a < kArmAxes; ++a) {
      longest = std::max<std::int64_t>(longest, std::abs(target[a] - static_cast<std::int64_t>(now[a])));
    }
    const std::int64_t cycles = std::max<std::int64_t>(1, (longest + step - 1) / step);
    for (unsigned a = 0; a < kArmAxes; ++a) {
      std::vector<std::int32_t> points;
      for (std::int64_t i = 1; i <= cycles; ++i) {
        const double t = static_cast<double>(i) / static_cast<double>(cycles);
        points.push_back(static_cast<std::int32_t>(now[a] + (target[a] - now[a]) * t));
      }
      axes_[a].follow(points);
    }
    rig_.run_until([&] { return axes_[0].trajectory_done(); }, std::chrono::milliseconds(cycles + 10));
    rig_.run_until(
        [&] {
          for (unsigned a = 0; a < kArmAxes; ++a) {
            if (std::abs(axes_[a].actual_position() - target[a]) > 2) {
              return false;
            }
          }
          return true;
        },
        1s);
  }

 private:
  static ethercat::master::MasterOptions options() {
    ethercat::master::MasterOptions o;
    o.dc_static_drift_frames = 200;
    return o;
  }
  void cycle() {
    master_.slave(0).set<std::uint32_t>(do_, outputs_);
    master_.exchange();
    for (auto& axis : axes_) {
      axis.update();
    }
  }

  Rig& rig_;
  SmartRobotCell& cell_;
  const RobotSpec& spec_;
  ethercat::slave::SegmentLink link_;
  ethercat::master::Master master_;
  std::vector<ethercat::master::Cia402Axis> axes_;
  ethercat::master::EntryRef do_;
  ethercat::master::EntryRef di_;
  std::uint32_t outputs_ = 0;
};

}  // namespace sf::plant::testing
