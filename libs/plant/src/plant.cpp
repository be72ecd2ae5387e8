// Plant (plant.hpp): the world, its controllers' programs and the faults.
#include "sf/plant/plant.hpp"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

#include "sf/modbus/protocol.hpp"

namespace sf::plant {

namespace {
// The index of a dispenser known to be in the layout (check() saw it).
std::size_t dispenser_index(const Layout& layout, std::string_view name) {
  return static_cast<std::size_t>(layout.dispenser(name) - layout.dispensers.data());
}
}  // namespace

Plant::Plant(Layout layout, const Clock& clock, PlantOptions options)
    : world_(std::move(layout), options.seed), clock_(&clock), last_(clock.now()) {
  const Layout& l = world_.layout();
  for (std::size_t b = 0; b < l.belts.size(); ++b) {
    plcs_.push_back(std::make_unique<ConveyorPlc>(world_, b));
  }
  plcs_.push_back(std::make_unique<TransferPlc>(world_, TransferPlc::Role::upload));
  plcs_.push_back(std::make_unique<TransferPlc>(world_, TransferPlc::Role::download));
  std::uint32_t serial = options.first_serial;
  for (std::size_t r = 0; r < l.robots.size(); ++r) {
    if (l.robots[r].legacy()) {
      plcs_.push_back(std::make_unique<RobotControllerPlc>(world_, r));
    } else {
      smart_robots_.push_back(std::make_unique<SmartRobotCell>(world_, r, clock, serial++));
    }
  }
}

void Plant::advance(std::chrono::nanoseconds dt) {
  pending_ += dt;
  while (pending_ >= kWorldStep) {
    pending_ -= kWorldStep;
    step();
  }
}

void Plant::advance_to(Clock::time_point now) {
  if (now > last_) {
    advance(now - last_);
    last_ = now;
  }
}

void Plant::step() {
  const double dt = std::chrono::duration<double>(kWorldStep).count();
  for (auto& plc : plcs_) {
    plc->scan(world_, dt);
  }
  for (auto& robot : smart_robots_) {
    robot->scan(world_);
  }
  world_.advance(kWorldStep);
  run_schedule();
}

PlcDevice* Plant::plc(std::string_view name) const {
  auto it = std::find_if(plcs_.begin(), plcs_.end(), [&](const auto& p) { return p->name() == name; });
  return it == plcs_.end() ? nullptr : it->get();
}

SmartRobotCell* Plant::smart_robot(std::string_view name) const {
  auto it = std::find_if(smart_robots_.begin(), smart_robots_.end(),
                         [&](const auto& r) { return r->name() == name; });
  return it == smart_robots_.end() ? nullptr : it->get();
}

// --- faults ------------------------------------------------------------------

Status Plant::check(const FaultSpec& f) const {
  const Layout& l = layout();
  const auto unknown = [&](std::string_view what) {
    return make_error(Errc::not_found, fmt::format("fault {}: no {} '{}'", format(f), what, f.target));
  };
  switch (f.kind) {
    case FaultKind::jam:
      return l.belt(f.target) != nullptr ? Status{} : unknown("belt");
    case FaultKind::dispenser_empty:
      return l.dispenser(f.target) != nullptr ? Status{} : unknown("dispenser");
    case FaultKind::mixup:
      if (l.dispenser(f.target) == nullptr) {
        return unknown("dispenser");
      }
      if (l.catalog.candy_types.size() < 2) {
        return make_error(Errc::invalid_argument,
                          fmt::format("fault {}: the catalog has no other candy type to mix up", format(f)));
      }
      return {};
    case FaultKind::axis_fault:
    case FaultKind::cable_cut:
      return smart_robot(f.target) != nullptr ? Status{} : unknown("smart robot");
    case FaultKind::plc_unreachable:
    case FaultKind::plc_exception:
      return plc(f.target) != nullptr ? Status{} : unknown("machine with a PLC");
    case FaultKind::overheat: {
      const auto* robot = l.robot(f.target);
      return robot != nullptr && robot->legacy() ? Status{} : unknown("legacy robot");
    }
    case FaultKind::box_drop:
      return Status{};
  }
  return {};
}

Status Plant::inject(const FaultSpec& fault) {
  SF_TRY(check(fault));
  if ((fault.at || fault.duration) && schedule_.size() >= kMaxScheduledFaults) {
    return make_error(Errc::limit_exceeded,
                      fmt::format("{} timed faults are pending already", schedule_.size()));
  }
  if (fault.at && *fault.at > world_.time()) {
    schedule_.push_back({*fault.at, fault, true});
    return {};
  }
  SF_TRY(apply(fault, true));
  if (fault.duration) {
    schedule_.push_back({world_.time() + *fault.duration, fault, false});
  }
  return {};
}

Status Plant::clear(const FaultSpec& fault) {
  SF_TRY(check(fault));
  if (fault.kind == FaultKind::box_drop) {
    return make_error(Errc::unsupported, "a dropped box cannot be put back");
  }
  return apply(fault, false);
}

Status Plant::apply(const FaultSpec& f, bool on) {
  const Layout& l = layout();
  switch (f.kind) {
    case FaultKind::jam:
      world_.set_jam(*l.belt_index(f.target), on);
      break;
    case FaultKind::dispenser_empty: {
      const std::size_t d = dispenser_index(l, f.target);
      world_.set_stock(d, on ? 0 : l.dispensers[d].capacity);
      break;
    }
    case FaultKind::mixup:
      world_.set_mixup(dispenser_index(l, f.target), on);
      break;
    case FaultKind::axis_fault:
      if (on) {
        smart_robot(f.target)->axis_fault(f.argument, f.code);
      }
      world_.record(on ? EventKind::fault_raised : EventKind::fault_cleared, f.target, 0, -1, {}, format(f));
      break;
    case FaultKind::cable_cut:
      on ? smart_robot(f.target)->cut_cable() : smart_robot(f.target)->restore_cable();
      world_.record(on ? EventKind::fault_raised : EventKind::fault_cleared, f.target, 0, -1, {},
                    "cable cut");
      break;
    case FaultKind::plc_unreachable:
    case FaultKind::plc_exception: {
      const auto fault = f.kind == FaultKind::plc_unreachable
                             ? modbus::Fault::unreachable()
                             : modbus::Fault::answer(static_cast<modbus::ExceptionCode>(f.argument));
      plc(f.target)->set_fault(on ? fault : modbus::Fault{});
      world_.record(on ? EventKind::fault_raised : EventKind::fault_cleared, f.target, 0, -1, {}, format(f));
      break;
    }
    case FaultKind::overheat:
      world_.set_cooling_failed(static_cast<std::size_t>(l.robot(f.target) - l.robots.data()), on);
      break;
    case FaultKind::box_drop: {
      std::uint32_t id = 0;
      std::from_chars(f.target.data(), f.target.data() + f.target.size(), id);
      return world_.drop_box(id);
    }
  }
  const auto same = [&](const FaultSpec& a) {
    return a.kind == f.kind && a.target == f.target && a.argument == f.argument;
  };
  active_.erase(std::remove_if(active_.begin(), active_.end(), same), active_.end());
  if (on) {
    FaultSpec untimed = f;
    untimed.at.reset();
    untimed.duration.reset();
    active_.push_back(std::move(untimed));
  }
  return {};
}

void Plant::run_schedule() {
  const auto now = world_.time();
  for (std::size_t i = 0; i < schedule_.size();) {
    if (schedule_[i].at > now) {
      ++i;
      continue;
    }
    Scheduled due = std::move(schedule_[i]);
    schedule_.erase(schedule_.begin() + static_cast<std::ptrdiff_t>(i));
    due.fault.at.reset();
    (void)(due.inject ? inject(due.fault) : clear(due.fault));
  }
}

Snapshot Plant::snapshot() const {
  Snapshot s = world_snapshot(world_);
  for (const auto& plc : plcs_) {
    std::string kind = "conveyor";
    if (plc->name() == layout().uploader.name) {
      kind = "uploader";
    } else if (plc->name() == layout().downloader.name) {
      kind = "downloader";
    } else if (layout().robot(plc->name()) != nullptr) {
      kind = "legacy-robot";
    }
    s.machines.push_back(
        {plc->name(), kind, static_cast<std::uint16_t>(plc->fault_code()),
         plc->fault_code() == FaultCode::none ? "" : std::string(to_string(plc->fault_code()))});
  }
  for (const auto& robot : smart_robots_) {
    s.machines.push_back({robot->name(), "smart-robot", 0, robot->cable_cut() ? "cable cut" : ""});
  }
  for (const auto& f : active_) {
    s.faults.push_back(format(f));
  }
  return s;
}

}  // namespace sf::plant
