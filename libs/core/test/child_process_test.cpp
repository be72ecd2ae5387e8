// The test helper that runs peers in other processes (dds_test_peer, node-opcua scripts):
// what it reads from a child's stdout is seen line by line, none dropped.
#include "sf/testing/child_process.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

namespace sf::testing {
namespace {

using namespace std::chrono_literals;

// One write of three lines: they arrive in one read.
bool spawn_printing(ChildProcess& child, const std::string& text) {
  return child.spawn({"sh", "-c", "printf '" + text + "'"}, ".", true);
}

TEST(ChildProcess, LinesAfterTheAcceptedOneWaitForTheNextCall) {
  ChildProcess child;
  ASSERT_TRUE(spawn_printing(child, "a\\nb\\nc\\n"));
  EXPECT_TRUE(child.wait_for_line([](const std::string& l) { return l == "a"; }, 20s));
  std::vector<std::string> rest;
  EXPECT_TRUE(child.wait_for_line(
      [&](const std::string& l) {
        rest.push_back(l);
        return l == "c";
      },
      20s));
  EXPECT_EQ(rest, (std::vector<std::string>{"b", "c"}));
  EXPECT_FALSE(child.wait_for_line([](const std::string&) { return true; }, 20s));  // stdout closed
  child.stop(false);
}

TEST(ChildProcess, ANewProcessStartsWithoutTheLastOnesUnreadLines) {
  ChildProcess child;
  ASSERT_TRUE(spawn_printing(child, "a\\nb\\n"));
  EXPECT_TRUE(child.wait_for_line([](const std::string& l) { return l == "a"; }, 20s));
  ASSERT_TRUE(spawn_printing(child, "c\\n"));
  std::string first;
  EXPECT_TRUE(child.wait_for_line(
      [&](const std::string& l) {
        first = l;
        return true;
      },
      20s));
  EXPECT_EQ(first, "c");
  child.stop(false);
}

}  // namespace
}  // namespace sf::testing
