#include "sf/negotiation/contractor.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "support.hpp"

namespace sf::negotiation {
namespace {

using detail::Overloaded;

std::chrono::nanoseconds scaled(std::chrono::nanoseconds d, double speed) {
  return std::chrono::nanoseconds{static_cast<std::int64_t>(static_cast<double>(d.count()) / speed)};
}

}  // namespace

Result<Contractor> Contractor::create(ContractorTransport& transport, const Clock& clock,
                                      ContractorConfig config, ContractorEvents events) {
  SF_TRY(validate_name("contractor", config.name));
  if (config.skills.empty()) {
    return Error{Errc::invalid_argument, fmt::format("contractor {} supports no operation", config.name)};
  }
  for (const auto& s : config.skills) {
    SF_TRY(validate_operation(s.operation));
    if (s.duration.count() < 0) {
      return Error{Errc::invalid_argument, fmt::format("negative duration for {}", s.operation)};
    }
  }
  if (!(config.speed > 0.0) || config.capacity == 0) {
    return Error{Errc::invalid_argument, "speed must be > 0 and capacity >= 1"};
  }
  return Contractor{transport, clock, std::move(config), std::move(events)};
}

Contractor::Contractor(ContractorTransport& transport, const Clock& clock, ContractorConfig config,
                       ContractorEvents events)
    : transport_(&transport),
      clock_(&clock),
      config_(std::move(config)),
      events_(std::move(events)),
      rng_(config_.seed),
      log_(log::get("negotiation")) {}

const Skill* Contractor::skill(const std::string& operation) const {
  const auto it = std::find_if(config_.skills.begin(), config_.skills.end(),
                               [&](const Skill& s) { return s.operation == operation; });
  return it == config_.skills.end() ? nullptr : &*it;
}

Clock::time_point Contractor::free_at() const {
  const auto now = clock_->now();
  if (jobs_.empty()) {
    return now;
  }
  auto t = jobs_.front().started_at.value_or(now);
  for (const auto& j : jobs_) {
    t += j.duration;
  }
  return std::max(now, t);
}

std::chrono::nanoseconds Contractor::work_time(const Skill& s) {
  auto d = scaled(s.duration, config_.speed);
  if (config_.jitter.count() > 0) {
    std::uniform_int_distribution<std::int64_t> extra{0, config_.jitter.count()};
    d += std::chrono::nanoseconds{extra(rng_)};
  }
  return d;
}

UtcTime Contractor::to_utc(Clock::time_point t) const {
  return clock_->utc_now() + std::chrono::duration_cast<UtcTime::duration>(t - clock_->now());
}

void Contractor::on_announce(const Announce& a) {
  const Skill* s = skill(a.operation);
  if (s == nullptr) {
    ignore(fmt::format("ANNOUNCE {}", a.conversation), fmt::format("unknown operation type {}", a.operation));
    return;
  }
  if (clock_->utc_now() > a.bid_deadline) {
    ignore(fmt::format("ANNOUNCE {}", a.conversation), "past its bid deadline");
    return;
  }
  auto it = offers_.find(a.conversation);
  if (it != offers_.end() && a.round <= it->second.round) {
    ignore(fmt::format("ANNOUNCE {} round {}", a.conversation, a.round), "duplicate or out-of-order round");
    return;
  }
  // The manager announces again a conversation we work: it gave up on us.
  drop_job(a.conversation, "conversation announced again");
  Offer& offer = offers_[a.conversation];
  offer.operation = a.operation;
  offer.product = a.product;
  offer.round = a.round;
  offer.forget_at = clock_->now() + config_.bid_memory;
  offer.params = a.params;
  if (config_.backend != nullptr && jobs_.size() < config_.capacity) {
    bid_from_backend(a, offer);
    return;
  }
  if (jobs_.size() >= config_.capacity) {
    offer.bid = false;
    ++stats_.declines;
    (void)send(a.conversation, a.operation, a.round, Refuse{0, "queue full"});
    return;
  }
  const auto start = free_at();
  const auto duration = scaled(s->duration, config_.speed);
  const Bid bid{to_utc(start), to_utc(start + duration),
                std::chrono::duration<double>(duration).count() * s->cost_rate,
                static_cast<std::uint32_t>(jobs_.size())};
  if (!send(a.conversation, a.operation, a.round, bid)) {
    return;
  }
  offer.bid = true;
  ++stats_.bids;
  if (events_.on_bid) {
    events_.on_bid(a);
  }
}

void Contractor::bid_from_backend(const Announce& a, Offer& offer) {
  std::string why_not;
  const auto estimate = config_.backend->estimate(a.operation, a.params, why_not);
  if (!estimate) {
    offer.bid = false;
    ++stats_.declines;
    (void)send(a.conversation, a.operation, a.round,
               Refuse{0, fit_text(why_not.empty() ? "cannot do it now" : why_not)});
    return;
  }
  const auto start = clock_->now() + estimate->start_in;
  const Skill* s = skill(a.operation);
  const Bid bid{to_utc(start), to_utc(start + estimate->duration),
                std::chrono::duration<double>(estimate->duration).count() * s->cost_rate,
                estimate->queue_length};
  if (!send(a.conversation, a.operation, a.round, bid)) {
    return;
  }
  offer.bid = true;
  ++stats_.bids;
  if (events_.on_bid) {
    events_.on_bid(a);
  }
}

void Contractor::on_manager_message(const ManagerMessage& m) {
  if (m.contractor != config_.name) {
    return;  // addressed to another contractor of this operation
  }
  if (skill(m.operation) == nullptr) {
    ignore(describe(m), fmt::format("unknown operation type {}", m.operation));
    return;
  }
  std::visit(Overloaded{[&](const Award& a) { on_award(m, a.award_id, a.confirm_by, nullptr); },
                        [&](const DirectedAward& a) { on_award(m, a.award_id, a.confirm_by, &a.params); },
                        [&](const Cancel& c) { on_cancel(m, c.award_id, c.reason); }},
             m.body);
}

void Contractor::on_award(const ManagerMessage& m, std::uint32_t award_id, UtcTime confirm_by,
                          const std::vector<Param>* directed) {
  auto it = offers_.find(m.conversation);
  if (award_id == 0 || (it != offers_.end() && award_id <= it->second.handled_award)) {
    ignore(describe(m), "duplicate or stale award");
    return;
  }
  if (events_.on_awarded) {
    events_.on_awarded(m);
  }
  if (directed != nullptr) {
    offers_[m.conversation].params = *directed;  // the work's parameters: no announcement gave them
    it = offers_.find(m.conversation);
  }
  if (directed == nullptr && (it == offers_.end() || !it->second.bid)) {
    refuse(m, award_id, "no bid in this conversation");
  } else if (directed == nullptr && m.round != it->second.round) {
    refuse(m, award_id, fmt::format("award for round {}, bid was for round {}", m.round, it->second.round));
  } else if (clock_->utc_now() > confirm_by) {
    refuse(m, award_id, "award arrived after its confirm-by time");
  } else if (std::any_of(jobs_.begin(), jobs_.end(),
                         [&](const Job& j) { return j.conversation == m.conversation; })) {
    refuse(m, award_id, "already working this conversation");
  } else if (jobs_.size() >= config_.capacity) {
    refuse(m, award_id, "queue full");
  } else if (auto why = backend_declines(m, directed)) {
    refuse(m, award_id, std::move(*why));
  } else {
    accept(m, award_id, *skill(m.operation));
  }
  Offer& offer = offers_[m.conversation];
  offer.operation = m.operation;
  offer.product = m.product;
  offer.handled_award = std::max(offer.handled_award, award_id);
  offer.forget_at = clock_->now() + config_.bid_memory;
}

// A directed award was never bid for: the backend is asked now whether it would do the work.
std::optional<std::string> Contractor::backend_declines(const ManagerMessage& m,
                                                        const std::vector<Param>* directed) const {
  if (directed == nullptr || config_.backend == nullptr) {
    return std::nullopt;
  }
  std::string why_not;
  if (config_.backend->estimate(m.operation, *directed, why_not)) {
    return std::nullopt;
  }
  return fit_text(why_not.empty() ? "cannot do it now" : why_not);
}

void Contractor::accept(const ManagerMessage& m, std::uint32_t award_id, const Skill& s) {
  Job job{m.conversation, m.product,    m.operation,   award_id,
          m.round,        work_time(s), clock_->now(), std::nullopt};
  if (!send(m.conversation, m.operation, m.round, Confirm{award_id})) {
    return;
  }
  ++stats_.confirms;
  jobs_.push_back(std::move(job));
  if (events_.on_confirmed) {
    events_.on_confirmed(jobs_.back());
  }
  const auto now = clock_->now();
  if (config_.backend != nullptr) {
    // The backend queues and times the work itself; it reports the end.
    jobs_.back().started_at = now;
    auto it = offers_.find(m.conversation);
    const auto& params = it != offers_.end() ? it->second.params : std::vector<Param>{};
    if (auto started = config_.backend->start(jobs_.back(), params); !started) {
      end_job(std::prev(jobs_.end()), false, started.error().message);
    }
    return;
  }
  start_head(now);
  finish_due(now);  // work that takes no time is done at once
}

Status Contractor::report(const std::string& conversation, bool ok, const std::string& detail,
                          std::vector<Param> results) {
  auto it =
      std::find_if(jobs_.begin(), jobs_.end(), [&](const Job& j) { return j.conversation == conversation; });
  if (it == jobs_.end()) {
    return make_error(Errc::not_found,
                      fmt::format("{} has no job in conversation {}", config_.name, conversation));
  }
  end_job(it, ok, detail, std::move(results));
  return {};
}

Status Contractor::report(const std::string& conversation, std::uint32_t award_id, bool ok,
                          const std::string& detail, std::vector<Param> results) {
  auto it = std::find_if(jobs_.begin(), jobs_.end(), [&](const Job& j) {
    return j.conversation == conversation && j.award_id == award_id;
  });
  if (it == jobs_.end()) {
    return make_error(Errc::not_found, fmt::format("{} has no job for award {} in conversation {}",
                                                   config_.name, award_id, conversation));
  }
  end_job(it, ok, detail, std::move(results));
  return {};
}

void Contractor::end_job(const std::deque<Job>::iterator& it, bool ok, const std::string& detail,
                         std::vector<Param> results) {
  const Job job = *it;
  jobs_.erase(it);
  if (ok) {
    ++stats_.done;
    (void)send(job.conversation, job.operation, job.round,
               InformDone{job.award_id, fit_text(detail), std::move(results)});
  } else {
    ++stats_.failures;
    (void)send(job.conversation, job.operation, job.round, Failure{job.award_id, fit_text(detail)});
  }
  if (events_.on_work_finished) {
    events_.on_work_finished(job, ok);
  }
}

void Contractor::refuse(const ManagerMessage& m, std::uint32_t award_id, std::string reason) {
  log_->info("{} refuses {}: {}", config_.name, describe(m), reason);
  ++stats_.refusals;
  (void)send(m.conversation, m.operation, m.round, Refuse{award_id, fit_text(reason)});
}

void Contractor::on_cancel(const ManagerMessage& m, std::uint32_t award_id, const std::string& reason) {
  const auto it = std::find_if(jobs_.begin(), jobs_.end(), [&](const Job& j) {
    return j.conversation == m.conversation && j.award_id == award_id;
  });
  if (it == jobs_.end()) {
    ignore(describe(m), "cancel of an award not worked here");
    return;
  }
  drop_job(m.conversation, fmt::format("award cancelled: {}", reason));
}

void Contractor::drop_job(const std::string& conversation, const std::string& why) {
  const auto it =
      std::find_if(jobs_.begin(), jobs_.end(), [&](const Job& j) { return j.conversation == conversation; });
  if (it == jobs_.end()) {
    return;
  }
  const bool was_head = it == jobs_.begin();
  const Job job = *it;
  jobs_.erase(it);
  ++stats_.aborted;
  log_->info("{} drops {} (award {}): {}", config_.name, conversation, job.award_id, why);
  if (config_.backend != nullptr) {
    config_.backend->abort(job, why);
  }
  if (events_.on_work_aborted) {
    events_.on_work_aborted(job, why);
  }
  if (was_head) {
    start_head(clock_->now());
  }
}

void Contractor::start_head(Clock::time_point at) {
  if (jobs_.empty() || jobs_.front().started_at) {
    return;
  }
  jobs_.front().started_at = std::max(at, jobs_.front().accepted_at);
  if (events_.on_work_started) {
    events_.on_work_started(jobs_.front());
  }
}

void Contractor::finish_head() {
  const Job job = jobs_.front();
  jobs_.pop_front();
  const bool ok = config_.failure_probability <= 0.0 ||
                  std::uniform_real_distribution<double>{0.0, 1.0}(rng_) >= config_.failure_probability;
  if (ok) {
    ++stats_.done;
    (void)send(job.conversation, job.operation, job.round, InformDone{job.award_id, "done"});
  } else {
    ++stats_.failures;
    (void)send(job.conversation, job.operation, job.round, Failure{job.award_id, "simulated failure"});
  }
  if (events_.on_work_finished) {
    events_.on_work_finished(job, ok);
  }
  // The next job starts when this one finished, not when we noticed.
  start_head(*job.started_at + job.duration);
}

void Contractor::finish_due(Clock::time_point now) {
  if (config_.backend != nullptr) {
    return;  // the backend reports its jobs' ends
  }
  while (!jobs_.empty() && jobs_.front().started_at &&
         *jobs_.front().started_at + jobs_.front().duration <= now) {
    finish_head();
  }
}

void Contractor::tick() {
  const auto now = clock_->now();
  finish_due(now);
  if (now < next_purge_) {
    return;
  }
  // Old offers are swept now and then, not on every tick (there may be thousands).
  next_purge_ = now + config_.bid_memory / 8;
  std::erase_if(offers_, [&](const auto& entry) {
    return entry.second.forget_at <= now && std::none_of(jobs_.begin(), jobs_.end(), [&](const Job& j) {
             return j.conversation == entry.first;
           });
  });
}

std::optional<Clock::time_point> Contractor::next_deadline() const {
  if (config_.backend != nullptr || jobs_.empty() || !jobs_.front().started_at) {
    return std::nullopt;
  }
  return *jobs_.front().started_at + jobs_.front().duration;
}

void Contractor::on_conversation_closed(const std::string& operation, const std::string& conversation) {
  const bool known = offers_.erase(conversation) > 0;
  const bool working =
      std::any_of(jobs_.begin(), jobs_.end(), [&](const Job& j) { return j.conversation == conversation; });
  drop_job(conversation, "conversation closed by the manager");
  if (known || working) {
    transport_->close(operation, conversation);
  }
}

Status Contractor::send(const std::string& conversation, const std::string& operation, std::uint32_t round,
                        ContractorBody body) {
  ContractorMessage m{conversation, config_.name, operation, round, std::move(body)};
  auto st = transport_->send(m);
  if (!st) {
    log_->warn("{}: sending {} failed: {}", config_.name, describe(m), st.error().describe());
  }
  return st;
}

void Contractor::ignore(std::string_view what, std::string_view reason) {
  ++stats_.ignored;
  last_ignored_ = std::string{reason};
  log_->info("{} ignored {}: {}", config_.name, what, reason);
}

}  // namespace sf::negotiation
