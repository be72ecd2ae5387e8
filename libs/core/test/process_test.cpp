// sf::Process: starting programs with their stdio, scheduling policy, parent-death signal and
// process group as asked; reading their output line by line; waiting, terminating and reaping.
#include "sf/core/process.hpp"

#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/testing/temp_dir.hpp"

namespace sf {
namespace {

using namespace std::chrono_literals;

ProcessOptions shell(const std::string& script) {
  ProcessOptions o;
  o.argv = {"sh", "-c", script};
  o.out = Stdio::pipe();
  return o;
}

Process start(ProcessOptions o) {
  auto p = Process::spawn(std::move(o));
  EXPECT_TRUE(p.ok()) << (p ? "" : p.error().describe());
  return p ? std::move(*p) : Process{};
}

std::string read_file(const std::filesystem::path& path) {
  std::ostringstream out;
  out << std::ifstream(path).rdbuf();
  return out.str();
}

bool accept_all(const std::string&) {
  return true;
}

// One write of three lines: they arrive in one read.
TEST(Process, LinesAfterTheAcceptedOneWaitForTheNextCall) {
  auto child = start(shell("printf 'a\\nb\\nc\\n'"));
  EXPECT_TRUE(child.wait_for_line([](const std::string& l) { return l == "a"; }, 20s));
  std::vector<std::string> rest;
  EXPECT_TRUE(child.wait_for_line(
      [&](const std::string& l) {
        rest.push_back(l);
        return l == "c";
      },
      20s));
  EXPECT_EQ(rest, (std::vector<std::string>{"b", "c"}));
  const auto after = child.wait_for_line(accept_all, 20s);  // stdout closed
  ASSERT_FALSE(after.ok());
  EXPECT_EQ(after.error().code, Errc::state);
}

TEST(Process, ANewProcessStartsWithoutTheLastOnesUnreadLines) {
  auto child = start(shell("printf 'a\\nb\\n'"));
  EXPECT_TRUE(child.wait_for_line([](const std::string& l) { return l == "a"; }, 20s));
  child = start(shell("printf 'c\\n'"));
  const auto first = child.wait_for_line(accept_all, 20s);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(*first, "c");
}

TEST(Process, ALastLineWithoutNewlineIsStillALine) {
  auto child = start(shell("printf 'x\\ny'"));
  EXPECT_EQ(child.read_line(20s).value_or("?"), "x");
  EXPECT_EQ(child.read_line(20s).value_or("?"), "y");
  EXPECT_FALSE(child.read_line(20s).ok());
}

TEST(Process, NoLineInTimeIsATimeoutAndTheLineStillComesLater) {
  auto o = shell("read go; echo late");
  o.in = Stdio::pipe();
  auto child = start(o);
  const auto early = child.read_line(50ms);  // the child waits for its stdin
  ASSERT_FALSE(early.ok());
  EXPECT_EQ(early.error().code, Errc::timeout);
  ASSERT_TRUE(child.write_stdin("go\n").ok());
  EXPECT_EQ(child.read_line(20s).value_or("?"), "late");
}

TEST(Process, RunsUnderTheSchedulingPolicyAskedFor) {
  for (const auto& [policy, name] :
       {std::pair{SchedulingPolicy::batch, "SCHED_BATCH"}, std::pair{SchedulingPolicy::idle, "SCHED_IDLE"},
        std::pair{SchedulingPolicy::normal, "SCHED_OTHER"}}) {
    auto o = shell("chrt -p $$");
    o.scheduling = policy;
    const auto done = Process::run(o, 20s);
    ASSERT_TRUE(done.ok()) << done.error().describe();
    EXPECT_NE(done->out.find(name), std::string::npos) << to_string(policy) << ": " << done->out;
  }
}

TEST(Process, PassesTheExtraEnvironmentAndReportsTheCpuTimeAndMemoryOfAnExitedChild) {
  auto o = shell("echo \"$SF_PROCESS_TEST\"; i=0; while [ $i -lt 100000 ]; do i=$((i+1)); done");
  o.env = {"SF_PROCESS_TEST=forty-two"};
  auto child = start(o);
  EXPECT_EQ(child.read_line(20s).value_or("?"), "forty-two");
  const auto status = child.wait(60s);
  ASSERT_TRUE(status.ok());
  EXPECT_TRUE(status->success());
  EXPECT_GT(status->cpu_time.count(), 0);
  EXPECT_GT(status->max_rss_kib, 0);
  EXPECT_EQ(child.pid(), -1);
  EXPECT_FALSE(child.running());
}

TEST(Process, TheExtraEnvironmentReplacesAVariableOfTheSameName) {
  auto o = shell("echo \"$PATH\"");
  o.env = {"PATH=/bin:/usr/bin:/sf-test"};
  const auto done = Process::run(o, 20s);
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done->out, "/bin:/usr/bin:/sf-test\n");
}

TEST(Process, RunGathersStdoutWithStderrInTheWorkingDirectoryAskedFor) {
  testing::TempDir dir;
  auto o = shell("pwd; echo oops >&2; exit 3");
  o.cwd = dir.path();
  o.err = Stdio::to_stdout();
  const auto done = Process::run(o, 20s);
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done->out, dir.path().string() + "\noops\n");
  EXPECT_EQ(done->status.code, 3);
  EXPECT_FALSE(done->status.success());
  EXPECT_EQ(done->status.describe(), "exit code 3");
}

