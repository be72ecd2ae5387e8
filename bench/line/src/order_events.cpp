// What the line benchmark reads: the order service's event lines, each order's times from them,
// and the orders it feeds the line.
#include <algorithm>
#include <fstream>
#include <map>
#include <random>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/bench/line.hpp"
#include "sf/bench/percentile.hpp"

namespace sf::bench {
namespace {

// The latest event of an order other than `order` among `seen` (in log order), if any.
const LoggedOrderEvent* latest_of_another(const std::vector<const LoggedOrderEvent*>& seen,
                                          const std::string& order) {
  const auto it = std::find_if(seen.rbegin(), seen.rend(), [&](const auto* e) { return e->order != order; });
  return it == seen.rend() ? nullptr : *it;
}

void first_award(OrderTimes& o, const LoggedOrderEvent& award, const LoggedOrderEvent* before) {
  o.first_award = award.t;
  if (before != nullptr && before->t > o.accepted) {
    o.started_at = before->t;
    o.started_by = before->what;
  }
}

}  // namespace

std::optional<LoggedOrderEvent> parse_order_event(std::string_view line) {
  const auto j = nlohmann::json::parse(line, nullptr, false);
  if (j.is_discarded() || !j.is_object() || j.value("event", "") != "order" || !j.contains("t") ||
      !j["t"].is_number() || !j.contains("order") || !j["order"].is_string() || !j.contains("what") ||
      !j["what"].is_string()) {
    return std::nullopt;
  }
  return LoggedOrderEvent{j["t"].get<double>(), j["order"].get<std::string>(), j["what"].get<std::string>(),
                          j.value("machine", ""), j.value("detail", "")};
}

std::vector<OrderTimes> order_times(const std::vector<LoggedOrderEvent>& events) {
  std::vector<OrderTimes> orders;
  std::map<std::string, std::size_t> index;
  std::vector<const LoggedOrderEvent*> seen;
  for (const auto& e : events) {
    const auto it = index.find(e.order);
    if (it == index.end()) {
      if (e.what == "accepted") {
        index.emplace(e.order, orders.size());
        orders.push_back({e.order, e.t, std::nullopt, std::nullopt, false, e.t, "accepted"});
      }
    } else {
      OrderTimes& o = orders[it->second];
      if (e.what == "awarded" && !o.first_award) {
        first_award(o, e, latest_of_another(seen, e.order));
      } else if (e.what == "done" || e.what == "failed") {
        o.done = e.t;
        o.failed = e.what == "failed";
      } else if (e.what == "remade") {  // the failure was one attempt's; the order goes on
        o.done.reset();
        o.failed = false;
      }
    }
    seen.push_back(&e);
  }
  return orders;
}

std::vector<factory::Order> small_orders(const line::Catalog& catalog, std::size_t count, std::uint64_t seed,
                                         const std::string& prefix) {
  if (catalog.box_types.empty() || catalog.candy_types.empty()) {
    return {};
  }
  const auto box = std::min_element(catalog.box_types.begin(), catalog.box_types.end(),
                                    [](const auto& a, const auto& b) { return a.capacity() < b.capacity(); });
  std::mt19937_64 rng(seed);
  std::vector<factory::Order> orders;
  for (std::size_t i = 1; i <= count; ++i) {
    // One type twice as often as two; distinct types, each once.
    const std::size_t kinds = std::min<std::size_t>(catalog.candy_types.size(), rng() % 3 == 2 ? 2 : 1);
    std::vector<std::size_t> types(catalog.candy_types.size());
    for (std::size_t t = 0; t < types.size(); ++t) {
      types[t] = t;
    }
    std::shuffle(types.begin(), types.end(), rng);
    factory::Order order{fmt::format("{}-{}", prefix, i), box->name, {}};
    for (std::size_t k = 0; k < kinds; ++k) {
      order.lines.push_back({catalog.candy_types[types[k]].name, 1});
    }
    orders.push_back(std::move(order));
  }
  return orders;
}

std::vector<std::string> FileLines::read_new() {
  std::ifstream in(path_, std::ios::binary);
  std::vector<std::string> lines;
  if (!in || !in.seekg(static_cast<std::streamoff>(offset_))) {
    return lines;
  }
  std::string chunk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  offset_ += chunk.size();
  partial_ += chunk;
  std::size_t begin = 0;
  for (auto end = partial_.find('\n'); end != std::string::npos; end = partial_.find('\n', begin)) {
    lines.push_back(partial_.substr(begin, end - begin));
    begin = end + 1;
  }
  partial_.erase(0, begin);
  return lines;
}

std::string_view to_string(Arrivals arrivals) {
  return arrivals == Arrivals::file ? "all in the order file at the start" : "one at a time";
}

Percentiles percentiles(std::vector<double> samples) {
  Percentiles p;
  p.samples = samples.size();
  std::sort(samples.begin(), samples.end());
  p.p50 = percentile_of_sorted(std::span<const double>(samples), 0.50);
  p.p99 = percentile_of_sorted(std::span<const double>(samples), 0.99);
  return p;
}

LineBenchResult summarize(const std::vector<OrderTimes>& orders) {
  LineBenchResult r;
  std::vector<double> award;
  std::vector<double> after_start;
  std::vector<double> lead;
  std::map<std::string, std::size_t> started_by;
  double first = orders.empty() ? 0 : orders.front().accepted;  // accepted in this order
  double last = 0;
  for (const auto& o : orders) {
    if (o.first_award) {
      award.push_back((*o.first_award - o.accepted) * 1e3);
      after_start.push_back((*o.first_award - o.started_at) * 1e3);
      ++started_by[o.started_by];
    }
    if (o.done) {
      last = std::max(last, *o.done);
      ++(o.failed ? r.failed : r.done);
      if (!o.failed) {
        lead.push_back(*o.done - o.accepted);
      }
    }
  }
  r.span_s = last > first ? last - first : 0;
  r.first_award_ms = percentiles(std::move(award));
  r.after_start_ms = percentiles(std::move(after_start));
  r.lead_time_s = percentiles(std::move(lead));
  r.started_by.assign(started_by.begin(), started_by.end());
  std::stable_sort(r.started_by.begin(), r.started_by.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return r;
}

}  // namespace sf::bench
