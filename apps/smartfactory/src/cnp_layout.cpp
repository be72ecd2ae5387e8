// `smartfactory cnp layout`: every agent of both domains with its readers and writers, as DDS
// discovery sees them.
#include "agent_common.hpp"

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sf/core/clock.hpp"
#include "sf/dds/config.hpp"
#include "sf/dds/introspection.hpp"

namespace sf::app::agents {
namespace {

struct LayoutCliOptions {
  DdsCliOptions dds;
  unsigned settle_ms = 1500;
};

int run_layout(const LayoutCliOptions& o) {
  const auto settings = dds_settings(o.dds);
  auto xml = dds::cyclone_config_xml(settings.network);
  if (!xml) {
    std::cerr << "cnp layout: " << xml.error().describe() << "\n";
    return kExitUsage;
  }
  json out = json::array();
  for (const auto domain : {settings.machining_domain, settings.conveying_domain}) {
    auto observer = dds::Participant::create(domain, {*xml, "observer", settings.partition});
    if (!observer) {
      std::cerr << "cnp layout: " << observer.error().describe() << "\n";
      return kExitFailure;
    }
    auto seen = dds::discover(*observer, SteadyClock::instance(), std::chrono::milliseconds{o.settle_ms},
                              settings.partition);
    if (!seen) {
      std::cerr << "cnp layout: " << seen.error().describe() << "\n";
      return kExitFailure;
    }
    for (const auto& layout : *seen) {
      out.push_back(json::parse(dds::to_json(layout)));
    }
  }
  if (o.dds.json) {
    std::cout << out.dump() << "\n";
    return kExitOk;
  }
  for (const auto& p : out) {
    std::vector<std::string> readers;
    std::vector<std::string> writers;
    for (const auto& r : p["readers"]) {
      readers.push_back(r["topic"].get<std::string>());
    }
    for (const auto& w : p["writers"]) {
      writers.push_back(w["topic"].get<std::string>());
    }
    say(fmt::format("{} (domain {}): readers [{}] writers [{}]", p["participant"].get<std::string>(),
                    p["domain"].get<unsigned>(), fmt::join(readers, " "), fmt::join(writers, " ")));
  }
  return kExitOk;
}

}  // namespace

void register_layout(CLI::App& group, CommandResult& result) {
  auto l = std::make_shared<LayoutCliOptions>();
  auto* layout = group.add_subcommand(
      "layout",
      "List every agent in both domains with its DDS readers and writers, as discovered through the "
      "built-in topics (DCPSParticipant, DCPSPublication, DCPSSubscription)");
  layout->add_option("--settle-ms", l->settle_ms, "How long to listen for discovery before printing")
      ->capture_default_str();
  add_dds_options(*layout, l->dds);
  layout->callback([l, &result] { result.exit_code = run_layout(*l); });
}

}  // namespace sf::app::agents
