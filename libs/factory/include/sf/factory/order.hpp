// Orders: what a consumer asks of the candy-packing line (paper §VII: a box
// of a chosen type with chosen candy types and quantities), checked against
// the line's catalog before anything starts. The catalog is the one the
// ontology's individuals are derived from (`plant ontology`), so a box type's
// capacity and the candy types here are the ontology's sf:capacity and
// sf:CandyType individuals.
//
// An order becomes the product's operations (OrderAgent): upload a box of its
// type, load each candy line into consecutive slots (a line longer than a
// robot's visit is split into several loads, which may go to different
// robots), download and inspect.
//
// Order files (`smartfactory order --file`, the demo's stream):
//   orders:
//     - {id: alice-1, box: small-box, candy: {gummy: 4, toffee: 2}}
//     - {box: large-box, candy: {chocolate: 30}}      # id: order-<n> when missing
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/line/layout.hpp"

namespace sf::factory {

struct OrderLine {
  std::string candy;  // catalog candy type name
  int quantity = 0;
  friend bool operator==(const OrderLine&, const OrderLine&) = default;
};

struct Order {
  std::string id;
  std::string box_type;  // catalog box type name
  std::vector<OrderLine> lines;
  friend bool operator==(const Order&, const Order&) = default;
  // The quantity per candy type (lines of one type added up).
  [[nodiscard]] std::map<std::string, int> counts() const;
  [[nodiscard]] int total() const;
};

// Why the order cannot be made, naming the offending line ("line 2 (mint:4):
// unknown candy type 'mint' (known: ...)"): an unknown box or candy type, a
// quantity of zero or less, more candies than the box has slots, no lines.
Status validate(const Order& order, const line::Catalog& catalog);

// "gummy:4" as the CLI's --candy takes it.
Result<OrderLine> parse_order_line(std::string_view text);

// An order file (format above); every order validated, errors say file:line:column.
Result<std::vector<Order>> load_orders(const std::filesystem::path& file, const line::Catalog& catalog);
Result<std::vector<Order>> parse_orders(std::string_view yaml, const line::Catalog& catalog,
                                        std::string name = "<orders>");

// Orders as an order file holds them (what load_orders reads back).
std::string orders_yaml(const std::vector<Order>& orders);

// One load of a candy type into consecutive slots of the box.
struct LoadTask {
  std::size_t candy = 0;  // catalog index
  int count = 0;
  int first_slot = 0;  // 0-based, row by row
  friend bool operator==(const LoadTask&, const LoadTask&) = default;
};

// The loads of a valid order, slots filled in line order, each at most
// `max_per_load` candies.
std::vector<LoadTask> load_tasks(const Order& order, const line::Catalog& catalog, int max_per_load);

// A stream of random valid orders (the demo's consumers): a box type, then
// one to three candy lines filling up to the whole box. Same seed, same stream.
class OrderGenerator {
 public:
  OrderGenerator(const line::Catalog& catalog, std::uint64_t seed, std::string prefix = "order");
  Order next();

 private:
  const line::Catalog* catalog_;
  std::mt19937_64 rng_;
  std::string prefix_;
  std::uint64_t count_ = 0;
};

}  // namespace sf::factory
