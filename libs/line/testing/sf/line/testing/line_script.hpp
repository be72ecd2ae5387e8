// A scripted line for tests: the sequences a line's controllers will run —
// job handshakes, belts carrying a box to a station, a smart robot's pick and
// place through our EtherCAT master — written against the line's hardware
// faces only (Modbus clients, an EtherCAT master), so the same script drives
// the plant in one process on a ManualClock (plant tests) and a plant in
// another network namespace in real time (tests/integration). It never links
// the plant: what it knows of the line comes from the layout, as a real
// controller's would.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sf/core/result.hpp"
#include "sf/ethercat/master/cia402.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/line/layout.hpp"
#include "sf/line/registers.hpp"
#include "sf/line/smart_robot.hpp"
#include "sf/modbus/client.hpp"
#include "sf/motion/scara.hpp"

namespace sf::line::testing {

using namespace std::chrono_literals;

// The line as a script sees it.
class LineIo {
 public:
  virtual ~LineIo() = default;
  [[nodiscard]] virtual const Layout& layout() const = 0;
  virtual modbus::Client& plc(const std::string& machine) = 0;
  // One millisecond of the line: a plant step, or a real master cycle. Runs
  // the cycle hook (a master's exchange) first.
  virtual void step() = 0;
  // Conditions on Modbus inputs are checked every this many steps (a
  // gateway's poll period).
  [[nodiscard]] virtual int poll_steps() const { return 1; }
  void on_cycle(std::function<void()> hook) { cycle_ = std::move(hook); }

 protected:
  void run_cycle() {
    if (cycle_) {
      cycle_();
    }
  }

 private:
  std::function<void()> cycle_;
};

inline Result<bool> di(LineIo& io, const std::string& machine, std::uint16_t address) {
  auto v = io.plc(machine).read_discrete_inputs(address, 1);
  if (!v) {
    return Error(v.error()).with_context(machine);
  }
  return static_cast<bool>((*v)[0]);
}

inline Result<std::uint16_t> ir(LineIo& io, const std::string& machine, std::uint16_t address) {
  auto v = io.plc(machine).read_input_registers(address, 1);
  if (!v) {
    return Error(v.error()).with_context(machine);
  }
  return (*v)[0];
}

inline Status coil(LineIo& io, const std::string& machine, std::uint16_t address, bool on) {
  auto s = io.plc(machine).write_single_coil(address, on);
  return s ? Status{} : Status(Error(s.error()).with_context(machine));
}

inline Status hr(LineIo& io, const std::string& machine, std::uint16_t address, std::uint16_t value) {
  auto s = io.plc(machine).write_single_register(address, value);
  return s ? Status{} : Status(Error(s.error()).with_context(machine));
}

inline void run_for(LineIo& io, std::chrono::milliseconds d) {
  for (auto t = 0ms; t < d; t += 1ms) {
    io.step();
  }
}

// Steps until `done` (checked every poll_steps()) is true; a timeout names `what`.
template <typename F>
Status run_until(LineIo& io, F done, std::chrono::milliseconds limit, std::string_view what) {
  for (auto t = 0ms; t <= limit; t += std::chrono::milliseconds(io.poll_steps())) {
    Result<bool> ok = done();
    if (!ok) {
      return ok.error();
    }
    if (*ok) {
      return {};
    }
    run_for(io, std::chrono::milliseconds(io.poll_steps()));
  }
  return make_error(Errc::timeout, fmt::format("{} did not happen within {} ms", what, limit.count()));
}

// The job handshake (registers.hpp): start, wait for done or fault, clear
// start; the fault code it ended with.
inline Result<FaultCode> run_job(LineIo& io, const std::string& machine,
                                 std::chrono::milliseconds limit = 30s) {
  const bool transfer = machine == io.layout().uploader.name || machine == io.layout().downloader.name;
  SF_TRY(coil(io, machine, transfer_plc::kStart, true));
  SF_TRY(run_until(
      io,
      [&]() -> Result<bool> {
        auto v = io.plc(machine).read_discrete_inputs(0, 4);
        if (!v) {
          return Error(v.error());
        }
        return (*v)[transfer_plc::kDone] || (*v)[transfer_plc::kFault];
      },
      limit, machine + "'s job"));
  auto code = ir(io, machine, transfer ? transfer_plc::kFaultCode : robot_controller::kFaultCode);
  if (!code) {
    return code.error();
  }
  SF_TRY(coil(io, machine, transfer_plc::kStart, false));
  io.step();
  return static_cast<FaultCode>(*code);
}

// Belt by belt: the box standing on belts.front() is carried to station
// `to_station` of belts.back(), with that stopper raised and each diverter
// set on the way; the motors stop once it is in place.
inline Status convey(LineIo& io, const std::vector<std::string>& belts, std::size_t to_station) {
  const Layout& layout = io.layout();
  for (std::size_t i = 0; i + 1 < belts.size(); ++i) {
    const auto& next = layout.belt(belts[i])->next;
    SF_TRY(coil(io, belts[i], conveyor_plc::kDivert, next.size() > 1 && next[1] == belts[i + 1]));
  }
  for (const auto& b : belts) {
    for (std::size_t k = 0; k < layout.belt(b)->stations.size(); ++k) {
      SF_TRY(coil(io, b, static_cast<std::uint16_t>(conveyor_plc::kStopper + k),
                  b == belts.back() && k == to_station));
    }
    SF_TRY(coil(io, b, conveyor_plc::kMotorRun, true));
  }
  const auto tag = static_cast<std::uint16_t>(conveyor_plc::kStationBox + to_station);
  SF_TRY(run_until(
      io,
      [&]() -> Result<bool> {
        auto id = ir(io, belts.back(), tag);
        return id ? Result<bool>(*id != 0) : Result<bool>(id.error());
      },
      60s, fmt::format("a box at station {} of {}", to_station, belts.back())));
  for (const auto& b : belts) {
    SF_TRY(coil(io, b, conveyor_plc::kMotorRun, false));
  }
  return {};
}

// A smart robot driven as its controller will drive it: our EtherCAT master
// in OP, the arm's four CiA 402 axes in CSP following straight joint-space
// lines, the vacuum gripper on DO 0 (smart_robot.hpp).
class SmartArm {
 public:
  SmartArm(LineIo& io, ethercat::master::Master& master, const std::string& robot)
      : io_(io), master_(master), spec_(*io.layout().robot(robot)) {}
  ~SmartArm() { io_.on_cycle(nullptr); }
  SmartArm(const SmartArm&) = delete;
  SmartArm& operator=(const SmartArm&) = delete;

