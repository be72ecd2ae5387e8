// A legacy robot's gateway (TOSHIBA THL300, DENSO VS-6577G): "load" of
// `count` candies is one controller job (registers.hpp, robot_controller) per
// candy, into consecutive slots of the box at its station. The controller
// moves by itself; the estimate follows its taught program (RobotProgram)
// through the layout's geometry at the arm's tool speed.
//
// The gateway cannot see a dispenser's stock: it declines a candy type only
// when none of its dispensers holds that type, and after a job failed with
// dispenser_empty for it, until an operator's Reset (the refill).
#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "device_logic.hpp"
#include "handshake.hpp"

namespace sf::factory::gateway {

namespace {

namespace rc = line::robot_controller;
using line::FaultCode;
using motion::Vec3;

Vec3 above(Vec3 p, double dz) {
  return {p.x, p.y, p.z + dz};
}

class LegacyRobotLogic final : public DeviceLogic {
 public:
  explicit LegacyRobotLogic(const LogicContext& c)
      : config_(c.config),
        layout_(c.layout),
        robot_(*c.layout.robot(c.config.controller.machine)),
        program_(c.config.robot),
        handshake_(rc::kFaultCode) {
    const std::string& station = program_.station.empty() ? robot_.stations.front() : program_.station;
    station_index_ = static_cast<std::uint16_t>(
        std::find(robot_.stations.begin(), robot_.stations.end(), station) - robot_.stations.begin());
    station_ = *line::find_station(layout_, station);  // checked with the configuration
    const line::StationRef first = *line::find_station(layout_, robot_.stations.front());
    home_ = above(station_top(first, 0.0), program_.home_above_m);
  }

  [[nodiscard]] std::vector<std::string> operations() const override { return {std::string(kLoad)}; }
  [[nodiscard]] std::string tag_prefix() const override { return "robot"; }

  [[nodiscard]] std::vector<TagSpec> tags() const override {
    std::vector<std::string> stations;
    for (const auto& s : robot_.stations) {
      stations.push_back(s.substr(s.find('/') + 1));
    }
    const std::size_t joints = robot_.kind == line::RobotKind::legacy_articulated ? 6 : 4;
    auto specs = tag_specs(rc::map(),
                           {{"box_in_place[k]", stations},
                            {"station_box[k]", stations},
                            {"joint[j]", std::vector<std::string>(joints), true}},
                           {{"joint[j]", TagType::signed_word},
                            {"tool_x", TagType::signed_word},
                            {"tool_y", TagType::signed_word},
                            {"tool_z", TagType::signed_word},
                            {"temperature", TagType::tenths}});
    for (auto& spec : specs) {
      if (spec.name == "temperature") {
        spec.unit = "CEL";  // 0.1 °C in the register, °C once scaled
      }
    }
    return specs;
  }

  [[nodiscard]] Result<std::chrono::nanoseconds> duration(const Operation& op) const override {
    auto candy = int_param(op, "candy", 0, static_cast<std::int64_t>(layout_.catalog.candy_types.size()) - 1);
    if (!candy) {
      return candy.error();
    }
    const auto& name = layout_.catalog.candy_types[static_cast<std::size_t>(*candy)].name;
    const line::DispenserSpec* dispenser = dispenser_of(name);
    if (dispenser == nullptr) {
      return make_error(Errc::unsupported, fmt::format("{} has no dispenser of {}", robot_.name, name));
    }
    if (empty_.contains(static_cast<std::size_t>(*candy))) {
      return make_error(Errc::state, fmt::format("{}'s {} dispenser ran empty; an operator's Reset clears it",
                                                 robot_.name, name));
    }
    auto count = int_param(op, "count", 1, std::int64_t{line::kMaxRepeats} * line::kMaxRepeats);
    auto slot = int_param(op, "slot", 0, 0xFFFF);
    auto box = int_param(op, "box", 1, 0xFFFF);
    for (const auto* p : {&count, &slot, &box}) {
      if (!*p) {
        return p->error();
      }
    }
    auto type = box_type(op, *slot + *count);
    if (!type) {
      return type.error();
    }
    std::chrono::nanoseconds total{0};
    for (std::int64_t i = 0; i < *count; ++i) {
      total += cycle(dispenser->at, place_point(*type, static_cast<int>(*slot + i)));
    }
    return total;
  }

  // A load begins once its box stands at the robot's station (its tag reader reads it).
  [[nodiscard]] bool ready(const Operation& op, const PlcIo& io) const override {
    return box_read(op, io, static_cast<std::uint16_t>(rc::kStationBox + station_index_));
  }

  void begin(const Operation& op) override {
    candy_ = static_cast<std::size_t>(*op.param("candy"));
    count_ = static_cast<int>(op.param("count").value_or(1));
    slot_ = static_cast<int>(*op.param("slot"));
    box_ = static_cast<std::uint16_t>(*op.param("box"));
    placed_ = 0;
  }

  std::optional<JobResult> step(PlcIo& io, bool go) override {
    if (handshake_.running()) {
      auto code = handshake_.follow(io);
      if (!code) {
        return std::nullopt;
      }
      if (*code != FaultCode::none) {
        return failed(*code);
      }
      ++placed_;
    }
    if (placed_ == count_) {
      return done();
    }
    if (go) {  // the next candy at once, in the poll that saw the last one done
      const std::array<std::uint16_t, 3> job{static_cast<std::uint16_t>(candy_ + 1),
                                             static_cast<std::uint16_t>(slot_ + placed_), station_index_};
      handshake_.start(io, [&](PlcIo& plc) { plc.write_registers(rc::kCandyType, job); });
    }
    return std::nullopt;
  }

