// The box uploader and downloader PLCs (plc.hpp, registers.hpp).
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "sf/plant/plc.hpp"

namespace sf::plant {

namespace {
constexpr double kMaxWait = 10.0;  // s the uploader waits for its place on the belt before it faults
}

TransferPlc::TransferPlc(const World& world, Role role)
    : PlcDevice(role == Role::upload ? world.layout().uploader.name : world.layout().downloader.name,
                transfer_bank_layout()),
      role_(role) {
  station_ = *find_station(world.layout(), spec(world).station);  // checked with the layout
}

const TransferSpec& TransferPlc::spec(const World& world) const {
  return role_ == Role::upload ? world.layout().uploader : world.layout().downloader;
}

void TransferPlc::run(World& world, double dt) {
  using namespace transfer_plc;
  if (job_.scan(bank_)) {
    begin(world);
  }
  if (job_.phase() == JobHandshake::Phase::busy) {
    remaining_s_ -= dt;
    if (remaining_s_ <= 0.0) {
      finish_job(world);
    }
  }
  fault_code_ = job_.code();
  job_.publish(bank_);
  bank_.set_discrete_input(kBoxPresent, world.box_in_place(station_.belt, station_.station) != nullptr);
  bank_.set_input_register(kStationBox, world.tag_reading(station_.belt, station_.station));
  bank_.set_input_register(kFaultCode, static_cast<std::uint16_t>(fault_code_));
  bank_.set_input_register(kJobsDone, jobs_done_);
}

void TransferPlc::begin(World& world) {
  const std::string& name = spec(world).name;
  // A real machine's cycle varies a little (air pressure, belt grip): ±10 %, from the plant's seed.
  remaining_s_ = spec(world).cycle_s * std::uniform_real_distribution<double>(0.9, 1.1)(world.random());
  waited_s_ = 0.0;
  if (role_ == Role::upload) {
    const std::uint16_t type = bank_.holding_register(transfer_plc::kBoxType);
    if (type == 0 || type > world.layout().catalog.box_types.size()) {
      job_.fail(FaultCode::bad_job);
      world.record(EventKind::job_failed, name, 0, -1, {}, fmt::format("box type {} unknown", type));
      return;
    }
    box_type_ = type - 1U;
    world.record(EventKind::job_started, name, 0, -1, {}, world.layout().catalog.box_types[box_type_].name);
    return;
  }
  const Box* box = world.box_in_place(station_.belt, station_.station);
  if (box == nullptr) {
    job_.fail(FaultCode::no_box);
    world.record(EventKind::job_failed, name, 0, -1, {}, "no box in place");
    return;
  }
  world.record(EventKind::job_started, name, box->id);
}

void TransferPlc::finish_job(World& world) {
  const std::string& name = spec(world).name;
  if (role_ == Role::upload) {
    auto id = world.place_box(box_type_, station_, name);
    if (!id) {
      waited_s_ -= remaining_s_;  // remaining_s_ is the (negative) time past the cycle
      remaining_s_ = 0.0;
      if (waited_s_ > kMaxWait) {
        job_.fail(FaultCode::station_occupied);
        world.record(EventKind::job_failed, name, 0, -1, {}, id.error().message);
      }
      return;
    }
    bank_.set_input_register(transfer_plc::kBoxId, static_cast<std::uint16_t>(*id));
    ++jobs_done_;
    job_.finish();
    world.record(EventKind::job_done, name, *id);
    return;
  }
  auto inspection = world.take_box(station_, name);
  if (!inspection) {
    job_.fail(FaultCode::no_box);
    world.record(EventKind::job_failed, name, 0, -1, {}, inspection.error().message);
    return;
  }
  publish_inspection(*inspection);
  ++jobs_done_;
  job_.finish();
  world.record(EventKind::job_done, name, inspection->box);
}

void TransferPlc::publish_inspection(const Inspection& inspection) {
  using namespace transfer_plc;
  bank_.set_input_register(kBoxId, static_cast<std::uint16_t>(inspection.box));
  bank_.set_input_register(
      kWeight, static_cast<std::uint16_t>(std::lround(std::min(inspection.weight_g, 6553.5) * 10.0)));
  int total = 0;
  for (std::size_t c = 0; c < inspection.counts.size() && c < kMaxRepeats; ++c) {
    total += inspection.counts[c];
    bank_.set_input_register(static_cast<std::uint16_t>(kCandyCount + c),
                             static_cast<std::uint16_t>(inspection.counts[c]));
  }
  bank_.set_input_register(kCandyTotal, static_cast<std::uint16_t>(total));
}

}  // namespace sf::plant
