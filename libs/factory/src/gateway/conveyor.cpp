// A conveyor's gateway (a Siemens PLC per belt, registers.hpp conveyor_plc):
// "transport" carries a box along its own belt (conveying.hpp), across polls:
// the diverter set towards the next belt, the stoppers of the stations on the
// way lowered and the target's raised, the motor on; done when the target
// station's tag reader reads the box, or, onto the next belt, when the exit
// photo-eye has seen the box and then lost it. Between transports every
// stopper stays raised, so boxes wait where they were brought. A transport
// begins only when its way is clear (ready()): its box at its start, no other
// box at a station on the way or at the target, the exit free; a later
// transport whose way is clear goes first (it may be the one that clears it).
#include <algorithm>

#include <fmt/format.h>

#include "device_logic.hpp"
#include "sf/factory/conveying.hpp"

namespace sf::factory::gateway {

namespace {

namespace cp = line::conveyor_plc;
using line::FaultCode;

std::uint16_t stopper(std::size_t k) {
  return static_cast<std::uint16_t>(cp::kStopper + k);
}
std::uint16_t station_box(std::size_t k) {
  return static_cast<std::uint16_t>(cp::kStationBox + k);
}

class ConveyorLogic final : public DeviceLogic {
 public:
  explicit ConveyorLogic(const LogicContext& c)
      : config_(c.config),
        layout_(c.layout),
        belt_(*c.layout.belt_index(c.config.controller.machine)),
        spec_(c.layout.belts[belt_]),
        places_(places(c.layout)) {}

  [[nodiscard]] std::vector<std::string> operations() const override { return {std::string(kTransport)}; }

  [[nodiscard]] std::vector<TagSpec> tags() const override {
    std::vector<std::string> stations;
    for (const auto& s : spec_.stations) {
      stations.push_back(s.name);
    }
    return tag_specs(cp::map(),
                     {{"stopper[k]", stations}, {"station_eye[k]", stations}, {"station_box[k]", stations}});
  }

  [[nodiscard]] Result<std::chrono::nanoseconds> duration(const Operation& op) const override {
    auto route = resolve(op);
    if (!route) {
      return route.error();
    }
    return travel_time(route->metres, spec_.speed_mps) + config_.modbus.poll_period;
  }

  // A transport begins once its way is clear; until then the belt serves the others.
  [[nodiscard]] bool ready(const Operation& op, const PlcIo& io) const override {
    auto route = resolve(op);
    return route && !blocked(*route, io, true);
  }

  void begin(const Operation& op) override {
    route_ = *resolve(op);  // duration() accepted it
    checked_ = false;
    left_from_ = !route_.from.station.has_value();
    exit_seen_ = false;
  }

  std::optional<JobResult> step(PlcIo& io, bool go) override {
    if (!go) {
      io.ensure_coil(cp::kMotorRun, false);
      return std::nullopt;
    }
    if (!checked_) {
      if (auto refused = blocked(route_, io, false)) {  // ready() saw it clear: the safety net
        return JobResult{false, *refused, {}, std::nullopt};
      }
      checked_ = true;
    }
    track(io);
    if (arrived(io)) {
      io.ensure_coil(cp::kMotorRun, false);
      return JobResult{true,
                       fmt::format("box {} from {} to {}", route_.box, route_.from.name, route_.to.name),
                       {{"box", route_.box}},
                       std::nullopt};
    }
    set_outputs(io);
    return std::nullopt;
  }

  [[nodiscard]] bool settled() const override { return true; }

  [[nodiscard]] JobResult interrupted(const std::string& why) const override {
    return {false,
            fmt::format("{}: box {} from {} to {} {}", spec_.name, route_.box, route_.from.name,
                        route_.to.name, why),
            {},
            std::nullopt};
  }

  void halt(PlcIo& io) override { io.ensure_coil(cp::kMotorRun, false); }

  bool reset(PlcIo& io) override {
    io.ensure_coil(cp::kMotorRun, false);
    io.ensure_coil(cp::kReverse, false);
    for (std::size_t k = 0; k < spec_.stations.size(); ++k) {
      io.ensure_coil(stopper(k), true);
    }
    if (io.input(cp::kFault)) {
      io.write_coil(cp::kFaultReset, !io.coil(cp::kFaultReset));  // a rising edge every other poll
      return false;
    }
    io.ensure_coil(cp::kFaultReset, false);
    return true;
  }

  [[nodiscard]] std::optional<StopReason> standing_fault(const PlcIo& io) const override {
    if (!io.input(cp::kFault)) {
      return std::nullopt;
    }
    return plc_stop_reason(spec_.name, static_cast<FaultCode>(io.input_register(cp::kFaultCode)));
  }

