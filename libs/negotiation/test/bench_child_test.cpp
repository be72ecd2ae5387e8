// The processes `cnp bench` starts: contractors and ddsperf pongs run under the scheduling policy
// asked for (SchedulingPolicy), and a child that will not exit by itself is stopped.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "bench_child.hpp"

namespace sf::negotiation::detail {
namespace {

using namespace std::chrono_literals;

std::string temp_output() {
  char name[] = "/tmp/sf-bench-child-XXXXXX";
  const int fd = ::mkstemp(name);
  ::close(fd);
  return name;
}

std::string read_all(const std::string& path) {
  std::ostringstream out;
  out << std::ifstream(path).rdbuf();
  return out.str();
}

// What `chrt -p` (util-linux) says of the child's own process.
std::string policy_seen_by_child(SchedulingPolicy policy) {
  const auto out = temp_output();
  auto child = BenchChild::spawn({"sh", "-c", "chrt -p $$"}, {}, out, policy);
  EXPECT_TRUE(static_cast<bool>(child)) << (child ? "" : child.error().describe());
  if (!child) {
    return {};
  }
  EXPECT_TRUE(child->wait(10s));
  auto text = read_all(out);
  std::remove(out.c_str());
  return text;
}

TEST(BenchChild, RunsUnderTheSchedulingPolicyAskedFor) {
  EXPECT_NE(policy_seen_by_child(SchedulingPolicy::batch).find("SCHED_BATCH"), std::string::npos);
  EXPECT_NE(policy_seen_by_child(SchedulingPolicy::normal).find("SCHED_OTHER"), std::string::npos);
}

TEST(BenchChild, PassesTheExtraEnvironmentAndReportsTheCpuTimeOfAnExitedChild) {
  const auto out = temp_output();
  auto child = BenchChild::spawn({"sh", "-c", "echo \"$SF_BENCH_CHILD_TEST\""},
                                 {"SF_BENCH_CHILD_TEST=forty-two"}, out);
  ASSERT_TRUE(static_cast<bool>(child));
  ASSERT_TRUE(child->wait(10s));
  EXPECT_EQ(read_all(out), "forty-two\n");
  EXPECT_EQ(child->pid(), 0);
  EXPECT_TRUE(child->cpu_at_exit().has_value());
  std::remove(out.c_str());
}

TEST(BenchChild, StopsAChildThatDoesNotExitByItself) {
  auto child = BenchChild::spawn({"sleep", "600"}, {}, "/dev/null");
  ASSERT_TRUE(static_cast<bool>(child));
  const pid_t pid = child->pid();
  ASSERT_GT(pid, 0);
  EXPECT_FALSE(child->wait(50ms));
  child->stop();
  EXPECT_EQ(child->pid(), 0);
  EXPECT_NE(::kill(pid, 0), 0);  // reaped: no such process
}

TEST(BenchChild, AProgramThatCannotBeStartedIsAnError) {
  auto child = BenchChild::spawn({"/nonexistent/sf-no-such-program"}, {}, "/dev/null");
  ASSERT_FALSE(static_cast<bool>(child));
  EXPECT_NE(child.error().describe().find("/nonexistent/sf-no-such-program"), std::string::npos);
}

}  // namespace
}  // namespace sf::negotiation::detail
