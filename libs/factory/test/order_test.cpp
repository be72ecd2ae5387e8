// Orders against the line's catalog: what is accepted, what is refused and
// how the refusal names the line; the loads an order becomes; the generated
// stream the demo's consumers send.
#include "sf/factory/order.hpp"

#include <gtest/gtest.h>

#include "sf/factory/order_host.hpp"

namespace sf::factory {
namespace {

const line::Catalog& catalog() {
  static const line::Layout layout = *line::default_layout();
  return layout.catalog;
}

std::string refusal(const Order& o) {
  auto s = validate(o, catalog());
  return s ? std::string() : s.error().message;
}

TEST(Order, AValidOrderIsAccepted) {
  EXPECT_EQ(refusal({"a", "small-box", {{"gummy", 4}, {"toffee", 8}}}), "");
  EXPECT_EQ(refusal({"a", "large-box", {{"chocolate", 30}}}), "");
}

TEST(Order, EveryKindOfBadOrderIsRefusedNamingItsLine) {
  EXPECT_NE(refusal({"a", "gift-12", {{"gummy", 1}}})
                .find("unknown box type 'gift-12' (known: small-box, large-box)"),
            std::string::npos);
  const auto unknown = refusal({"a", "small-box", {{"gummy", 1}, {"mint", 4}}});
  EXPECT_NE(unknown.find("line 2 (mint:4): unknown candy type 'mint'"), std::string::npos) << unknown;
  EXPECT_NE(
      refusal({"a", "small-box", {{"gummy", 0}}}).find("line 1 (gummy:0): the quantity must be at least 1"),
      std::string::npos);
  EXPECT_NE(refusal({"a", "small-box", {{"gummy", -3}}}).find("line 1 (gummy:-3)"), std::string::npos);
  const auto over = refusal({"a", "small-box", {{"gummy", 8}, {"toffee", 5}}});
  EXPECT_NE(over.find("line 2 (toffee:5): 13 candies in all, over the capacity of a small-box (12 slots)"),
            std::string::npos)
      << over;
  EXPECT_NE(refusal({"a", "small-box", {}}).find("no candy"), std::string::npos);
}

TEST(Order, CandyArgumentsParseOrSayWhy) {
  EXPECT_EQ(*parse_order_line("mint:4"), (OrderLine{"mint", 4}));
  EXPECT_EQ(*parse_order_line("gummy:-2"), (OrderLine{"gummy", -2}));  // validate() refuses it, naming it
  for (const char* bad : {"mint", "mint:", ":4", "mint:four", "mint:4x"}) {
    EXPECT_FALSE(parse_order_line(bad)) << bad;
  }
}

TEST(Order, FilesAreReadAndTheirErrorsSayWhere) {
  auto orders = parse_orders(
      "orders:\n"
      "  - {id: alice-1, box: small-box, candy: {gummy: 4, toffee: 2}}\n"
      "  - {box: large-box, candy: {chocolate: 30}}\n",
      catalog(), "orders.yaml");
  ASSERT_TRUE(orders) << orders.error().describe();
  ASSERT_EQ(orders->size(), 2U);
  EXPECT_EQ((*orders)[0], (Order{"alice-1", "small-box", {{"gummy", 4}, {"toffee", 2}}}));
  EXPECT_EQ((*orders)[1].id, "order-2");

  auto over = parse_orders("orders:\n  - {box: small-box, candy: {gummy: 13}}\n", catalog(), "orders.yaml");
  ASSERT_FALSE(over);
  EXPECT_NE(over.error().message.find("orders.yaml:2:"), std::string::npos) << over.error().message;
  EXPECT_NE(over.error().message.find("over the capacity"), std::string::npos);

  auto typo = parse_orders("orders:\n  - {box: small-box, candies: {gummy: 1}}\n", catalog(), "orders.yaml");
  ASSERT_FALSE(typo);
  EXPECT_NE(typo.error().message.find("candies"), std::string::npos) << typo.error().message;
  EXPECT_FALSE(parse_orders("orders: []\n", catalog()));
  EXPECT_FALSE(parse_orders("orders: [\n", catalog()));
  EXPECT_FALSE(parse_orders("orders:\n  - {box: small-box, candy: {gummy: many}}\n", catalog()));
}

TEST(Order, AGeneratedStreamWrittenAsAFileReadsBackTheSame) {
  OrderGenerator g(catalog(), 3);
  std::vector<Order> orders;
  orders.reserve(20);
  for (int i = 0; i < 20; ++i) {
    orders.push_back(g.next());
  }
  auto back = parse_orders(orders_yaml(orders), catalog());
  ASSERT_TRUE(back) << back.error().describe();
  EXPECT_EQ(*back, orders);
}

TEST(Order, LinesBecomeLoadsIntoConsecutiveSlotsSplitAtTheVisitSize) {
  const Order o{"a", "small-box", {{"gummy", 6}, {"toffee", 2}}};
  const auto gummy = *catalog().candy_index("gummy");
  const auto toffee = *catalog().candy_index("toffee");
  EXPECT_EQ(load_tasks(o, catalog(), 4),
            (std::vector<LoadTask>{{gummy, 4, 0}, {gummy, 2, 4}, {toffee, 2, 6}}));
  EXPECT_EQ(load_tasks(o, catalog(), 12).size(), 2U);
}

TEST(Order, TheGeneratedStreamIsValidAndRepeatsWithItsSeed) {
  OrderGenerator a(catalog(), 7);
  OrderGenerator b(catalog(), 7);
  OrderGenerator c(catalog(), 8);
  bool differs = false;
  for (int i = 0; i < 500; ++i) {
    const Order o = a.next();
    EXPECT_EQ(refusal(o), "") << o.id;
    EXPECT_EQ(o, b.next());
    differs = differs || !(o == c.next());
  }
  EXPECT_TRUE(differs);
}

TEST(OrderHost, TheSafeNumberOfBoxesIsOneLessThanTheShortestCycleOfBelts) {
  // uploader → conveyor1 → conveyor2 | conveyor3 → conveyor4 → conveyor5 → conveyor1: four belts.
  EXPECT_EQ(safe_wip(*line::default_layout()), 3U);
  line::Layout open = *line::default_layout();
  open.belts.back().next.clear();  // conveyor5 no longer returns boxes to conveyor1
  EXPECT_EQ(safe_wip(open), open.belts.size());
}

}  // namespace
}  // namespace sf::factory