  // The segment to OP, the axes enabled where they stand.
  Status start() {
    SF_TRY(master_.bring_up(ethercat::AlState::Op));
    for (unsigned a = 0; a < kArmAxes; ++a) {
      auto axis = ethercat::master::Cia402Axis::attach(master_, 0, a);
      if (!axis) {
        return axis.error();
      }
      axes_.push_back(std::move(*axis));
    }
    auto out = master_.slave(0).entry(0x7000, 0);
    auto in = master_.slave(0).entry(0x6000, 0);
    if (!out || !in) {
      return make_error(Errc::not_found, "the smart controller maps no digital IO");
    }
    do_ = *out;
    di_ = *in;
    io_.on_cycle([this] { cycle(); });
    io_.step();
    for (auto& axis : axes_) {
      axis.set_target_position(axis.actual_position());
      axis.enable();
    }
    return wait_for([&] { return enabled(); }, 2s, "the arm's drives to be enabled");
  }

  [[nodiscard]] bool enabled() const {
    return std::all_of(axes_.begin(), axes_.end(), [](const auto& a) { return a.enabled(); });
  }
  [[nodiscard]] std::uint32_t inputs() { return master_.slave(0).get<std::uint32_t>(di_); }
  ethercat::master::Cia402Axis& axis(unsigned a) { return axes_.at(a); }
  ethercat::master::Master& master() { return master_; }

  // Waits until the digital inputs in `mask` are all on (or all off).
  Status wait_inputs(std::uint32_t mask, bool on, std::chrono::milliseconds limit, std::string_view what) {
    return wait_for([&] { return on ? (inputs() & mask) == mask : (inputs() & mask) == 0; }, limit, what);
  }

  Status gripper(bool on) {
    outputs_ = on ? (outputs_ | kDoGripper) : (outputs_ & ~kDoGripper);
    run_for(io_, 20ms);
    return {};
  }

  // A straight line in joint space to the tool point, at most `step` counts
  // per cycle on the longest axis; returns once the drives have settled.
  Status move_to(const motion::Vec3& point, std::int32_t step = 150) {
    std::array<double, kArmAxes> now{};
    for (unsigned a = 0; a < kArmAxes; ++a) {
      now[a] = axes_[a].target_position();
    }
    auto q = motion::scara_inverse_nearest(spec_.scara, {point, 0.0}, joints_from_counts(now));
    if (!q) {
      return q.error();
    }
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
    run_for(io_, std::chrono::milliseconds(cycles));
    return wait_for(
        [&] {
          for (unsigned a = 0; a < kArmAxes; ++a) {
            if (std::abs(axes_[a].actual_position() - target[a]) > 2) {
              return false;
            }
          }
          return true;
        },
        2s, "the arm to settle");
  }

