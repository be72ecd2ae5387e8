#include "sf/core/log.hpp"

#include <gtest/gtest.h>

namespace sf {
namespace {

TEST(Log, OneLoggerPerModule) {
  auto a = log::get("test-a");
  auto b = log::get("test-a");
  auto c = log::get("test-c");
  EXPECT_EQ(a.get(), b.get());
  EXPECT_NE(a.get(), c.get());
  EXPECT_EQ(a->name(), "test-a");
}

TEST(Log, SetLevelGlobalAndPerModule) {
  auto a = log::get("lvl-a");
  auto b = log::get("lvl-b");
  ASSERT_TRUE(log::set_level("warn,lvl-b=trace").ok());
  EXPECT_EQ(a->level(), spdlog::level::warn);
  EXPECT_EQ(b->level(), spdlog::level::trace);
  // Loggers created later take the global level.
  EXPECT_EQ(log::get("lvl-late")->level(), spdlog::level::warn);
  ASSERT_TRUE(log::set_level("info").ok());
}

TEST(Log, UnknownLevelIsAnError) {
  const auto st = log::set_level("loud");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("loud"), std::string::npos);
  EXPECT_FALSE(log::set_level("x=verbose").ok());
}

}  // namespace
}  // namespace sf
