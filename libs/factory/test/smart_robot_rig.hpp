// The smart robot's controller against the plant: our EtherCAT master on the
// robot's in-memory segment, the plant on a ManualClock, one millisecond per
// step (the controller's cycle first, then the plant's physics). Boxes are put
// at the robot's station by the plant's hand; conveying is the gateways' work.
#pragma once

#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "sf/factory/smart_robot.hpp"
#include "sf/factory/smart_robot/arm.hpp"
#include "sf/plant/testing/rig.hpp"

namespace sf::factory::testing {

inline constexpr const char* kRobot = "scara-robot-1";

class SmartRobotRig {
 public:
  explicit SmartRobotRig(bool auto_start = false)
      : link_(rig.plant().smart_robot(kRobot)->segment()),
        master_(link_, rig.clock(), master_options()),
        robot(config(auto_start), rig.layout(), master_, rig.clock()) {}
  ~SmartRobotRig() { rig.on_cycle(nullptr); }
  SmartRobotRig(const SmartRobotRig&) = delete;
  SmartRobotRig& operator=(const SmartRobotRig&) = delete;

  // Starts the controller; `more` runs in each cycle after the controller's poll.
  void start(std::function<void()> more = nullptr) {
    auto started = robot.start();
    ASSERT_TRUE(started) << started.error().describe();
    rig.on_cycle([this, more = std::move(more)] {
      robot.poll(rig.clock().now());
      if (more) {
        more();
      }
    });
  }

  [[nodiscard]] int candy(std::string_view name) const {
    return static_cast<int>(*rig.layout().catalog.candy_index(name));
  }
  [[nodiscard]] std::size_t box_type(std::string_view name) const {
    return *rig.layout().catalog.box_index(name);
  }

  // A small box standing in place at the robot's first station.
  plant::BoxId place_box() {
    auto at = line::find_station(rig.layout(), rig.layout().robot(kRobot)->stations.front());
    auto id = rig.world().place_box(box_type("small-box"), *at, "test");
    EXPECT_TRUE(id) << id.error().describe();
    return id ? *id : 0;
  }

  void inject(std::string_view fault) {
    auto spec = plant::parse_fault(fault);
    ASSERT_TRUE(spec) << spec.error().describe();
    auto s = rig.plant().inject(*spec);
    ASSERT_TRUE(s) << s.error().describe();
  }
  void clear(std::string_view fault) {
    auto s = rig.plant().clear(*plant::parse_fault(fault));
    ASSERT_TRUE(s) << s.error().describe();
  }

  plant::testing::Rig rig;

 private:
  static ethercat::master::MasterOptions master_options() {
    ethercat::master::MasterOptions o;
    o.dc_static_drift_frames = 200;
    return o;
  }
  static SmartRobotConfig config(bool auto_start) {
    SmartRobotConfig c;
    c.robot = kRobot;
    c.auto_start = auto_start;
    return c;
  }

  ethercat::slave::SegmentLink link_;
  ethercat::master::Master master_;

 public:
  SmartRobot robot;
};

}  // namespace sf::factory::testing
