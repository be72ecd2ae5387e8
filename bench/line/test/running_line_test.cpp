// The ready line of `smartfactory line --json` as RunningLine reads it (the processes and their
// OPC UA endpoints bench_line and bench_dashboard connect to).
#include <gtest/gtest.h>

#include "sf/bench/running_line.hpp"

namespace sf::bench {
namespace {

TEST(LineReadyLine, ListsEveryProcessWithItsEndpoint) {
  const auto p = ready_processes(
      R"j({"event":"ready","line":"prototype","processes":[{"name":"plant","role":"plant","opcua":"","log":"/r/log/plant.log","pid":7},)j"
      R"j({"name":"scara-robot-1","role":"machine","opcua":"opc.tcp://127.0.0.1:4851","log":"/r/log/scara-robot-1.log"}]})j");
  ASSERT_TRUE(p.has_value());
  ASSERT_EQ(p->size(), 2U);
  EXPECT_EQ((*p)[0].name, "plant");
  EXPECT_EQ((*p)[0].opcua, "");
  EXPECT_EQ((*p)[1].name, "scara-robot-1");
  EXPECT_EQ((*p)[1].role, "machine");
  EXPECT_EQ((*p)[1].opcua, "opc.tcp://127.0.0.1:4851");
  EXPECT_EQ((*p)[1].log, "/r/log/scara-robot-1.log");
}

TEST(LineReadyLine, OtherLinesAreNotIt) {
  for (const char* other :
       {R"({"event":"status","processes":[]})", R"({"event":"ready","opcua":"opc.tcp://x:1"})",
        "line: 12 processes", R"({"event":"ready","processes":)"}) {
    EXPECT_FALSE(ready_processes(other).has_value()) << other;
  }
}

}  // namespace
}  // namespace sf::bench
