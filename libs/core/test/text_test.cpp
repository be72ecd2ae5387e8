#include "sf/core/text.hpp"

#include <gtest/gtest.h>

#include <string_view>
#include <vector>

namespace sf {
namespace {

using Parts = std::vector<std::string_view>;

TEST(Text, SplitKeepsEmptyFieldsAndGivesNoneForEmptyText) {
  EXPECT_EQ(split("a,,b", ','), (Parts{"a", "", "b"}));
  EXPECT_EQ(split("a,b,", ','), (Parts{"a", "b", ""}));
  EXPECT_EQ(split("$scrypt$x", '$'), (Parts{"", "scrypt", "x"}));
  EXPECT_EQ(split("one", ','), (Parts{"one"}));
  EXPECT_TRUE(split("", ',').empty());
}

TEST(Text, LowerChangesAsciiLettersOnly) {
  EXPECT_EQ(lower("Basic256Sha256:SignAndEncrypt"), "basic256sha256:signandencrypt");
  EXPECT_EQ(lower("AB-12_Z\xc3\x84"), "ab-12_z\xc3\x84");  // UTF-8 bytes stay as they are
}

TEST(Text, HexValueOfDigitsOnly) {
  EXPECT_EQ(hex_value('0'), 0);
  EXPECT_EQ(hex_value('9'), 9);
  EXPECT_EQ(hex_value('a'), 10);
  EXPECT_EQ(hex_value('F'), 15);
  EXPECT_EQ(hex_value('g'), -1);
  EXPECT_EQ(hex_value('/'), -1);
  EXPECT_EQ(hex_value(':'), -1);
}

TEST(Text, TrimTakesWhiteSpaceFromBothEnds) {
  EXPECT_EQ(trim(" \tx y\t "), "x y");
  EXPECT_EQ(trim("\r\n<a/>\n"), "<a/>");
  EXPECT_EQ(trim("   "), "");
  EXPECT_EQ(trim(""), "");
}

}  // namespace
}  // namespace sf
