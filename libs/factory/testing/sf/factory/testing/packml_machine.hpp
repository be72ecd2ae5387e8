// PackMLMachine: a small MachineController for tests of what sits above controllers (the OPC UA
// model, its host): a PackML unit whose acting states finish on the next poll, "load" jobs that
// take a fixed time in Execute, and a few tags the test can set (value, quality, reason). The
// real controllers (the legacy-machine gateways, the smart robot) are tested against the plant.
//
// Like every controller it is driven by one thread: a test that runs it under a MachineHost
// changes it through MachineHost::post.
#pragma once

#include <chrono>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "sf/factory/machine.hpp"
#include "sf/factory/packml.hpp"

namespace sf::factory::testing {

class PackMLMachine final : public MachineController {
 public:
  explicit PackMLMachine(const Clock& clock, Identification id = default_identification(),
                         std::chrono::nanoseconds job_time = std::chrono::seconds(1))
      : id_(std::move(id)), unit_(clock), job_time_(job_time) {
    set_tag("sensor.temperature", 21.5, Tag::Quality::good, {}, "CEL");
    set_tag("sensor.part_present", false);
    set_tag("plc.jobs_done", std::int64_t{0});
  }

  static Identification default_identification() {
    return {"scara-robot-1", "smart-robot", "smartfactory", "SCARA Robot 1", "SR1-0001"};
  }

  [[nodiscard]] const Identification& identification() const override { return id_; }
  [[nodiscard]] std::vector<std::string> operations() const override { return {std::string(kLoad)}; }
  [[nodiscard]] std::optional<Estimate> estimate(const Operation& op, std::string* why_not) const override {
    if (op.type != kLoad || unit_.state() != PackMLState::Execute) {
      if (why_not != nullptr) {
        *why_not = fmt::format("{} in {}", op.type, to_string(unit_.state()));
      }
      return std::nullopt;
    }
    return Estimate{job_time_ * static_cast<int>(queue_.size()), job_time_,
                    static_cast<std::uint32_t>(queue_.size())};
  }
  Status submit(const std::string& job, const Operation& op) override {
    std::string why;
    if (!estimate(op, &why)) {
      return make_error(Errc::state, why);
    }
    queue_.emplace_back(job, op);
    return {};
  }
  Status cancel(const std::string& job) override {
    std::erase_if(queue_, [&](const auto& q) { return q.first == job; });
    return {};
  }
  Status command(PackMLCommand command) override {
    const bool stops =
        command == PackMLCommand::Hold || command == PackMLCommand::Stop || command == PackMLCommand::Abort;
    return unit_.command(command,
                         stops ? std::optional<StopReason>(StopReason{0, "operator", {}}) : std::nullopt);
  }
  Clock::time_point poll(Clock::time_point now) override {
    if (PackMLUnit::acting(unit_.state())) {
      (void)unit_.state_complete();
    }
    if (unit_.state() != PackMLState::Execute || queue_.empty()) {
      return now + poll_period;
    }
    if (!started_) {
      started_ = now;
    } else if (now - *started_ >= job_time_) {
      finish_job();
    }
    return now + poll_period;
  }
  [[nodiscard]] ControllerStatus status() const override {
    ControllerStatus s;
    s.packml = unit_.status();
    if (!queue_.empty()) {
      s.job = queue_.front().first;
      s.operation = queue_.front().second;
      s.queued = static_cast<std::uint32_t>(queue_.size() - 1);
    }
    s.fault = fault_;
    s.tags = tags_;
    return s;
  }

  // Test controls (on the controller's thread).
  // A tag's value; `unit` (a UNECE code, Tag::unit) stays once given.
  void set_tag(const std::string& name, decltype(Tag::value) value, Tag::Quality quality = Tag::Quality::good,
               std::string reason = {}, std::string unit = {}) {
    for (Tag& t : tags_) {
      if (t.name == name) {
        t = Tag{name, std::move(value), quality, std::move(reason), unit.empty() ? t.unit : std::move(unit)};
        return;
      }
    }
    tags_.push_back(Tag{name, std::move(value), quality, std::move(reason), std::move(unit)});
  }
  void remove_tag(const std::string& name) {
    std::erase_if(tags_, [&](const Tag& t) { return t.name == name; });
  }
  void fail(std::int32_t code, std::string why) {
    fault_ = why;
    unit_.fault(StopReason{code, std::move(why), {}});
  }
  [[nodiscard]] PackMLState state() const { return unit_.state(); }

  std::chrono::nanoseconds poll_period = std::chrono::milliseconds(5);

 private:
  void finish_job() {
    const auto [job, op] = queue_.front();
    queue_.pop_front();
    started_.reset();
    unit_.count(true);
    set_tag("plc.jobs_done", static_cast<std::int64_t>(unit_.status().produced));
    job_ended({job, true, fmt::format("{} done", op.type)});
  }

  Identification id_;
  PackMLUnit unit_;
  std::chrono::nanoseconds job_time_;
  std::deque<std::pair<std::string, Operation>> queue_;
  std::optional<Clock::time_point> started_;  // of the job in work
  std::vector<Tag> tags_;
  std::string fault_;
};

}  // namespace sf::factory::testing
