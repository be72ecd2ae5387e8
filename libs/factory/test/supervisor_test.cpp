// The Supervisor with small real child processes (/bin/sh scripts that print a ready line, crash
// or hang) on a ManualClock: start order, restarts with back-off, giving up, ready timeouts and
// the stop in reverse order.
#include "sf/factory/supervisor.hpp"

#include <signal.h>

#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "sf/factory/line_supervisor.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf::factory {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

SupervisedProcess sh(std::string name, std::string script) {
  return {std::move(name),
          {"/bin/sh", "-c", std::move(script)},
          [](std::string_view line) -> std::optional<ReadyInfo> {
            if (line == "ready") {
              return ReadyInfo{};
            }
            return controller_ready(line);
          },
          {}};
}

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class SupervisorTest : public ::testing::Test {
 protected:
  SupervisorOptions options() {
    SupervisorOptions o;
    o.log_dir = dir_.path() / "log";
    o.backoff_initial = 500ms;
    o.backoff_max = 2s;
    o.stable_after = 10s;
    o.max_failures = 10;
    o.stop_grace = 5s;
    return o;
  }

  // Polls until `done` holds; the children are real processes, so this waits for them in real
  // time (at most 20 s, a bound for a stuck test, not a measurement).
  static bool drive(Supervisor& s, const std::function<bool()>& done) {
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    while (std::chrono::steady_clock::now() < deadline) {
      s.poll();
      if (done()) {
        return true;
      }
      std::this_thread::sleep_for(2ms);
    }
    return false;
  }

  static ProcessStatus of(const Supervisor& s, std::size_t i) { return s.status().at(i); }

  static std::function<bool()> in_state(const Supervisor& s, std::size_t i, ProcessState state) {
    return [&s, i, state] { return of(s, i).state == state; };
  }

  std::string path(std::string_view name) const { return (dir_.path() / name).string(); }

  sf::testing::TempDir dir_;
  ManualClock clock_;
};

TEST_F(SupervisorTest, EachProcessStartsAfterTheOneBeforeIsReady) {
  const std::string go = path("go");
  int plant_ready = 0;
  auto first =
      sh("plant", "echo waiting; while [ ! -e " + go + " ]; do sleep 0.01; done; echo ready; exec sleep 60");
  first.on_ready = [&](std::string_view line) {
    EXPECT_EQ(line, "ready");
    ++plant_ready;
    return Status{};
  };
  Supervisor s({first, sh("controller", "echo ready; exec sleep 60")}, options(), clock_);
  ASSERT_TRUE(s.begin());
  ASSERT_TRUE(drive(s, [&] { return read(of(s, 0).log).find("\nwaiting") != std::string::npos; }));
  s.poll();
  EXPECT_EQ(of(s, 0).state, ProcessState::starting);
  EXPECT_GT(of(s, 0).pid, 0);
  EXPECT_EQ(of(s, 1).state, ProcessState::stopped);
  EXPECT_EQ(of(s, 1).pid, -1);
  EXPECT_EQ(plant_ready, 0);

  std::ofstream(go).put('\n');
  ASSERT_TRUE(drive(s, [&] { return s.all_up(); }));
  EXPECT_EQ(plant_ready, 1);
  EXPECT_GT(of(s, 1).pid, 0);
  EXPECT_FALSE(s.start_error());
  clock_.advance(5s);
  EXPECT_EQ(of(s, 0).uptime, 5s);
  s.stop();
  EXPECT_EQ(of(s, 0).state, ProcessState::stopped);
  EXPECT_EQ(of(s, 1).state, ProcessState::stopped);
}

