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

// A protocol's code survives the context added on the way up, typed (no text to parse back).
TEST(Error, ContextKeepsTheProtocolCode) {
  constexpr std::string_view kTable = "test codes";
  const Error e{Errc::not_found, "BadNodeIdUnknown: ns=1;s=x", ProtocolCode{kTable, 0x80340000U}};
  const Error outer = e.with_context("Read").with_context("server plc7");
  EXPECT_EQ(outer.message, "server plc7: Read: BadNodeIdUnknown: ns=1;s=x");
  ASSERT_TRUE(outer.protocol_code.has_value());
  EXPECT_EQ(*outer.protocol_code, (ProtocolCode{kTable, 0x80340000U}));
  EXPECT_FALSE(Error(Errc::io, "no code").with_context("x").protocol_code.has_value());
}

TEST(Result, MoveOnlyValue) {
  Result<std::unique_ptr<int>> r{std::make_unique<int>(5)};
  ASSERT_TRUE(r.ok());
  auto p = std::move(r).value();
  EXPECT_EQ(*p, 5);
}

}  // namespace
}  // namespace sf
