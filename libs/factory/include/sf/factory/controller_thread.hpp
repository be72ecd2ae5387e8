// A MachineController on a thread of its own, and how the rest of a process
// reaches it. The smart robot's IPC (paper §VII.A) runs its EtherCAT cycle
// at 1 kHz while its OPC UA server and its DDS agent work on other threads:
// the controller's contract (machine.hpp) has one thread drive it, so that
// thread — the ControllerThread — polls it on its deadlines and, after each
// poll, runs the calls other threads posted (an estimate for a bid, a PackML
// command). A call therefore waits at most one cycle plus the calls ahead of
// it, and never delays the cycle it follows; the cycle's own timing (its
// wake-up lateness) is measured.
//
// RemoteController is the controller as another thread sees it: every member
// becomes a call on the controller's thread, status() is the snapshot the
// thread publishes, and job ends are handed to a `deliver` function (e.g. the
// DDS executor's post) so they arrive on the caller's thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <type_traits>

#include "sf/core/clock.hpp"
#include "sf/ethercat/master/statistics.hpp"
#include "sf/factory/machine.hpp"

namespace sf::factory {

struct ControllerThreadOptions {
  bool realtime = true;  // try SCHED_FIFO + mlockall (silently normal without the privilege)
  int priority = 80;
  // How often the status snapshot is refreshed (building it allocates: not every cycle).
  std::chrono::nanoseconds status_interval{std::chrono::milliseconds{10}};
};

class ControllerThread {
 public:
  using Task = std::function<void(MachineController&)>;

  // The controller and clock must outlive the thread. Job ends of the
  // controller are taken over: set on_job_end here.
  ControllerThread(MachineController& controller, Clock& clock, ControllerThreadOptions options = {});
  ~ControllerThread();
  ControllerThread(const ControllerThread&) = delete;
  ControllerThread& operator=(const ControllerThread&) = delete;

  void start();
  // Stops after the current turn and joins; posted calls not yet run are run
  // on the caller's thread first, so nobody waits forever.
  void stop();
  [[nodiscard]] bool running() const { return running_.load(); }
  [[nodiscard]] bool realtime_active() const { return realtime_.load(); }

  // Runs `task` on the controller's thread after its next poll.
  void post(Task task);
  // The same, waiting for the result.
  template <typename F>
  auto call(F&& f) -> std::invoke_result_t<F, MachineController&> {
    using R = std::invoke_result_t<F, MachineController&>;
    auto promise = std::make_shared<std::promise<R>>();
    auto result = promise->get_future();
    post([promise, f = std::forward<F>(f)](MachineController& c) mutable {
      if constexpr (std::is_void_v<R>) {
        f(c);
        promise->set_value();
      } else {
        promise->set_value(f(c));
      }
    });
    return result.get();
  }

  // Called on the controller's thread when a job ends.
  void on_job_end(std::function<void(const JobOutcome&)> callback);

  // The latest snapshot (at most status_interval old while running).
  [[nodiscard]] ControllerStatus status() const;
  // Wake-up lateness of the polls: |wake-up − deadline|.
  [[nodiscard]] ethercat::master::DurationHistogram lateness() const;
  void reset_lateness();
  [[nodiscard]] std::uint64_t polls() const { return polls_.load(); }

 private:
  void loop();
  void turn(Clock::time_point now);
  void run_posted();
  void publish(Clock::time_point now);

  MachineController* controller_;
  Clock* clock_;
  ControllerThreadOptions options_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_{false};
  std::atomic<bool> realtime_{false};
  std::atomic<std::uint64_t> polls_{0};

  mutable std::mutex tasks_mutex_;
  std::deque<Task> tasks_;

  mutable std::mutex status_mutex_;
  ControllerStatus status_;
  ethercat::master::DurationHistogram lateness_;
  Clock::time_point next_status_{};
  std::function<void(const JobOutcome&)> on_job_end_;
};

class RemoteController final : public MachineController {
 public:
  // `deliver` runs a function on the thread that owns this proxy (job ends).
  RemoteController(ControllerThread& thread, const Identification& identification,
                   std::function<void(std::function<void()>)> deliver);

  // The controller's own thread polls it: nothing to do here.
  Clock::time_point poll(Clock::time_point now) override;
  // The thread's snapshot, without waiting for the controller.
  [[nodiscard]] ControllerStatus status() const override;
  [[nodiscard]] const Identification& identification() const override { return identification_; }

  // Calls on the controller's thread (each waits for its next poll):
  [[nodiscard]] std::vector<std::string> operations() const override;
  Status command(PackMLCommand command) override;
  [[nodiscard]] std::optional<Estimate> estimate(const Operation& op,
                                                 std::string* why_not = nullptr) const override;
  Status cancel(const std::string& job) override;
  Status submit(const std::string& job, const Operation& op) override;

 private:
  ControllerThread* thread_;
  Identification identification_;
};

}  // namespace sf::factory