TEST(Process, RunKeepsStderrApartWhenItIsAPipe) {
  auto o = shell("echo out; echo err >&2");
  o.err = Stdio::pipe();
  const auto done = Process::run(o, 20s);
  ASSERT_TRUE(done.ok());
  EXPECT_EQ(done->out, "out\n");
  EXPECT_EQ(done->err, "err\n");
}

TEST(Process, OutputGoesToFilesAndStderrCanBeReadApart) {
  testing::TempDir dir;
  auto o = shell("echo out; echo err >&2");
  o.out = Stdio::file(dir.path() / "out.log");
  o.err = Stdio::pipe();
  auto child = start(o);
  EXPECT_EQ(child.read_line(20s, Stream::err).value_or("?"), "err");
  ASSERT_TRUE(child.wait(20s).ok());
  EXPECT_EQ(read_file(dir.path() / "out.log"), "out\n");
  auto again = shell("echo more");
  again.out = Stdio::file(dir.path() / "out.log", true);
  ASSERT_TRUE(Process::run(again, 20s).ok());
  EXPECT_EQ(read_file(dir.path() / "out.log"), "out\nmore\n");
}

TEST(Process, StdinOnAPipe) {
  ProcessOptions o;
  o.argv = {"cat"};
  o.in = Stdio::pipe();
  o.out = Stdio::pipe();
  auto child = start(o);
  ASSERT_TRUE(child.write_stdin("hello\n").ok());
  EXPECT_EQ(child.read_line(20s).value_or("?"), "hello");
  EXPECT_TRUE(child.close_and_wait(20s).success());  // cat ends on EOF: no SIGKILL
}

TEST(Process, WritingToAChildThatIsGoneIsAnErrorNotASignal) {
  ProcessOptions o;
  o.argv = {"true"};
  o.in = Stdio::pipe();
  auto child = start(o);
  ASSERT_TRUE(child.wait(20s).ok());
  const auto st = child.write_stdin("nobody reads this\n");
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::io);
}

TEST(Process, WaitTimesOutOnAChildThatRunsAndTerminateStopsIt) {
  ProcessOptions o;
  o.argv = {"sleep", "600"};
  auto child = start(o);
  const pid_t pid = child.pid();
  ASSERT_GT(pid, 0);
  EXPECT_TRUE(child.running());
  const auto early = child.wait(50ms);
  ASSERT_FALSE(early.ok());
  EXPECT_EQ(early.error().code, Errc::timeout);
  const auto status = child.terminate(10s);
  EXPECT_EQ(status.signal, SIGTERM);
  EXPECT_EQ(status.shell_code(), 128 + SIGTERM);
  EXPECT_EQ(child.pid(), -1);
  EXPECT_NE(::kill(pid, 0), 0);  // reaped: no such process
  EXPECT_EQ(child.exit_status()->signal, SIGTERM);
}

TEST(Process, TerminateKillsAChildThatIgnoresSigterm) {
  auto child = start(shell("trap '' TERM; echo ready; exec sleep 600"));
  ASSERT_TRUE(child.wait_for_line([](const std::string& l) { return l == "ready"; }, 20s));
  const auto status = child.terminate(200ms);
  EXPECT_EQ(status.signal, SIGKILL);
  EXPECT_EQ(status.describe(), "signal 9 (Killed)");
}

