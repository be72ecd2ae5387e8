// The controller's own thread: every call from another thread runs on it,
// after a poll; the status snapshot follows the controller; job ends reach
// the thread that owns the proxy. The controller here is a small PackML unit
// that records which thread calls it (the real controllers are tested
// against the plant; what is under test is the crossing of threads).
#include "sf/factory/controller_thread.hpp"

#include <gtest/gtest.h>

#include "sf/factory/packml.hpp"

namespace sf::factory {
namespace {

using namespace std::chrono_literals;

class CountingController final : public MachineController {
 public:
  explicit CountingController(const Clock& clock) : unit_(clock) {}
  [[nodiscard]] const Identification& identification() const override { return id_; }
  [[nodiscard]] std::vector<std::string> operations() const override {
    seen(std::this_thread::get_id());
    return {"load"};
  }
  [[nodiscard]] std::optional<Estimate> estimate(const Operation& /*op*/,
                                                 std::string* why_not) const override {
    seen(std::this_thread::get_id());
    if (unit_.state() != PackMLState::Execute) {
      *why_not = "not in Execute";
      return std::nullopt;
    }
    return Estimate{0ns, 10ms, 0};
  }
  Status submit(const std::string& job, const Operation& /*op*/) override {
    seen(std::this_thread::get_id());
    pending_.push_back(job);
    return {};
  }
  Status cancel(const std::string& /*job*/) override { return make_error(Errc::not_found, "no such job"); }
  Status command(PackMLCommand command) override {
    seen(std::this_thread::get_id());
    return unit_.command(command);
  }
  Clock::time_point poll(Clock::time_point now) override {
    poll_thread_ = std::this_thread::get_id();
    if (PackMLUnit::acting(unit_.state())) {
      (void)unit_.state_complete();
    }
    for (const auto& job : pending_) {
      job_ended({job, true, "done"});
    }
    pending_.clear();
    return now + 1ms;
  }
  [[nodiscard]] ControllerStatus status() const override {
    ControllerStatus s;
    s.packml = unit_.status();
    return s;
  }

  void seen(std::thread::id id) const { callers_.push_back(id); }
  mutable std::vector<std::thread::id> callers_;
  std::thread::id poll_thread_;

 private:
  Identification id_{"robot", "smart-robot", "maker", "model", "1"};
  PackMLUnit unit_;
  std::vector<std::string> pending_;
};

TEST(ControllerThread, CallsRunOnTheControllersThreadAndJobEndsComeBack) {
  SteadyClock& clock = SteadyClock::instance();
  CountingController controller(clock);
  ControllerThread thread(controller, clock, {.realtime = false, .status_interval = 1ms});
  std::mutex delivered_mutex;
  std::vector<std::function<void()>> delivered;  // what the owner's thread will run
  RemoteController remote(thread, controller.identification(), [&](std::function<void()> f) {
    std::lock_guard lock(delivered_mutex);
    delivered.push_back(std::move(f));
  });
  std::vector<JobOutcome> ends;
  remote.on_job_end([&](const JobOutcome& o) { ends.push_back(o); });
  thread.start();

  std::string why;
  EXPECT_FALSE(remote.estimate(Operation{"load", {}}, &why));
  EXPECT_EQ(why, "not in Execute");
  ASSERT_TRUE(remote.command(PackMLCommand::Reset));
  auto refused = remote.command(PackMLCommand::Unhold);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().code, Errc::state);
  // The snapshot follows: Resetting completes on the next poll, then Idle.
  for (int i = 0; i < 2000 && remote.status().packml.state != PackMLState::Idle; ++i) {
    std::this_thread::sleep_for(1ms);
  }
  EXPECT_EQ(remote.status().packml.state, PackMLState::Idle);
  ASSERT_TRUE(remote.command(PackMLCommand::Start));
  for (int i = 0; i < 2000 && remote.status().packml.state != PackMLState::Execute; ++i) {
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_TRUE(remote.estimate(Operation{"load", {}}, &why)) << why;
  ASSERT_TRUE(remote.submit("j1", Operation{"load", {}}));
  for (int i = 0; i < 2000; ++i) {
    std::lock_guard lock(delivered_mutex);
    if (!delivered.empty()) {
      break;
    }
    std::this_thread::sleep_for(1ms);
  }
  thread.stop();
  EXPECT_TRUE(ends.empty());  // not before the owner's thread runs what was delivered
  for (auto& f : delivered) {
    f();
  }
  ASSERT_EQ(ends.size(), 1U);
  EXPECT_EQ(ends[0].job, "j1");
  EXPECT_TRUE(ends[0].ok);

  ASSERT_FALSE(controller.callers_.empty());
  for (auto id : controller.callers_) {
    EXPECT_EQ(id, controller.poll_thread_);
    EXPECT_NE(id, std::this_thread::get_id());
  }
  EXPECT_GT(thread.polls(), 0U);
  EXPECT_GT(thread.lateness().count(), 0U);
}

TEST(ControllerThread, WithoutItsThreadCallsRunOnTheCallersThread) {
  SteadyClock& clock = SteadyClock::instance();
  CountingController controller(clock);
  ControllerThread thread(controller, clock, {.realtime = false});
  RemoteController remote(thread, controller.identification(), [](std::function<void()> f) { f(); });
  EXPECT_EQ(remote.operations(), std::vector<std::string>{"load"});
  ASSERT_EQ(controller.callers_.size(), 1U);
  EXPECT_EQ(controller.callers_[0], std::this_thread::get_id());
  EXPECT_EQ(remote.status().packml.state, PackMLState::Stopped);
}

}  // namespace
}  // namespace sf::factory
