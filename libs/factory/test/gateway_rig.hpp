// A rig for the gateways: the plant on a ManualClock, each gateway on a
// modbus::MemoryClient to its PLC device (the Modbus server's own request
// path), all stepped by one millisecond: the plant, then every gateway whose
// poll is due. Outcomes are collected per job.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "sf/factory/conveying.hpp"
#include "sf/factory/gateway.hpp"
#include "sf/modbus/memory_client.hpp"
#include "sf/plant/plant.hpp"

namespace sf::factory::testing {

using namespace std::chrono_literals;

class GatewayRig {
 public:
  explicit GatewayRig(std::uint64_t seed = 1)
      : plant_(std::make_unique<plant::Plant>(*line::default_layout(), clock_, plant::PlantOptions{seed})) {}

  // A gateway for `machine` of `kind`, from a configuration with `extra` YAML lines (started
  // to Execute unless `extra` says otherwise).
  Gateway& add(const std::string& machine, std::string_view kind,
               const std::string& extra = "start: execute\n") {
    auto setup = parse_gateway_config(fmt::format("machine: {}\nkind: {}\n{}", machine, kind, extra));
    EXPECT_TRUE(setup) << setup.error().describe();
    modbus::MemoryClientOptions options;
    options.clock = &clock_;
    options.response_timeout = setup->config.modbus.timeout;
    clients_.push_back(std::make_unique<modbus::MemoryClient>(*plant_->plc(machine), options));
    gateways_.push_back(
        std::make_unique<Gateway>(setup->config, std::move(setup->layout), *clients_.back(), clock_));
    Gateway& g = *gateways_.back();
    g.on_job_end([this](const JobOutcome& o) { outcomes_[o.job] = o; });
    return g;
  }

  // A gateway and a box put at `station` for it, after a few polls.
  struct WithBox {
    Gateway& gateway;
    std::uint16_t box;
  };
  WithBox add_with_box(const std::string& machine, std::string_view kind, std::string_view station,
                       const std::string& extra = "start: execute\n") {
    Gateway& g = add(machine, kind, extra);
    const std::uint16_t box = put_box(station);
    run_for(100ms);
    return {g, box};
  }

  void step() {
    clock_.advance(1ms);
    plant_->advance_to(clock_.now());
    for (auto& g : gateways_) {
      (void)g->poll(clock_.now());
    }
    for (auto& f : after_step_) {
      f();
    }
  }
  // Runs `f` at the end of every step (what else the test drives on this clock).
  void after_step(std::function<void()> f) { after_step_.push_back(std::move(f)); }
  template <typename F>
  bool run_until(F done, std::chrono::milliseconds limit) {
    const auto end = clock_.now() + limit;
    while (!done()) {
      if (clock_.now() >= end) {
        return false;
      }
      step();
    }
    return true;
  }
  void run_for(std::chrono::milliseconds d) {
    const auto end = clock_.now() + d;
    while (clock_.now() < end) {
      step();
    }
  }
  // Submits and runs until the job's outcome is in.
  JobOutcome run_job(Gateway& g, const std::string& job, const Operation& op,
                     std::chrono::milliseconds limit = 60s) {
    auto submitted = g.submit(job, op);
    EXPECT_TRUE(submitted) << submitted.error().describe();
    EXPECT_TRUE(run_until([&] { return outcomes_.contains(job); }, limit)) << job << " did not end";
    return outcomes_.contains(job) ? outcomes_.at(job) : JobOutcome{job, false, "no outcome", {}};
  }
  bool ended(const std::string& job) const { return outcomes_.contains(job); }
  const JobOutcome& outcome(const std::string& job) const { return outcomes_.at(job); }

  std::size_t place(std::string_view name) const {
    auto index = place_index(plant_->layout(), name);
    EXPECT_TRUE(index) << name;
    return index.value_or(0);
  }
  Operation transport(std::uint16_t box, std::string_view from, std::string_view to) const {
    return {
        std::string(kTransport),
        {{"box", box}, {"from", static_cast<double>(place(from))}, {"to", static_cast<double>(place(to))}}};
  }
  std::size_t candy(std::string_view name) const { return *plant_->layout().catalog.candy_index(name); }
  // A box of `type` put straight onto the belt at `station` (not through the uploader).
  std::uint16_t put_box(std::string_view station, std::string_view type = "small-box") {
    auto at = line::find_station(plant_->layout(), station);
    auto id = plant_->world().place_box(*plant_->layout().catalog.box_index(type), *at, "test");
    EXPECT_TRUE(id) << id.error().describe();
    return id ? static_cast<std::uint16_t>(*id) : 0;
  }
  void inject(std::string_view fault) {
    auto f = plant::parse_fault(fault);
    ASSERT_TRUE(f) << f.error().describe();
    ASSERT_TRUE(plant_->inject(*f));
  }
  void clear(std::string_view fault) {
    auto f = plant::parse_fault(fault);
    ASSERT_TRUE(f) << f.error().describe();
    ASSERT_TRUE(plant_->clear(*f));
  }

  // Whether box `id` stands in place at `station` ("conveyor3/toshiba").
  bool at(std::uint16_t id, std::string_view station) const {
    auto s = line::find_station(plant_->layout(), station);
    const plant::Box* b = plant_->world().box(id);
    return s && b != nullptr && plant_->world().box_in_place(s->belt, s->station) == b;
  }
  Gateway& gateway(std::string_view machine) {
    for (auto& g : gateways_) {
      if (g->config().controller.machine == machine) {
        return *g;
      }
    }
    ADD_FAILURE() << "no gateway " << machine;
    return *gateways_.front();
  }

  ManualClock& clock() { return clock_; }
  plant::Plant& plant() { return *plant_; }
  plant::World& world() { return plant_->world(); }

 private:
  ManualClock clock_;
  std::unique_ptr<plant::Plant> plant_;
  std::vector<std::unique_ptr<modbus::MemoryClient>> clients_;
  std::vector<std::unique_ptr<Gateway>> gateways_;
  std::map<std::string, JobOutcome> outcomes_;
  std::vector<std::function<void()>> after_step_;
};

inline bool has_tag(const ControllerStatus& status, std::string_view name) {
  return std::any_of(status.tags.begin(), status.tags.end(), [&](const Tag& t) { return t.name == name; });
}

// The tag of `status` named `name` (a failed expectation when there is none).
inline Tag tag(const ControllerStatus& status, std::string_view name) {
  for (const auto& t : status.tags) {
    if (t.name == name) {
      return t;
    }
  }
  ADD_FAILURE() << "no tag " << name;
  return {};
}

}  // namespace sf::factory::testing