  [[nodiscard]] std::string fault_text(const PlcIo& io) const override {
    return latched_fault(io, cp::kFault, cp::kFaultCode);
  }

 private:
  struct Route {
    Place from;
    Place to;
    double metres = 0.0;
    std::uint16_t box = 0;
  };

  [[nodiscard]] Result<Route> resolve(const Operation& op) const {
    auto box = int_param(op, "box", 1, 0xFFFF);
    auto from = int_param(op, "from", 0, static_cast<std::int64_t>(places_.size()) - 1);
    auto to = int_param(op, "to", 0, static_cast<std::int64_t>(places_.size()) - 1);
    for (const auto* p : {&box, &from, &to}) {
      if (!*p) {
        return p->error();
      }
    }
    Route r{places_[static_cast<std::size_t>(*from)], places_[static_cast<std::size_t>(*to)], 0.0,
            static_cast<std::uint16_t>(*box)};
    auto metres = belt_travel(layout_, belt_, r.from, r.to);
    if (!metres) {
      return make_error(Errc::unsupported, fmt::format("{} does not carry boxes from {} to {}", spec_.name,
                                                       r.from.name, r.to.name));
    }
    r.metres = *metres;
    return r;
  }

  // Stations the box passes between its start and its target.
  [[nodiscard]] bool on_the_way(const Route& r, std::size_t k) const {
    const double at = spec_.stations[k].at_m;
    return at > r.from.at_m && (r.to.belt != belt_ || at < r.to.at_m);
  }
  [[nodiscard]] bool on_the_way(std::size_t k) const { return on_the_way(route_, k); }

  // Why the transport's way is not clear, if it is not: the box is not at its start (a
  // station's tag reader, `steady` over two polls or as read now), another box stands at
  // a station on the way or at the target, or a box waits at the exit. The box itself
  // at a station on the way is no obstacle: waiting at the entry, it drifts up to the
  // first station when the belt runs for another box ("conveyor2" is anywhere from the
  // entry up to and including the first station).
  [[nodiscard]] std::optional<std::string> blocked(const Route& r, const PlcIo& io, bool steady) const {
    if (r.from.station) {
      const auto reader = station_box(*r.from.station);
      const std::uint16_t there = steady ? io.steady_input_register(reader) : io.input_register(reader);
      if (there != r.box) {
        return there == 0 ? fmt::format("box {} is not at {}: no box is", r.box, r.from.name)
                          : fmt::format("box {} is not at {}: box {} is", r.box, r.from.name, there);
      }
    }
    for (std::size_t k = 0; k < spec_.stations.size(); ++k) {
      const std::uint16_t other = io.input_register(station_box(k));
      const bool target = r.to.belt == belt_ && r.to.station == k;
      if ((on_the_way(r, k) || target) && other != 0 && other != r.box) {
        return fmt::format("box {} stands in the way at {}/{}", other, spec_.name, spec_.stations[k].name);
      }
    }
    if (r.to.belt != belt_ && io.input(cp::kExitEye)) {
      return fmt::format("a box waits at the exit of {}", spec_.name);
    }
    return std::nullopt;
  }

  void track(const PlcIo& io) {
    if (!left_from_ && io.input_register(station_box(*route_.from.station)) != route_.box) {
      left_from_ = true;
    }
    if (left_from_ && io.input(cp::kExitEye)) {
      exit_seen_ = true;
    }
  }

  [[nodiscard]] bool arrived(const PlcIo& io) const {
    if (route_.to.belt == belt_) {
      return io.input_register(station_box(*route_.to.station)) == route_.box;
    }
    return exit_seen_ && !io.input(cp::kExitEye);
  }

  void set_outputs(PlcIo& io) const {
    if (route_.to.belt != belt_) {
      const bool second = spec_.next.size() > 1 && spec_.next[1] == layout_.belts[route_.to.belt].name;
      io.ensure_coil(cp::kDivert, second);
    }
    for (std::size_t k = 0; k < spec_.stations.size(); ++k) {
      const bool leaving = route_.from.station == k && !left_from_;
      io.ensure_coil(stopper(k), !leaving && !on_the_way(k));
    }
    io.ensure_coil(cp::kReverse, false);
    io.ensure_coil(cp::kMotorRun, true);
  }

  const GatewayConfig& config_;
  const line::Layout& layout_;
  std::size_t belt_;
  const line::BeltSpec& spec_;
  std::vector<Place> places_;
  Route route_;
  bool checked_ = false;
  bool left_from_ = false;
  bool exit_seen_ = false;
};

}  // namespace

std::unique_ptr<DeviceLogic> make_conveyor(const LogicContext& context) {
  return std::make_unique<ConveyorLogic>(context);
}

}  // namespace sf::factory::gateway
