#include "sf/core/result.hpp"

#include <gtest/gtest.h>

namespace sf {
namespace {

Result<int> parse_positive(int v) {
  if (v <= 0) {
    return Error{Errc::invalid_argument, "not positive"};
  }
  return v;
}

Status chain(int v) {
  SF_TRY(parse_positive(v));
  return {};
}

TEST(Result, HoldsValueOrError) {
  auto good = parse_positive(3);
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(*good, 3);
  auto bad = parse_positive(-1);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::invalid_argument);
  EXPECT_EQ(bad.value_or(7), 7);
}

TEST(Result, TryPropagatesError) {
  EXPECT_TRUE(chain(1).ok());
  const auto st = chain(0);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "not positive");
}

TEST(Error, DescribeAndContext) {
  const Error e{Errc::malformed, "length 300 exceeds frame"};
  EXPECT_EQ(e.describe(), "malformed: length 300 exceeds frame");
  EXPECT_EQ(e.with_context("frame 7").describe(), "malformed: frame 7: length 300 exceeds frame");
}

TEST(Result, MoveOnlyValue) {
  Result<std::unique_ptr<int>> r{std::make_unique<int>(5)};
  ASSERT_TRUE(r.ok());
  auto p = std::move(r).value();
  EXPECT_EQ(*p, 5);
}

}  // namespace
}  // namespace sf