TEST_F(SupervisorTest, ACrashedProcessIsRestartedWithADoublingBackOff) {
  Supervisor s(
      {sh("gateway", R"(echo '{"event":"ready","opcua":"opc.tcp://127.0.0.1:4851"}'; exec sleep 60)")},
      options(), clock_);
  ASSERT_TRUE(s.begin());
  ASSERT_TRUE(drive(s, [&] { return s.all_up(); }));
  EXPECT_EQ(of(s, 0).opcua, "opc.tcp://127.0.0.1:4851");

  // Back-offs of 0.5, 1, 2 and (the maximum) 2 s for four crashes in a row.
  unsigned restarts = 0;
  for (const auto backoff : {500ms, 1000ms, 2000ms, 2000ms}) {
    const pid_t before = of(s, 0).pid;
    ASSERT_EQ(::kill(before, SIGKILL), 0);
    ASSERT_TRUE(drive(s, in_state(s, 0, ProcessState::restarting)));
    EXPECT_NE(of(s, 0).last_exit.find("signal 9"), std::string::npos) << of(s, 0).last_exit;
    EXPECT_EQ(of(s, 0).pid, -1);
    clock_.advance(backoff - 1ms);
    s.poll();
    EXPECT_EQ(of(s, 0).state, ProcessState::restarting)
        << "before its back-off of " << backoff.count() << " ms";
    clock_.advance(1ms);
    s.poll();
    EXPECT_EQ(of(s, 0).state, ProcessState::starting);
    EXPECT_EQ(of(s, 0).restarts, ++restarts);
    ASSERT_TRUE(drive(s, in_state(s, 0, ProcessState::up)));
    EXPECT_NE(of(s, 0).pid, before);
  }

  // Up for stable_after: healthy again, the back-off starts over.
  clock_.advance(10s);
  s.poll();
  ASSERT_EQ(::kill(of(s, 0).pid, SIGKILL), 0);
  ASSERT_TRUE(drive(s, in_state(s, 0, ProcessState::restarting)));
  clock_.advance(500ms);
  s.poll();
  EXPECT_EQ(of(s, 0).state, ProcessState::starting);
  EXPECT_EQ(of(s, 0).restarts, 5U);
  // Its log holds every run.
  const std::string log = read(of(s, 0).log);
  EXPECT_NE(log.find("gateway exited: exited (signal 9"), std::string::npos) << log;
}

TEST_F(SupervisorTest, AProcessThatKeepsCrashingIsGivenUpAndTheOthersRunOn) {
  auto o = options();
  o.max_failures = 3;
  const std::string once = path("once");
  Supervisor s({sh("plant", "echo ready; exec sleep 60"),
                sh("toshiba", "if [ -e " + once + " ]; then echo 'PLC refused' >&2; exit 3; fi; touch " +
                                  once + "; echo ready; exec sleep 60")},
               o, clock_);
  ASSERT_TRUE(s.begin());
  ASSERT_TRUE(drive(s, [&] { return s.all_up(); }));
  ASSERT_EQ(::kill(of(s, 1).pid, SIGKILL), 0);
  for (int round = 0; round < 10 && of(s, 1).state != ProcessState::failed; ++round) {
    ASSERT_TRUE(drive(s, [&] {
      const auto state = of(s, 1).state;
      return state == ProcessState::restarting || state == ProcessState::failed;
    }));
    clock_.advance(2s);
  }
  const auto toshiba = of(s, 1);
  EXPECT_EQ(toshiba.state, ProcessState::failed);
  EXPECT_EQ(toshiba.restarts, 2U);  // killed, then two restarts that exited at once
  EXPECT_EQ(toshiba.pid, -1);
  EXPECT_NE(toshiba.last_exit.find("exit code 3"), std::string::npos) << toshiba.last_exit;
  // Given up is final: no more restarts however long we wait.
  clock_.advance(60s);
  s.poll();
  EXPECT_EQ(of(s, 1).state, ProcessState::failed);
  EXPECT_EQ(of(s, 0).state, ProcessState::up);
  EXPECT_GT(of(s, 0).pid, 0);
}

TEST_F(SupervisorTest, StopEndsTheProcessesInReverseOrder) {
  const std::string order = path("order");
  std::vector<SupervisedProcess> processes;
  for (const char* name : {"plant", "conveyor1", "orders"}) {
    processes.push_back(sh(name, std::string("trap 'echo ") + name + " >> " + order +
                                     "; exit 0' TERM; echo ready; while :; do sleep 0.02; done"));
  }
  Supervisor s(std::move(processes), options(), clock_);
  ASSERT_TRUE(s.begin());
  ASSERT_TRUE(drive(s, [&] { return s.all_up(); }));
  std::vector<pid_t> pids;
  for (const auto& p : s.status()) {
    pids.push_back(p.pid);
  }
  s.stop();
  EXPECT_EQ(read(order), "orders\nconveyor1\nplant\n");
  for (std::size_t i = 0; i < pids.size(); ++i) {
    EXPECT_EQ(of(s, i).state, ProcessState::stopped);
    EXPECT_EQ(of(s, i).pid, -1);
    EXPECT_NE(of(s, i).last_exit.find("exit code 0"), std::string::npos) << of(s, i).last_exit;
    EXPECT_NE(::kill(pids[i], 0), 0) << "pid " << pids[i] << " is gone";
  }
  // Stopped is final: nothing restarts.
  clock_.advance(60s);
  s.poll();
  EXPECT_EQ(of(s, 0).pid, -1);
}

TEST_F(SupervisorTest, AProcessNeverReadyTimesOutWithItsNameAndLastLogLines) {
  Supervisor s(
      {sh("plant", "echo ready; exec sleep 60"),
       sh("scara-robot-1", "echo loading the layout; echo EtherCAT segment not found >&2; exec sleep 60"),
       sh("orders", "echo ready; exec sleep 60")},
      options(), clock_);
  ASSERT_TRUE(s.begin());
  // (The log's first line is the supervisor's note with the command, which holds the text too.)
  ASSERT_TRUE(
      drive(s, [&] { return read(of(s, 1).log).find("\nEtherCAT segment not found") != std::string::npos; }));
  clock_.advance(29s);
  s.poll();
  EXPECT_FALSE(s.start_error());
  clock_.advance(1s);
  s.poll();
  ASSERT_TRUE(s.start_error());
  const std::string message = s.start_error()->message;
  EXPECT_NE(message.find("scara-robot-1 was not ready within 30 s"), std::string::npos) << message;
  EXPECT_NE(message.find("loading the layout"), std::string::npos) << message;
  EXPECT_NE(message.find("EtherCAT segment not found"), std::string::npos) << message;
  EXPECT_EQ(of(s, 1).state, ProcessState::failed);
  EXPECT_EQ(of(s, 1).pid, -1);
  EXPECT_EQ(of(s, 2).state, ProcessState::stopped);  // never started
}

TEST_F(SupervisorTest, StartFailsAndStopsEverythingWhenAProcessExitsBeforeItIsReady) {
  auto o = options();
  o.tick = 5ms;
  SteadyClock clock;  // start() waits tick by tick on the clock
  Supervisor s({sh("plant", "echo ready; exec sleep 60"),
                sh("conveyor1", "echo 'conveyor1.yaml:3:9: modbus.port: expected a number' >&2; exit 2")},
               o, clock);
  auto st = s.start();
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().message.find("conveyor1 exited (exit code 2)"), std::string::npos)
      << st.error().message;
  EXPECT_NE(st.error().message.find("modbus.port: expected a number"), std::string::npos)
      << st.error().message;
  EXPECT_EQ(of(s, 0).state, ProcessState::stopped);
  EXPECT_EQ(of(s, 0).pid, -1);

  Supervisor missing({sh("plant", "echo ready; exec sleep 60"), {"x", {"/nonexistent/program"}, {}, {}}}, o,
                     clock);
  st = missing.start();
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().message.find("x could not be started"), std::string::npos) << st.error().message;
}

TEST_F(SupervisorTest, StartReturnsOnceAllAreUp) {
  auto o = options();
  o.tick = 5ms;
  SteadyClock clock;
  Supervisor s(
      {sh("plant", "echo ready; exec sleep 60"), sh("conveyor1", "sleep 0.1; echo ready; exec sleep 60")}, o,
      clock);
  ASSERT_TRUE(s.start());
  EXPECT_TRUE(s.all_up());
  bool cancelled = false;
  Supervisor never({sh("plant", "exec sleep 60")}, o, clock);
  auto st = never.start([&] { return cancelled = true; });
  ASSERT_FALSE(st);
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(st.error().code, Errc::state);
}

}  // namespace
}  // namespace sf::factory
