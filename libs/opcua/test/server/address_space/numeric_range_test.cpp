// NumericRange parsing and application (OPC 10000-4 §7.27).
#include <gtest/gtest.h>

#include "sf/opcua/server/services.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {
namespace {

TEST(NumericRangeTest, Parses) {
  auto empty = parse_numeric_range(String());
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
  auto r = parse_numeric_range(String("0:1,5,2:4"));
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->dimensions.size(), 3U);
  EXPECT_EQ(r->dimensions[0].low, 0U);
  EXPECT_EQ(r->dimensions[0].high, 1U);
  EXPECT_EQ(r->dimensions[1].low, 5U);
  EXPECT_EQ(r->dimensions[1].high, 5U);
  EXPECT_EQ(r->dimensions[2].high, 4U);
  for (const char* bad : {"-1", "1:", ":2", "2:2", "3:1", "1,,2", "a", "1 ", "99999999999"}) {
    auto result = parse_numeric_range(String(bad));
    ASSERT_FALSE(result.ok()) << bad;
    EXPECT_EQ(status_of(result.error()), status::BadIndexRangeInvalid) << bad;
  }
}

TEST(NumericRangeTest, AppliesToStringArraysPerElement) {
  Variant names(std::vector<String>{"alpha", "beta", "gamma"});
  auto r = apply_numeric_range(names, *parse_numeric_range(String("1:2,0:1")));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r->array_if<String>(), (Array<String>{"be", "ga"}));
  auto bytes = apply_numeric_range(Variant(ByteString{1, 2, 3, 4}), *parse_numeric_range(String("1:2")));
  ASSERT_TRUE(bytes.ok());
  EXPECT_EQ(*bytes->get_if<ByteString>(), (ByteString{2, 3}));
  auto none = apply_numeric_range(Variant(std::vector<std::int32_t>{}), *parse_numeric_range(String("0")));
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(status_of(none.error()), status::BadIndexRangeNoData);
}

TEST(NumericRangeTest, WritesKeepTheShape) {
  auto patched =
      write_numeric_range(Variant(std::vector<std::uint8_t>{1, 2, 3}), *parse_numeric_range(String("2")),
                          Variant(std::vector<std::uint8_t>{9}));
  ASSERT_TRUE(patched.ok());
  EXPECT_EQ(*patched->array_if<std::uint8_t>(), (Array<std::uint8_t>{1, 2, 9}));
  auto wrong = write_numeric_range(Variant("text"), *parse_numeric_range(String("0:1")), Variant("abc"));
  ASSERT_FALSE(wrong.ok());
  EXPECT_EQ(status_of(wrong.error()), status::BadTypeMismatch);
}

}  // namespace
}  // namespace sf::opcua::server
