#include <gtest/gtest.h>

#include "sf/historian/types.hpp"
#include "value_columns.hpp"

namespace sf::historian {
namespace {

TEST(SeriesId, IsStableAndSeparatesItsParts) {
  EXPECT_EQ(series_id("opc.tcp://a:4840", "ns=2;s=T"), series_id("opc.tcp://a:4840", "ns=2;s=T"));
  EXPECT_NE(series_id("ab", "c"), series_id("a", "bc"));
  EXPECT_GT(series_id("x", "y"), 0);
  // Pinned: ids are stored in databases, so the hash must never change.
  EXPECT_EQ(series_id("opc.tcp://cell1:4840", "ns=2;s=Temp"), 0x5427965b99d2d2f6);
}

TEST(Value, TypesNamesAndNumbers) {
  EXPECT_EQ(type_of(Value{}), DataType::empty);
  EXPECT_EQ(type_of(Value{std::uint64_t{1}}), DataType::uint64);
  EXPECT_EQ(to_string(DataType::float64), "float64");
  EXPECT_EQ(data_type_from_string("bytes"), DataType::bytes);
  EXPECT_EQ(data_type_from_string("float"), std::nullopt);
  EXPECT_EQ(numeric(Value{true}), 1.0);
  EXPECT_EQ(numeric(Value{std::int64_t{-3}}), -3.0);
  EXPECT_EQ(numeric(Value{std::string{"3"}}), std::nullopt);
  EXPECT_EQ(format_value(Value{Bytes{0x01, 0xff}}), "0x01ff");
  EXPECT_EQ(format_value(Value{std::string{"a"}}), "\"a\"");
  EXPECT_EQ(format_value(Value{2.5}), "2.5");
}

TEST(ValueColumns, RoundTripEveryType) {
  for (const Value& v : {Value{}, Value{true}, Value{std::int64_t{-7}}, Value{~std::uint64_t{0}}, Value{1.5},
                         Value{std::string{"s"}}, Value{Bytes{1, 2}}}) {
    auto back = detail::from_columns(detail::to_columns(v));
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(*back, v);
  }
  // uint64 shares the int64 column, bit for bit.
  EXPECT_EQ(detail::to_columns(Value{~std::uint64_t{0}}).v_int, -1);
}

TEST(ValueColumns, MissingColumnOrUnknownTypeIsMalformed) {
  EXPECT_EQ(detail::from_columns(detail::ValueColumns{2}).error().code, Errc::malformed);
  EXPECT_EQ(detail::from_columns(detail::ValueColumns{42}).error().code, Errc::malformed);
}

}  // namespace
}  // namespace sf::historian
