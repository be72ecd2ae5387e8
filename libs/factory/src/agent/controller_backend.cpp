#include <fmt/format.h>

#include <charconv>

#include "sf/core/log.hpp"
#include "sf/factory/contract_net.hpp"

namespace sf::factory {

Operation to_operation(const std::string& type, const std::vector<negotiation::Param>& params) {
  Operation op;
  op.type = type;
  for (const auto& p : params) {
    op.params[p.name] = p.value;
  }
  return op;
}

std::vector<negotiation::Param> to_params(const std::map<std::string, double>& results) {
  std::vector<negotiation::Param> out;
  for (const auto& [name, value] : results) {
    if (out.size() < negotiation::kMaxParams && !name.empty() && name.size() <= negotiation::kMaxName) {
      out.push_back({name, value});
    }
  }
  return out;
}

std::string job_id(const negotiation::Job& job) {
  return fmt::format("{}#{}", job.conversation, job.award_id);
}

std::optional<std::pair<std::string, std::uint32_t>> parse_job_id(const std::string& id) {
  const auto hash = id.rfind('#');
  if (hash == std::string::npos || hash == 0 || hash + 1 == id.size()) {
    return std::nullopt;
  }
  std::uint32_t award = 0;
  const char* first = id.data() + hash + 1;
  const char* last = id.data() + id.size();
  if (auto [end, ec] = std::from_chars(first, last, award); ec != std::errc{} || end != last) {
    return std::nullopt;
  }
  return std::pair{id.substr(0, hash), award};
}

ControllerBackend::ControllerBackend(MachineController& controller) : controller_(&controller) {
  controller_->on_job_end([this](const JobOutcome& outcome) {
    if (contractor_ == nullptr) {
      return;
    }
    const auto award = parse_job_id(outcome.job);
    if (!award) {
      return;  // not a job of the Contract Net (an operator's, a test's)
    }
    if (auto st = contractor_->report(award->first, award->second, outcome.ok, outcome.detail,
                                      to_params(outcome.results));
        !st) {
      log::get("factory")->warn("{}: {}", controller_->identification().name, st.error().message);
    }
  });
}

std::optional<negotiation::WorkEstimate> ControllerBackend::estimate(
    const std::string& operation, const std::vector<negotiation::Param>& params, std::string& why_not) {
  auto e = controller_->estimate(to_operation(operation, params), &why_not);
  if (!e) {
    return std::nullopt;
  }
  return negotiation::WorkEstimate{e->start_in, e->duration, e->queue_length};
}

Status ControllerBackend::start(const negotiation::Job& job, const std::vector<negotiation::Param>& params) {
  return controller_->submit(job_id(job), to_operation(job.operation, params));
}

void ControllerBackend::abort(const negotiation::Job& job, const std::string& why) {
  if (auto st = controller_->cancel(job_id(job)); !st) {
    log::get("factory")->info("{}: cancelling {} ({}): {}", controller_->identification().name, job_id(job),
                              why, st.error().message);
  }
}

std::vector<negotiation::Skill> ControllerBackend::skills() const {
  std::vector<negotiation::Skill> out;
  for (const auto& op : controller_->operations()) {
    out.push_back(negotiation::Skill{op, std::chrono::seconds{1}, 1.0});
  }
  return out;
}

}  // namespace sf::factory
