#include "sf/factory/order.hpp"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sf/core/config.hpp"

namespace sf::factory {

std::map<std::string, int> Order::counts() const {
  std::map<std::string, int> out;
  for (const auto& l : lines) {
    out[l.candy] += l.quantity;
  }
  return out;
}

int Order::total() const {
  int n = 0;
  for (const auto& l : lines) {
    n += l.quantity;
  }
  return n;
}

namespace {

template <typename T>
std::string known(const std::vector<T>& items) {
  std::vector<std::string> names;
  names.reserve(items.size());
  for (const auto& i : items) {
    names.push_back(i.name);
  }
  return fmt::format("{}", fmt::join(names, ", "));
}

}  // namespace

Status validate(const Order& order, const line::Catalog& catalog) {
  const line::BoxType* box = catalog.box(order.box_type);
  if (box == nullptr) {
    return make_error(Errc::invalid_argument, fmt::format("unknown box type '{}' (known: {})", order.box_type,
                                                          known(catalog.box_types)));
  }
  if (order.lines.empty()) {
    return make_error(Errc::invalid_argument,
                      "no candy: an order names at least one candy type and quantity");
  }
  int total = 0;
  for (std::size_t i = 0; i < order.lines.size(); ++i) {
    const OrderLine& l = order.lines[i];
    const std::string line = fmt::format("line {} ({}:{})", i + 1, l.candy, l.quantity);
    if (catalog.candy(l.candy) == nullptr) {
      return make_error(Errc::invalid_argument, fmt::format("{}: unknown candy type '{}' (known: {})", line,
                                                            l.candy, known(catalog.candy_types)));
    }
    if (l.quantity <= 0) {
      return make_error(Errc::invalid_argument, fmt::format("{}: the quantity must be at least 1", line));
    }
    total += l.quantity;
    if (total > box->capacity()) {
      return make_error(Errc::invalid_argument,
                        fmt::format("{}: {} candies in all, over the capacity of a {} ({} slots)", line,
                                    total, box->name, box->capacity()));
    }
  }
  return {};
}

Result<OrderLine> parse_order_line(std::string_view text) {
  const auto colon = text.rfind(':');
  if (colon == std::string_view::npos || colon == 0) {
    return make_error(Errc::invalid_argument,
                      fmt::format("'{}': expected CANDY:QUANTITY, e.g. gummy:4", text));
  }
  OrderLine l{std::string(text.substr(0, colon)), 0};
  const std::string_view n = text.substr(colon + 1);
  const auto [end, ec] = std::from_chars(n.data(), n.data() + n.size(), l.quantity);
  if (ec != std::errc{} || end != n.data() + n.size()) {
    return make_error(Errc::invalid_argument,
                      fmt::format("'{}': the quantity '{}' is not a whole number", text, n));
  }
  return l;
}

namespace {

Result<Order> parse_order(const config::Node& n, std::size_t index) {
  SF_TRY(n.only_keys({"id", "box", "candy"}));
  Order o;
  o.id = fmt::format("order-{}", index + 1);
  SF_TRY(n.read("id", o.id));
  auto box = n.get<std::string>("box");
  if (!box) {
    return box.error();
  }
  o.box_type = *box;
  auto candy = n.child("candy");
  if (!candy) {
    return candy.error();
  }
  auto keys = candy->keys();
  if (!keys) {
    return keys.error();
  }
  for (const auto& k : *keys) {
    auto q = candy->get<int>(k);
    if (!q) {
      return q.error();
    }
    o.lines.push_back({k, *q});
  }
  return o;
}

Result<std::vector<Order>> orders_from(const Result<config::Node>& root, const line::Catalog& catalog) {
  if (!root) {
    return root.error();
  }
  SF_TRY(root->only_keys({"orders"}));
  auto list = root->child("orders");
  if (!list) {
    return list.error();
  }
  auto items = list->items();
  if (!items) {
    return items.error();
  }
  std::vector<Order> out;
  for (std::size_t i = 0; i < items->size(); ++i) {
    const config::Node& n = (*items)[i];
    auto o = parse_order(n, i);
    if (!o) {
      return o.error();
    }
    if (auto valid = validate(*o, catalog); !valid) {
      return n.error(fmt::format("order '{}': {}", o->id, valid.error().message));
    }
    out.push_back(std::move(*o));
  }
  if (out.empty()) {
    return list->error("no orders");
  }
  return out;
}

}  // namespace

Result<std::vector<Order>> parse_orders(std::string_view yaml, const line::Catalog& catalog,
                                        std::string name) {
  return orders_from(config::load_string(yaml, std::move(name)), catalog);
}

Result<std::vector<Order>> load_orders(const std::filesystem::path& file, const line::Catalog& catalog) {
  return orders_from(config::load_file(file), catalog);
}

std::string orders_yaml(const std::vector<Order>& orders) {
  std::string out = "orders:\n";
  for (const auto& o : orders) {
    std::vector<std::string> candy;
    for (const auto& l : o.lines) {
      candy.push_back(fmt::format("{}: {}", l.candy, l.quantity));
    }
    out += fmt::format("  - {{id: {}, box: {}, candy: {{{}}}}}\n", o.id, o.box_type, fmt::join(candy, ", "));
  }
  return out;
}

std::vector<LoadTask> load_tasks(const Order& order, const line::Catalog& catalog, int max_per_load) {
  std::vector<LoadTask> out;
  int slot = 0;
  for (const auto& l : order.lines) {
    const std::size_t candy = *catalog.candy_index(l.candy);
    for (int left = l.quantity; left > 0;) {
      const int n = std::min(left, std::max(1, max_per_load));
      out.push_back({candy, n, slot});
      slot += n;
      left -= n;
    }
  }
  return out;
}

OrderGenerator::OrderGenerator(const line::Catalog& catalog, std::uint64_t seed, std::string prefix)
    : catalog_(&catalog), rng_(seed), prefix_(std::move(prefix)) {}

Order OrderGenerator::next() {
  auto pick = [this](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); };
  const line::BoxType& box = catalog_->box_types[pick(catalog_->box_types.size())];
  Order o{fmt::format("{}-{}", prefix_, ++count_), box.name, {}};
  std::vector<std::size_t> candies(catalog_->candy_types.size());
  for (std::size_t i = 0; i < candies.size(); ++i) {
    candies[i] = i;
  }
  std::shuffle(candies.begin(), candies.end(), rng_);
  const std::size_t kinds = 1 + pick(std::min<std::size_t>(3, candies.size()));
  int room = box.capacity();
  for (std::size_t k = 0; k < kinds && room > 0; ++k) {
    const int most = std::max(1, std::min(room, box.capacity() / static_cast<int>(kinds)));
    const int q = 1 + static_cast<int>(pick(static_cast<std::size_t>(most)));
    o.lines.push_back({catalog_->candy_types[candies[k]].name, q});
    room -= q;
  }
  return o;
}

}  // namespace sf::factory
