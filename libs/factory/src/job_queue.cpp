#include "sf/factory/job_queue.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace sf::factory {

Status JobQueue::add(std::string id, Operation op, std::chrono::nanoseconds estimate) {
  const bool taken =
      (current_ && current_->id == id) ||
      std::any_of(queue_.begin(), queue_.end(), [&](const QueuedJob& j) { return j.id == id; });
  if (id.empty() || taken) {
    return make_error(Errc::invalid_argument, fmt::format("job id '{}' is empty or already in use", id));
  }
  queue_.push_back(QueuedJob{std::move(id), std::move(op), estimate});
  return {};
}

Status JobQueue::admit(std::string_view machine, std::string id, const Operation& op,
                       const std::optional<Estimate>& estimate, std::string_view why_not) {
  if (!estimate) {
    return make_error(Errc::state, fmt::format("{} declines {}: {}", machine, op.type, why_not));
  }
  return add(std::move(id), op, estimate->duration);
}

ControllerStatus JobQueue::status(const PackMLUnit& unit) const {
  ControllerStatus status;
  status.packml = unit.status();
  if (current_) {
    status.job = current_->id;
    status.operation = current_->op;
  }
  status.queued = queued();
  status.working_time = worked_ + (current_ ? current_->active : std::chrono::nanoseconds{0});
  return status;
}

Status JobQueue::cancel(const std::string& id) {
  if (current_ && current_->id == id) {
    current_->cancel = true;
    return {};
  }
  auto it = std::find_if(queue_.begin(), queue_.end(), [&](const QueuedJob& j) { return j.id == id; });
  if (it == queue_.end()) {
    return make_error(Errc::not_found, fmt::format("no job '{}'", id));
  }
  outcomes_.push_back({id, false, "cancelled before it started"});
  queue_.erase(it);
  return {};
}

bool JobQueue::begin_next() {
  return begin_next([](const Operation&) { return true; });
}

bool JobQueue::begin_next(const std::function<bool(const Operation&)>& ready) {
  if (current_) {
    return false;
  }
  auto it = std::find_if(queue_.begin(), queue_.end(), [&](const QueuedJob& j) { return ready(j.op); });
  if (it == queue_.end()) {
    return false;
  }
  current_ = std::move(*it);
  queue_.erase(it);
  return true;
}

void JobQueue::finish(bool ok, std::string detail, std::map<std::string, double> results) {
  if (current_) {
    worked_ += current_->active;
    outcomes_.push_back({current_->id, ok, std::move(detail), std::move(results)});
    current_.reset();
  }
}

void JobQueue::drop_queued(const std::string& why) {
  for (const QueuedJob& j : queue_) {
    outcomes_.push_back({j.id, false, fmt::format("{} before it started", why)});
  }
  queue_.clear();
}

std::chrono::nanoseconds JobQueue::backlog() const {
  std::chrono::nanoseconds total{0};
  if (current_) {
    total += std::max(std::chrono::nanoseconds{0}, current_->estimate - current_->active);
  }
  for (const QueuedJob& j : queue_) {
    total += j.estimate;
  }
  return total;
}

}  // namespace sf::factory
