#include "live_protocol.hpp"

#include <gtest/gtest.h>

namespace sf::web {
namespace {

TEST(LiveProtocol, SubscribeAndUnsubscribe) {
  auto subscribe = parse_live_request(R"({"subscribe": ["machine/M1", "alarms"]})");
  ASSERT_TRUE(subscribe);
  EXPECT_EQ(subscribe->kind, LiveRequest::Kind::subscribe);
  EXPECT_EQ(subscribe->topics, (std::vector<std::string>{"machine/M1", "alarms"}));
  auto unsubscribe = parse_live_request(R"({"unsubscribe": []})");
  ASSERT_TRUE(unsubscribe);
  EXPECT_EQ(unsubscribe->kind, LiveRequest::Kind::unsubscribe);
  EXPECT_TRUE(unsubscribe->topics.empty());
}

TEST(LiveProtocol, RefusesEverythingElseWithAReason) {
  for (const char* bad :
       {"", "not json", "[]", "\"subscribe\"", R"({"subscribe": "a"})", R"({"subscribe": [1]})",
        R"({"subscribe": [""]})", R"({"subscribe": ["a"], "extra": 1})",
        R"({"subscribe": [], "unsubscribe": []})", R"({"publish": ["a"]})"}) {
    auto request = parse_live_request(bad);
    ASSERT_FALSE(request) << bad;
    EXPECT_FALSE(request.error().message.empty());
  }
}

}  // namespace
}  // namespace sf::web