  [[nodiscard]] bool settled() const override { return !handshake_.running(); }

  [[nodiscard]] JobResult interrupted(const std::string& why) const override {
    return {false,
            fmt::format("{}: {} after {} of {} {}", robot_.name, why, placed_, count_, candy_name()),
            {{"placed", placed_}},
            std::nullopt};
  }

  void halt(PlcIo& io) override { handshake_.abandon(io); }

  bool reset(PlcIo& io) override {
    empty_.clear();  // the operator refilled the dispensers
    return handshake_.reset(io);
  }

  [[nodiscard]] std::string fault_text(const PlcIo& io) const override {
    return latched_fault(io, rc::kFault, rc::kFaultCode);
  }

 private:
  [[nodiscard]] std::string candy_name() const { return layout_.catalog.candy_types.at(candy_).name; }

  [[nodiscard]] JobResult done() const {
    return {
        true,
        fmt::format("{} {} in box {}, slots {}-{}", count_, candy_name(), box_, slot_, slot_ + count_ - 1),
        {{"placed", placed_}},
        std::nullopt};
  }

  JobResult failed(FaultCode code) {
    if (code == FaultCode::dispenser_empty) {
      empty_.insert(candy_);
    }
    JobResult r{false,
                fmt::format("{}: slot {}: {} after {} of {} {}", robot_.name, slot_ + placed_, describe(code),
                            placed_, count_, candy_name()),
                {{"placed", placed_}},
                std::nullopt};
    // The arm itself is in trouble: the machine stops (PackML Aborted) with the PLC's code.
    if (code == FaultCode::part_lost || code == FaultCode::axis_fault) {
      r.machine_fault = plc_stop_reason(robot_.name, code);
    }
    return r;
  }

  [[nodiscard]] const line::DispenserSpec* dispenser_of(const std::string& candy) const {
    for (const auto& name : robot_.dispensers) {
      const line::DispenserSpec* d = layout_.dispenser(name);
      if (d != nullptr && d->candy == candy) {
        return d;
      }
    }
    return nullptr;
  }

  // The box type of the operation ("box_type", optional) holding `slots` slots.
  Result<const line::BoxType*> box_type(const Operation& op, std::int64_t slots) const {
    if (!op.param("box_type")) {
      return static_cast<const line::BoxType*>(nullptr);
    }
    auto type = int_param(op, "box_type", 0, static_cast<std::int64_t>(layout_.catalog.box_types.size()) - 1);
    if (!type) {
      return type.error();
    }
    const line::BoxType& t = layout_.catalog.box_types[static_cast<std::size_t>(*type)];
    if (slots > t.capacity()) {
      return make_error(Errc::invalid_argument, fmt::format("a {} has {} slots", t.name, t.capacity()));
    }
    return &t;
  }

  // The middle of a station at `height` above the belt.
  [[nodiscard]] Vec3 station_top(const line::StationRef& at, double height) const {
    const line::BeltSpec& belt = layout_.belts[at.belt];
    const motion::Vec2 p = belt.point_at(belt.stations[at.station].at_m);
    return {p.x, p.y, belt.height_m + height};
  }

  // Where the candy is released: over its slot, or, the box type unknown, over the middle of
  // the station at the top of the tallest box type.
  [[nodiscard]] Vec3 place_point(const line::BoxType* type, int slot) const {
    if (type != nullptr) {
      return above(line::slot_point(layout_, station_, *type, slot), program_.release_above_m);
    }
    double tallest = 0.0;
    for (const auto& t : layout_.catalog.box_types) {
      tallest = std::max(tallest, t.size_m.z);
    }
    return above(station_top(station_, tallest), program_.release_above_m);
  }

  // One controller job (docs/plant.md): from home over the pick point, down, grip, up, over
  // the slot, down, release, up, home; and the two polls of its handshake.
  [[nodiscard]] std::chrono::nanoseconds cycle(const Vec3& pick, const Vec3& place) const {
    const double a = program_.approach_m;
    const Vec3 over_pick = above(pick, a);
    const Vec3 over_place = above(place, a);
    const double path = motion::norm(over_pick - home_) + 2 * a + motion::norm(over_place - over_pick) +
                        2 * a + motion::norm(home_ - over_place);
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::duration<double>(path / robot_.tool_speed_mps)) +
           2 * program_.grip + 2 * config_.modbus.poll_period;
  }

  const GatewayConfig& config_;
  const line::Layout& layout_;
  const line::RobotSpec& robot_;
  const RobotProgram& program_;
  Handshake handshake_;
  line::StationRef station_;
  std::uint16_t station_index_ = 0;
  Vec3 home_;
  std::set<std::size_t> empty_;  // candy types whose dispensers ran empty
  std::size_t candy_ = 0;
  int count_ = 0;
  int slot_ = 0;
  std::uint16_t box_ = 0;
  int placed_ = 0;
};

}  // namespace

std::unique_ptr<DeviceLogic> make_legacy_robot(const LogicContext& context) {
  return std::make_unique<LegacyRobotLogic>(context);
}

}  // namespace sf::factory::gateway
