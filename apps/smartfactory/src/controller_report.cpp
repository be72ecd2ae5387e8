#include "controller_report.hpp"

#include <fmt/format.h>

namespace sf::app {

nlohmann::json controller_status_json(const std::string& machine, const factory::ControllerStatus& s,
                                      const negotiation::ContractorStats& n) {
  nlohmann::json j{{"event", "status"},
                   {"machine", machine},
                   {"state", factory::to_string(s.packml.state)},
                   {"mode", factory::to_string(s.packml.mode)},
                   {"fault", s.fault},
                   {"job", s.job.value_or("")},
                   {"queued", s.queued},
                   {"produced", s.packml.produced},
                   {"defective", s.packml.defective},
                   {"bids", n.bids},
                   {"declines", n.declines},
                   {"done", n.done},
                   {"failures", n.failures}};
  if (s.packml.stop_reason) {
    j["stop_reason"] = {{"id", s.packml.stop_reason->id}, {"message", s.packml.stop_reason->message}};
  }
  return j;
}

std::string controller_status_text(const std::string& machine, const factory::ControllerStatus& s,
                                   const negotiation::ContractorStats& n) {
  const std::string job =
      s.job ? fmt::format("{} ({})", *s.job, s.operation ? s.operation->type : "?") : std::string("-");
  return fmt::format("{}: {}, job {}, queue {}; {} bids, {} done, {} failed", machine,
                     factory::to_string(s.packml.state), job, s.queued, n.bids, n.done, n.failures);
}

}  // namespace sf::app
