// A line of several stages made from the prototype line: every check of a
// layout passes, the machines are multiplied, every candy can still be loaded.
#include "sf/line/staged_line.hpp"

#include <algorithm>
#include <set>

#include <gtest/gtest.h>

namespace sf::line {
namespace {

std::size_t smart(const Layout& l) {
  return static_cast<std::size_t>(
      std::count_if(l.robots.begin(), l.robots.end(), [](const RobotSpec& r) { return !r.legacy(); }));
}

TEST(StagedLine, TenStagesOfThePrototypeMultiplyItsCellsAndPassEveryCheck) {
  const Layout base = *default_layout();
  auto ten = staged_line(base, 10);
  ASSERT_TRUE(ten) << ten.error().describe();
  EXPECT_EQ(ten->robots.size(), 10 * base.robots.size());
  EXPECT_EQ(smart(*ten), 10 * smart(base));
  EXPECT_EQ(ten->dispensers.size(), 10 * base.dispensers.size());
  // The uploader's belt and the return belt once, the two cell belts and conveyor 4 per stage.
  EXPECT_EQ(ten->belts.size(), 2 + 10 * 3U);
  EXPECT_EQ(ten->downloader.station, "conveyor4-10/download");
  EXPECT_EQ(ten->uploader.station, base.uploader.station);
  EXPECT_EQ(ten->belt("conveyor4-3")->next, (std::vector<std::string>{"conveyor2-4", "conveyor3-4"}));
  EXPECT_EQ(ten->belt("conveyor4-10")->next, std::vector<std::string>{"conveyor5"});
  EXPECT_EQ(ten->belt("conveyor4")->stations.size(), 1U) << "the download station is on the last stage only";
  ASSERT_NE(ten->robot("denso-7"), nullptr);
  EXPECT_EQ(ten->robot("denso-7")->stations, std::vector<std::string>{"conveyor4-7/denso"});
  // Every candy has a robot with a dispenser of it in every stage.
  for (const auto& candy : ten->catalog.candy_types) {
    std::set<std::string> robots;
    for (const auto& r : ten->robots) {
      for (const auto& d : r.dispensers) {
        if (ten->dispenser(d)->candy == candy.name) {
          robots.insert(r.name);
        }
      }
    }
    EXPECT_GE(robots.size(), 10U) << candy.name;
  }
}

TEST(StagedLine, OneStageIsTheBaseLine) {
  const Layout base = *default_layout();
  auto one = staged_line(base, 1);
  ASSERT_TRUE(one) << one.error().describe();
  EXPECT_EQ(one->line, base.line);
  EXPECT_EQ(one->robots.size(), base.robots.size());
  ASSERT_EQ(one->belts.size(), base.belts.size());
  EXPECT_EQ(one->downloader.station, base.downloader.station);
  for (const auto& b : base.belts) {
    ASSERT_NE(one->belt(b.name), nullptr) << b.name;
    EXPECT_EQ(one->belt(b.name)->path, b.path) << b.name;
    EXPECT_EQ(one->belt(b.name)->next, b.next) << b.name;
  }
}

TEST(StagedLine, ALineOfAnotherShapeOrNoStagesIsRefused) {
  Layout base = *default_layout();
  EXPECT_FALSE(staged_line(base, 0));
  base.belts[1].next = {"conveyor5"};  // a cell belt that bypasses the downloader's belt
  auto bad = staged_line(base, 3);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().message.find("cell belt 'conveyor2' must feed the downloader's belt only"),
            std::string::npos)
      << bad.error().message;
}

}  // namespace
}  // namespace sf::line
