#include "sf/factory/controller_thread.hpp"

#include "sf/core/realtime.hpp"

namespace sf::factory {

ControllerThread::ControllerThread(MachineController& controller, Clock& clock,
                                   ControllerThreadOptions options)
    : controller_(&controller), clock_(&clock), options_(options) {
  controller_->on_job_end([this](const JobOutcome& outcome) {
    if (on_job_end_) {
      on_job_end_(outcome);
    }
  });
  status_ = controller_->status();
}

ControllerThread::~ControllerThread() {
  stop();
}

void ControllerThread::on_job_end(std::function<void(const JobOutcome&)> callback) {
  on_job_end_ = std::move(callback);
}

void ControllerThread::start() {
  if (running_.exchange(true)) {
    return;
  }
  stop_ = false;
  thread_ = std::thread([this] { loop(); });
  if (options_.realtime) {
    realtime_ = try_realtime(thread_, options_.priority);
  }
}

void ControllerThread::stop() {
  if (!running_.load()) {
    return;
  }
  stop_ = true;
  thread_.join();
  running_ = false;
  run_posted();
}

void ControllerThread::post(Task task) {
  {
    std::lock_guard lock(tasks_mutex_);
    tasks_.push_back(std::move(task));
  }
  if (!running_.load()) {
    run_posted();  // nobody polls: the caller's thread is the controller's now
  }
}

void ControllerThread::loop() {
  Clock::time_point deadline = clock_->now();
  while (!stop_.load()) {
    clock_->sleep_until(deadline);
    const auto now = clock_->now();
    {
      std::lock_guard lock(status_mutex_);
      lateness_.record(now > deadline ? now - deadline : deadline - now);
    }
    deadline = controller_->poll(now);
    polls_.fetch_add(1, std::memory_order_relaxed);
    run_posted();
    publish(now);
    // A turn that overran its deadline is not made up for: the next one starts now.
    if (deadline < clock_->now()) {
      deadline = clock_->now();
    }
  }
}

void ControllerThread::run_posted() {
  std::deque<Task> tasks;
  {
    std::lock_guard lock(tasks_mutex_);
    tasks.swap(tasks_);
  }
  for (auto& task : tasks) {
    task(*controller_);
  }
}

void ControllerThread::publish(Clock::time_point now) {
  if (now < next_status_) {
    return;
  }
  next_status_ = now + options_.status_interval;
  ControllerStatus s = controller_->status();
  std::lock_guard lock(status_mutex_);
  status_ = std::move(s);
}

ControllerStatus ControllerThread::status() const {
  if (!running_.load()) {
    return controller_->status();
  }
  std::lock_guard lock(status_mutex_);
  return status_;
}

ethercat::master::DurationHistogram ControllerThread::lateness() const {
  std::lock_guard lock(status_mutex_);
  return lateness_;
}

void ControllerThread::reset_lateness() {
  std::lock_guard lock(status_mutex_);
  lateness_.reset();
}

// --- RemoteController -------------------------------------------------------

RemoteController::RemoteController(ControllerThread& thread, const Identification& identification,
                                   std::function<void(std::function<void()>)> deliver)
    : thread_(&thread), identification_(identification) {
  thread.on_job_end([this, deliver = std::move(deliver)](const JobOutcome& outcome) {
    deliver([this, outcome] { job_ended(outcome); });
  });
}

std::vector<std::string> RemoteController::operations() const {
  return thread_->call([](MachineController& c) { return c.operations(); });
}

std::optional<Estimate> RemoteController::estimate(const Operation& op, std::string* why_not) const {
  return thread_->call([&](MachineController& c) { return c.estimate(op, why_not); });
}

Status RemoteController::submit(const std::string& job, const Operation& op) {
  return thread_->call([&](MachineController& c) { return c.submit(job, op); });
}

Status RemoteController::cancel(const std::string& job) {
  return thread_->call([&](MachineController& c) { return c.cancel(job); });
}

Status RemoteController::command(PackMLCommand command) {
  return thread_->call([&](MachineController& c) { return c.command(command); });
}

Clock::time_point RemoteController::poll(Clock::time_point now) {
  return now + std::chrono::seconds{1};
}

ControllerStatus RemoteController::status() const {
  return thread_->status();
}

}  // namespace sf::factory
