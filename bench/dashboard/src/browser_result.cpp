// What bench_dashboard reads from the browser (browser.mjs's result line) and how it pairs the
// page's samples with the gateway's (dashboard.hpp).
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/bench/dashboard.hpp"

namespace sf::bench {
namespace {

using nlohmann::json;

std::optional<double> optional_number(const json& j, const char* key) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number()) {
    return std::nullopt;
  }
  return it->get<double>();
}

PageLoad page_load(const json& j) {
  PageLoad load;
  load.path = j.value("path", "");
  for (const auto& r : j.value("requests", json::array())) {
    const auto bytes = r.value("bytes", std::uint64_t{0});
    const auto path = r.value("path", "");
    const auto type = r.value("type", "");
    ++load.requests;
    load.bytes += bytes;
    load.api_bytes += (type == "Fetch" || type == "XHR") ? bytes : 0;
    load.vendor_bytes += path.starts_with("/vendor/") ? bytes : 0;
    load.uplot_js_bytes += path == "/vendor/uPlot.esm.js" ? bytes : 0;
    if (const auto failed = r.value("failed", ""); !failed.empty()) {
      load.failed.push_back(fmt::format("{}: {}", path, failed));
    }
  }
  load.load_ms = optional_number(j, "load_ms");
  load.ws_open_ms = optional_number(j, "ws_open_ms");
  load.first_live_ms = optional_number(j, "first_live_ms");
  load.first_live_frame_ms = optional_number(j, "first_live_frame_ms");
  return load;
}

// ["<series id>", source ms, page ms]; nullopt when malformed.
std::optional<PageSample> page_sample(const json& j) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_string() || !j[1].is_number_integer() || !j[2].is_number()) {
    return std::nullopt;
  }
  try {
    return PageSample{std::stoll(j[0].get<std::string>()), j[1].get<std::int64_t>(), j[2].get<double>()};
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::vector<PageSample> page_samples(const json& list) {
  std::vector<PageSample> out;
  for (const auto& s : list) {
    if (auto sample = page_sample(s)) {
      out.push_back(*sample);
    }
  }
  return out;
}

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  return a / b - ((a % b != 0 && (a < 0) != (b < 0)) ? 1 : 0);
}

}  // namespace

std::optional<BrowserResult> parse_browser_result(std::string_view line) {
  const auto j = json::parse(line, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("result") || !j["result"].is_object()) {
    return std::nullopt;
  }
  const auto& r = j["result"];
  BrowserResult out;
  out.chromium = r.value("chromium", "");
  for (const auto& l : r.value("operator", json::array())) {
    out.operator_loads.push_back(page_load(l));
  }
  out.consumer = page_load(r.value("consumer", json::object()));
  out.samples = page_samples(r.value("samples", json::array()));
  out.client_samples = page_samples(r.value("client_samples", json::array()));
  if (const auto w = r.find("window_ms");
      w != r.end() && w->is_array() && w->size() == 2 && (*w)[0].is_number() && (*w)[1].is_number()) {
    out.window = {(*w)[0].get<double>(), (*w)[1].get<double>()};
  }
  out.clock_offset_ms = r.value("clock_offset_ms", 0.0);
  return out;
}

LatencyFigures latency_figures(const std::vector<GatewaySample>& gateway, const std::vector<PageSample>& page,
                               const std::vector<PageSample>& client, Window window) {
  // The live stream carries the source time in whole milliseconds (time_text): that and the
  // series name one sample (a series changes at most every sampling interval).
  std::map<std::pair<std::int64_t, std::int64_t>, const GatewaySample*> by_key;
  for (const auto& g : gateway) {
    by_key.emplace(std::make_pair(g.series, floor_div(g.source_us, 1000)), &g);
  }
  LatencyFigures f;
  auto gateway_of = [&](const PageSample& p) -> const GatewaySample* {
    const auto it = by_key.find({p.series, p.source_ms});
    if (it == by_key.end()) {
      ++f.unpaired;
      return nullptr;
    }
    return it->second;
  };
  // Receive − source time, with the gateway's exact source time where it has the sample.
  auto latencies = [&](const std::vector<PageSample>& samples, auto&& with_gateway) {
    std::vector<double> ms;
    for (const auto& p : samples) {
      const auto* g = gateway_of(p);
      ms.push_back(p.received_ms - (g != nullptr ? static_cast<double>(g->source_us) / 1000.0
                                                 : static_cast<double>(p.source_ms)));
      if (g != nullptr) {
        with_gateway(p, *g);
      }
    }
    return percentiles(std::move(ms));
  };
  std::vector<double> same_ms;
  std::vector<double> after_ms;
  f.page_ms = latencies(page, [&](const PageSample& p, const GatewaySample& g) {
    same_ms.push_back(static_cast<double>(g.received_us - g.source_us) / 1000.0);
    after_ms.push_back(p.received_ms - static_cast<double>(g.received_us) / 1000.0);
  });
  f.client_ms = latencies(client, [](const PageSample&, const GatewaySample&) {});
  // Every gateway sample of the page's window, whether the page had it or not.
  std::vector<double> all_ms;
  for (const auto& g : gateway) {
    const auto ms = static_cast<double>(g.source_us) / 1000.0;
    if (ms >= window.from_ms && ms <= window.to_ms) {
      all_ms.push_back(static_cast<double>(g.received_us - g.source_us) / 1000.0);
    }
  }
  f.gateway_same_ms = percentiles(std::move(same_ms));
  f.gateway_all_ms = percentiles(std::move(all_ms));
  f.page_after_gateway_ms = percentiles(std::move(after_ms));
  return f;
}

}  // namespace sf::bench
