#include "sf/line/inspection.hpp"

#include <gtest/gtest.h>

namespace sf::line {
namespace {

InspectionRecord sample() {
  return {"alice-1", 17,   "small-box", {{"gummy", 4}, {"toffee", 2}}, {{"gummy", 4}, {"toffee", 1}},
          18.0,      41.25};
}

TEST(Inspection, TheTextReadsBackAsTheRecord) {
  const auto r = sample();
  const std::string text = format_inspection(r);
  EXPECT_EQ(text,
            "alice-1 box=17 type=small-box ordered=gummy:4,toffee:2 counted=gummy:4,toffee:1 weight_g=18.0 "
            "lead_s=41.250");
  auto back = parse_inspection(text);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(*back, r);
  EXPECT_FALSE(back->matches());
}

TEST(Inspection, AnEmptyBoxHasNoCounts) {
  auto r = sample();
  r.counted.clear();
  auto back = parse_inspection(format_inspection(r));
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_TRUE(back->counted.empty());
}

TEST(Inspection, UnknownKeysAreIgnoredAndTheOrderOfKeysIsFree) {
  auto r = parse_inspection("o-2 colour=red ordered=mint:1 type=large-box box=3 counted=mint:1");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->box, 3U);
  EXPECT_EQ(r->box_type, "large-box");
  EXPECT_TRUE(r->matches());
}

TEST(Inspection, MalformedTextIsRefusedNamingWhatIsWrong) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "order id"},
      {"box=1 type=a ordered=x:1", "order id"},
      {"o box=1 type=a", "required"},
      {"o box=one type=a ordered=x:1", "box=one"},
      {"o box=1 type=a ordered=x", "ordered=x"},
      {"o box=1 type=a ordered=x:-1", "ordered=x:-1"},
      {"o box=1 type=a ordered=x:1,x:2", "twice"},
      {"o box=1 type=a ordered=:1", "ordered=:1"},
      {"o box=1 type=a ordered=x:1 weight_g=nan", "weight_g=nan"},
      {"o box=1 type=a ordered=x:1 lead_s=-2", "lead_s=-2"},
      {"o box=1 type=a ordered=x:1 junk", "junk"},
      {"o box=1 type= ordered=x:1", "required"},
  };
  for (const auto& [text, says] : cases) {
    auto r = parse_inspection(text);
    ASSERT_FALSE(r) << text;
    EXPECT_NE(r.error().message.find(says), std::string::npos) << text << ": " << r.error().message;
  }
}

TEST(OrderStep, ReadsBackWhatItWrites) {
  const OrderStep cases[] = {
      {"loaded", "scara-robot-1", "gummy:4 slots 0-3"},
      {"accepted", "", "small-box with 6 candies"},
      {"done", "", ""},
      {"awarded", "conveyor-3", ""},
  };
  for (const auto& step : cases) {
    const std::string text = format_order_step(step);
    auto back = parse_order_step(text);
    ASSERT_TRUE(back) << text << ": " << back.error().message;
    EXPECT_EQ(*back, step) << text;
  }
  EXPECT_EQ(format_order_step({"accepted", "", "small-box"}), "accepted - small-box");
}

TEST(OrderStep, MalformedTextIsRefused) {
  for (const char* text : {"", "accepted", " - x", "accepted  x"}) {
    auto r = parse_order_step(text);
    ASSERT_FALSE(r) << text;
    EXPECT_NE(r.error().message.find("order step"), std::string::npos) << r.error().message;
  }
}

}  // namespace
}  // namespace sf::line