 private:
  template <typename F>
  Status wait_for(F done, std::chrono::milliseconds limit, std::string_view what) {
    for (auto t = 0ms; t < limit; t += 1ms) {
      if (done()) {
        return {};
      }
      io_.step();
    }
    return done() ? Status{} : make_error(Errc::timeout, fmt::format("waited in vain for {}", what));
  }
  void cycle() {
    master_.slave(0).set<std::uint32_t>(do_, outputs_);
    master_.exchange();
    for (auto& axis : axes_) {
      axis.update();
    }
  }

  LineIo& io_;
  ethercat::master::Master& master_;
  const RobotSpec& spec_;
  std::vector<ethercat::master::Cia402Axis> axes_;
  ethercat::master::EntryRef do_;
  ethercat::master::EntryRef di_;
  std::uint32_t outputs_ = 0;
};

inline std::uint16_t candy_number(const Layout& layout, std::string_view candy) {
  return static_cast<std::uint16_t>(*layout.catalog.candy_index(candy) + 1);
}

// The whole sequence on the default line: the uploader puts a small box on
// conveyor1; the belts carry it to SCARA Robot 1, which loads a gummy into
// slot 3; on to the DENSO arm, whose controller loads a lollipop into slot
// 7; on to the downloader, which takes it off and inspects it. Returns the
// box id; every step's failure is an error naming the step.
inline Result<std::uint16_t> pack_one_box(LineIo& io, SmartArm& arm) {
  const Layout& layout = io.layout();
  SF_TRY(hr(io, layout.uploader.name, transfer_plc::kBoxType, 1));
  auto uploaded = run_job(io, layout.uploader.name);
  if (!uploaded || *uploaded != FaultCode::none) {
    return uploaded ? make_error(Errc::remote, fmt::format("upload: {}", to_string(*uploaded)))
                    : uploaded.error();
  }
  auto id = ir(io, layout.uploader.name, transfer_plc::kBoxId);
  if (!id) {
    return id.error();
  }
  SF_TRY(convey(io, {"conveyor1", "conveyor2"}, 0));

  const std::string robot = "scara-robot-1";
  SF_TRY(arm.wait_inputs(1U << kDiBoxInPlace, true, 100ms, "SCARA Robot 1 to see the box in place"));
  const motion::Vec3 pick = layout.dispenser("scara1-gummy")->at;
  const StationRef station = *find_station(layout, layout.robot(robot)->stations.front());
  const motion::Vec3 slot = slot_point(layout, station, *layout.catalog.box("small-box"), 3);
  SF_TRY(arm.move_to(pick + motion::Vec3{0, 0, 0.05}));
  SF_TRY(arm.move_to(pick));
  SF_TRY(arm.gripper(true));
  SF_TRY(arm.wait_inputs(kDiPartPresent | kDiVacuumOk, true, 100ms,
                         "SCARA Robot 1 to hold a part after the pick"));
  SF_TRY(arm.move_to(pick + motion::Vec3{0, 0, 0.05}));
  SF_TRY(arm.move_to(slot + motion::Vec3{0, 0, 0.05}));
  SF_TRY(arm.move_to(slot + motion::Vec3{0, 0, 0.01}));
  SF_TRY(arm.gripper(false));
  SF_TRY(arm.wait_inputs(kDiPartPresent, false, 100ms, "SCARA Robot 1 to let go of the part"));
  SF_TRY(arm.move_to(slot + motion::Vec3{0, 0, 0.08}));

  SF_TRY(convey(io, {"conveyor2", "conveyor4"}, 0));
  SF_TRY(hr(io, "denso", robot_controller::kCandyType, candy_number(layout, "lollipop")));
  SF_TRY(hr(io, "denso", robot_controller::kSlot, 7));
  SF_TRY(hr(io, "denso", robot_controller::kStation, 0));
  auto loaded = run_job(io, "denso");
  if (!loaded || *loaded != FaultCode::none) {
    return loaded ? make_error(Errc::remote, fmt::format("DENSO job: {}", to_string(*loaded)))
                  : loaded.error();
  }
  SF_TRY(convey(io, {"conveyor4"}, 1));
  auto downloaded = run_job(io, layout.downloader.name);
  if (!downloaded || *downloaded != FaultCode::none) {
    return downloaded ? make_error(Errc::remote, fmt::format("download: {}", to_string(*downloaded)))
                      : downloaded.error();
  }
  return *id;
}

}  // namespace sf::line::testing
