#include "target.hpp"

#include <gtest/gtest.h>

namespace sf::web {
namespace {

TEST(Target, SplitsPathAndDecodedQuery) {
  auto target = parse_target("/api/series?name=axis%201&from=10&to=+20&flag");
  ASSERT_TRUE(target);
  EXPECT_EQ(target->path, "/api/series");
  EXPECT_EQ(target->query.at("name"), "axis 1");
  EXPECT_EQ(target->query.at("to"), " 20");
  EXPECT_EQ(target->query.at("flag"), "");
}

TEST(Target, DecodesPercentEscapesInThePath) {
  auto target = parse_target("/a%20b/%2e%2e/c");
  ASSERT_TRUE(target);
  EXPECT_EQ(target->path, "/a b/../c");  // decoded once; the static files refuse the '..'
}

TEST(Target, RefusesWhatIsNotAnOriginFormPath) {
  for (const char* bad :
       {"", "*", "http://other/", "/a%2fb", "/a%2Fb", "/a%00b", "/a%5cb", "/a%zz", "/a%4", "/a?x=%g1"}) {
    EXPECT_FALSE(parse_target(bad)) << bad;
  }
}

}  // namespace
}  // namespace sf::web
