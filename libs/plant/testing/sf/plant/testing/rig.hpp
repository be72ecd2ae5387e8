// Test rigs: the plant on a ManualClock, its Modbus faces through
// MemoryClients (the PLC servers' own request path) and a smart robot
// through our EtherCAT master on the segment's in-memory link. Every step is
// one millisecond: the master's cycle (when an arm is attached), then the
// plant. The sequences themselves are the control side's script
// (sf/line/testing/line_script.hpp), which sees only the hardware faces.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "sf/ethercat/master/master.hpp"
#include "sf/line/testing/line_script.hpp"
#include "sf/modbus/memory_client.hpp"
#include "sf/plant/plant.hpp"

namespace sf::plant::testing {

using namespace std::chrono_literals;
using line::testing::LineIo;
using line::testing::SmartArm;

class Rig final : public LineIo {
 public:
  explicit Rig(std::uint64_t seed = 1, Layout layout = *default_layout())
      : plant_(std::make_unique<Plant>(std::move(layout), clock_, PlantOptions{seed})) {
    for (const auto& plc : plant_->plcs()) {
      modbus::MemoryClientOptions options;
      options.clock = &clock_;
      clients_[plc->name()] = std::make_unique<modbus::MemoryClient>(*plc, options);
    }
  }

  [[nodiscard]] const Layout& layout() const override { return plant_->layout(); }
  modbus::Client& plc(const std::string& name) override { return *clients_.at(name); }
  void step() override {
    clock_.advance(1ms);
    run_cycle();
    plant_->advance_to(clock_.now());
  }

  ManualClock& clock() { return clock_; }
  Plant& plant() { return *plant_; }
  World& world() { return plant_->world(); }

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
  void run_for(std::chrono::milliseconds d) { line::testing::run_for(*this, d); }

  bool di(const std::string& name, std::uint16_t address) {
    auto v = line::testing::di(*this, name, address);
    EXPECT_TRUE(v) << v.error().describe();
    return v && *v;
  }
  std::uint16_t ir(const std::string& name, std::uint16_t address) {
    auto v = line::testing::ir(*this, name, address);
    EXPECT_TRUE(v) << v.error().describe();
    return v ? *v : 0;
  }
  void coil(const std::string& name, std::uint16_t address, bool on) {
    auto s = line::testing::coil(*this, name, address, on);
    EXPECT_TRUE(s) << s.error().describe();
  }
  void hr(const std::string& name, std::uint16_t address, std::uint16_t value) {
    auto s = line::testing::hr(*this, name, address, value);
    EXPECT_TRUE(s) << s.error().describe();
  }
  // A rising and a falling edge on a coil, one step apart (fault_reset).
  void pulse(const std::string& name, std::uint16_t address) {
    coil(name, address, true);
    step();
    coil(name, address, false);
    step();
  }
  FaultCode run_job(const std::string& name, std::chrono::milliseconds limit = 30s) {
    auto code = line::testing::run_job(*this, name, limit);
    EXPECT_TRUE(code) << code.error().describe();
    return code ? *code : FaultCode::bad_job;
  }
  void convey(const std::vector<std::string>& belts, std::size_t to_station) {
    auto s = line::testing::convey(*this, belts, to_station);
    EXPECT_TRUE(s) << s.error().describe();
  }

 private:
  ManualClock clock_;
  std::unique_ptr<Plant> plant_;
  std::map<std::string, std::unique_ptr<modbus::MemoryClient>> clients_;
};

// A smart robot's segment on its in-memory link, our master on it, the arm
// started (OP, drives enabled).
class RigArm {
 public:
  RigArm(Rig& rig, const std::string& robot)
      : link_(rig.plant().smart_robot(robot)->segment()),
        master_(link_, rig.clock(), options()),
        arm_(rig, master_, robot) {
    auto started = arm_.start();
    EXPECT_TRUE(started) << started.error().describe();
  }
  SmartArm& operator*() { return arm_; }
  SmartArm* operator->() { return &arm_; }

 private:
  static ethercat::master::MasterOptions options() {
    ethercat::master::MasterOptions o;
    o.dc_static_drift_frames = 200;
    return o;
  }
  ethercat::slave::SegmentLink link_;
  ethercat::master::Master master_;
  SmartArm arm_;
};

}  // namespace sf::plant::testing
