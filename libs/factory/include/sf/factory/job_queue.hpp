// The awarded work of one controller: the job in work and the ones queued
// behind it, their estimates (a bid's start_in is the backlog), and the
// outcomes waiting to be reported. Every controller keeps its jobs the same
// way; what a job does on the machine is the controller's business.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/factory/machine.hpp"
#include "sf/factory/packml.hpp"

namespace sf::factory {

struct QueuedJob {
  std::string id;
  Operation op;
  std::chrono::nanoseconds estimate{0};
  std::chrono::nanoseconds active{0};  // time in work while the unit could work on it
  bool cancel = false;                 // asked to stop: ends once the machine is settled
};

class JobQueue {
 public:
  // Refused (Errc::invalid_argument) when the id is empty or already in use.
  Status add(std::string id, Operation op, std::chrono::nanoseconds estimate);
  // MachineController::submit: `op` queued with the controller's estimate, or refused (Errc::state:
  // "<machine> declines <op>: <why_not>") when it gave none.
  Status admit(std::string_view machine, std::string id, const Operation& op,
               const std::optional<Estimate>& estimate, std::string_view why_not);
  // A controller's status as far as its unit and its jobs tell: PackML state and
  // counters, the job in work, its operation, the queue's length.
  // Its working_time: the active time of every job that ended plus the current one's.
  [[nodiscard]] ControllerStatus status(const PackMLUnit& unit) const;
  // A queued job ends at once ("cancelled before it started"); the one in
  // work is flagged (QueuedJob::cancel). Errc::not_found for an unknown id.
  Status cancel(const std::string& id);

  [[nodiscard]] QueuedJob* current() { return current_ ? &*current_ : nullptr; }
  [[nodiscard]] const QueuedJob* current() const { return current_ ? &*current_ : nullptr; }
  // Moves the next queued job into work; false when there is none.
  bool begin_next();
  // Moves the first queued job whose operation is `ready` into work (FIFO among the
  // ready ones); false when none is. Many boxes share the line: a job waits for its
  // box, and a later job whose box is already at the station need not wait behind it.
  bool begin_next(const std::function<bool(const Operation&)>& ready);
  // The job in work ends with `ok`, `detail` and its typed results (JobOutcome::results).
  void finish(bool ok, std::string detail, std::map<std::string, double> results = {});
  // Every queued job fails with "<why> before it started" (the one in work
  // must have been finished first).
  void drop_queued(const std::string& why);

  // Remaining work: what is left of the current job's estimate plus every queued estimate.
  [[nodiscard]] std::chrono::nanoseconds backlog() const;
  [[nodiscard]] std::uint32_t queued() const { return static_cast<std::uint32_t>(queue_.size()); }
  [[nodiscard]] std::uint32_t length() const { return queued() + (current_ ? 1U : 0U); }

  // The outcomes since the last call, for MachineController::job_ended (called
  // after the controller's state is complete: callbacks may submit or cancel).
  std::vector<JobOutcome> take_outcomes() { return std::exchange(outcomes_, {}); }

 private:
  std::optional<QueuedJob> current_;
  std::deque<QueuedJob> queue_;
  std::vector<JobOutcome> outcomes_;
  std::chrono::nanoseconds worked_{0};  // active time of the jobs that ended
};

}  // namespace sf::factory