TEST(Process, ATerminatedStoppedChildStillGoes) {
  ProcessOptions o;
  o.argv = {"sleep", "600"};
  auto child = start(o);
  ASSERT_TRUE(child.signal(SIGSTOP).ok());
  EXPECT_EQ(child.terminate(10s).signal, SIGTERM);
}

TEST(Process, RunKillsAChildThatDoesNotFinishInTime) {
  ProcessOptions o;
  o.argv = {"sleep", "600"};
  const auto done = Process::run(o, 100ms);
  ASSERT_FALSE(done.ok());
  EXPECT_EQ(done.error().code, Errc::timeout);
}

// PR_SET_PDEATHSIG fires when the thread that spawned the child ends.
TEST(Process, TheParentDeathSignalComesWhenTheSpawningThreadEnds) {
  Process child;
  std::thread([&] {
    ProcessOptions o;
    o.argv = {"sleep", "600"};
    o.parent_death_signal = SIGKILL;
    child = start(o);
  }).join();
  const auto status = child.wait(20s);
  ASSERT_TRUE(status.ok());
  EXPECT_EQ(status->signal, SIGKILL);
}

// With its own process group, terminate() reaches what the child started.
TEST(Process, TerminateReachesTheWholeProcessGroup) {
  auto o = shell("sleep 600 & echo $!; wait");
  o.own_process_group = true;
  auto child = start(o);
  const auto line = child.read_line(20s);
  ASSERT_TRUE(line.ok());
  const pid_t grandchild = std::stoi(*line);
  child.terminate(10s);
  // The grandchild is not ours to reap: gone, or a zombie until init reaps it.
  const auto gone = [&] {
    std::ifstream stat("/proc/" + std::to_string(grandchild) + "/stat");
    std::string text;
    std::getline(stat, text);
    return text.empty() || text.find(") Z ") != std::string::npos;
  };
  const auto end = SteadyClock::instance().now() + 20s;
  while (!gone() && SteadyClock::instance().now() < end) {
    std::this_thread::sleep_for(10ms);
  }
  EXPECT_TRUE(gone());
}

TEST(Process, AProgramThatCannotBeStartedIsAnErrorThatNamesIt) {
  ProcessOptions o;
  o.argv = {"/nonexistent/sf-no-such-program"};
  auto child = Process::spawn(o);
  ASSERT_FALSE(child.ok());
  EXPECT_EQ(child.error().code, Errc::io);
  EXPECT_NE(child.error().message.find("/nonexistent/sf-no-such-program"), std::string::npos);
  EXPECT_NE(child.error().message.find("execve"), std::string::npos);

  o.argv = {"sf-no-such-program-on-path"};
  ASSERT_FALSE(Process::spawn(o).ok());
  o.argv = {"sh", "-c", "true"};
  o.cwd = "/nonexistent/sf-no-such-dir";
  const auto in_missing_dir = Process::spawn(o);
  ASSERT_FALSE(in_missing_dir.ok());
  EXPECT_NE(in_missing_dir.error().message.find("chdir"), std::string::npos);
  EXPECT_FALSE(Process::spawn(ProcessOptions{}).ok());
}

TEST(Process, ReadingAStreamThatIsNotAPipeIsAnError) {
  ProcessOptions o;
  o.argv = {"true"};
  o.out = Stdio::null();
  auto child = start(o);
  const auto line = child.read_line(1s);
  ASSERT_FALSE(line.ok());
  EXPECT_EQ(line.error().code, Errc::state);
}

TEST(Process, FindsProgramsOnThePath) {
  const auto sh = find_program("sh");
  ASSERT_TRUE(sh.has_value());
  EXPECT_TRUE(std::filesystem::exists(*sh));
  EXPECT_FALSE(find_program("sf-no-such-program-on-path").has_value());
  EXPECT_EQ(find_program("./relative").value_or(""), "./relative");
  EXPECT_FALSE(find_program("").has_value());
}

TEST(Process, SchedulingPolicyNamesRoundTrip) {
  for (auto p : {SchedulingPolicy::inherit, SchedulingPolicy::normal, SchedulingPolicy::batch,
                 SchedulingPolicy::idle}) {
    EXPECT_EQ(scheduling_policy_from_string(to_string(p)), p);
  }
  EXPECT_FALSE(scheduling_policy_from_string("fifo").has_value());
}

}  // namespace
}  // namespace sf
