#include "sf/negotiation/manager.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "support.hpp"

namespace sf::negotiation {
namespace {

using detail::Overloaded;
using detail::random_incarnation;

}  // namespace

std::string_view to_string(Phase phase) {
  switch (phase) {
    case Phase::Directing:
      return "directing";
    case Phase::Collecting:
      return "collecting";
    case Phase::Waiting:
      return "waiting";
    case Phase::Awarding:
      return "awarding";
    case Phase::Working:
      return "working";
    case Phase::Done:
      return "done";
    case Phase::Failed:
      return "failed";
  }
  return "?";
}

Conversation open_conversation(std::string id, OperationRequest request, ConversationEvents events,
                               Clock::time_point now) {
  Conversation c;
  c.id = std::move(id);
  c.product = std::move(request.product);
  c.operation = std::move(request.operation);
  c.params = std::move(request.params);
  c.started_at = now;
  c.events = std::move(events);
  return c;
}

Manager::Manager(ManagerTransport& transport, const Clock& clock, ManagerConfig config,
                 SelectionPolicy policy)
    : transport_(&transport),
      clock_(&clock),
      config_(config),
      policy_(std::move(policy)),
      log_(log::get("negotiation")) {
  if (config_.incarnation == 0) {
    config_.incarnation = random_incarnation();
  }
}

Result<std::string> Manager::negotiate(OperationRequest request, ConversationEvents events) {
  SF_TRY(validate_name("product", request.product));
  SF_TRY(validate_operation(request.operation));
  if (request.params.size() > kMaxParams) {
    return Error{Errc::limit_exceeded,
                 fmt::format("{} parameters, at most {}", request.params.size(), kMaxParams)};
  }
  if (!request.directed_to.empty()) {
    SF_TRY(validate_name("contractor", request.directed_to));
  }
  auto id =
      fmt::format("{}/{}/{:x}.{}", request.product, request.operation, config_.incarnation, ++next_seq_);
  if (id.size() > kMaxConversation) {
    return Error{Errc::limit_exceeded,
                 fmt::format("conversation id '{}' is longer than {}", id, kMaxConversation)};
  }
  const std::string directed_to = request.directed_to;
  Conversation& c = conversations_[id] =
      open_conversation(id, std::move(request), std::move(events), clock_->now());
  ++stats_.started;
  if (directed_to.empty()) {
    start_round(c);
    return id;
  }
  // DIRECTEDAWARD: no call for proposals; confirm or we fall back to ANNOUNCE.
  c.phase = Phase::Directing;
  c.contractor = directed_to;
  c.last_award = 1;
  c.awarded[1] = c.contractor;
  const auto confirm_by = clock_->utc_now() + config_.confirm_window;
  if (auto st = send(c, c.contractor, DirectedAward{1, confirm_by, c.params}); !st) {
    start_round(c);
    return id;
  }
  set_timer(c, clock_->now() + config_.confirm_window + config_.confirm_grace);
  return id;
}

Conversation* Manager::lookup(const std::string& id) {
  auto it = conversations_.find(id);
  return it == conversations_.end() ? nullptr : &it->second;
}

const Conversation* Manager::find(std::string_view id) const {
  auto it = conversations_.find(id);
  return it == conversations_.end() ? nullptr : &it->second;
}

// timers_ holds exactly one entry per conversation with a timer: a stale entry would make
// next_deadline() earlier than any real timer, and the agent loop would wake for nothing (with
// two-second windows, once per finished negotiation two seconds later).
void Manager::set_timer(Conversation& c, Clock::time_point at) {
  clear_timer(c);
  c.timer = at;
  if (at != Clock::time_point::max()) {
    timers_.emplace(at, c.id);
  }
}

void Manager::clear_timer(Conversation& c) {
  if (c.timer == Clock::time_point::max()) {
    return;
  }
  auto [first, last] = timers_.equal_range(c.timer);
  const auto it = std::find_if(first, last, [&](const auto& entry) { return entry.second == c.id; });
  if (it != last) {
    timers_.erase(it);
  }
  c.timer = Clock::time_point::max();
}

std::optional<Clock::time_point> Manager::next_deadline() const {
  if (timers_.empty()) {
    return std::nullopt;
  }
  return timers_.begin()->first;
}

void Manager::tick() {
  const auto now = clock_->now();
  while (!timers_.empty() && timers_.begin()->first <= now) {
    const auto node = timers_.extract(timers_.begin());
    if (Conversation* c = lookup(node.mapped()); c != nullptr) {
      c->timer = Clock::time_point::max();
      on_timer(*c);
    }
  }
}

void Manager::on_timer(Conversation& c) {
  switch (c.phase) {
    case Phase::Collecting:
      close_bidding(c);
      break;
    case Phase::Waiting:
      start_round(c);
      break;
    case Phase::Awarding:
      log_->info("{}: {} did not confirm award {} in time", c.id, c.contractor, c.last_award);
      withdraw(c, "confirmation timeout");
      award_next(c);
      break;
    case Phase::Directing:
      log_->info("{}: {} did not confirm the directed award in time; announcing", c.id, c.contractor);
      withdraw(c, "confirmation timeout");
      start_round(c);
      break;
    case Phase::Working:
      on_work_timer(c);
      break;
    case Phase::Done:
    case Phase::Failed:
      break;
  }
}

void Manager::start_round(Conversation& c) {
  if (config_.max_rounds != 0 && c.announcements >= config_.max_rounds) {
    fail(c, fmt::format("no contractor confirmed {} after {} announcements", c.operation, c.announcements));
    return;
  }
  ++c.round;
  ++c.announcements;
  ++stats_.announcements;
  c.bids.clear();
  c.answered.clear();
  c.candidates.clear();
  c.lost.clear();
  c.contractor.clear();
  c.phase = Phase::Collecting;
  const Announce a{c.id, c.product, c.operation, c.round, c.params, clock_->utc_now() + config_.bid_window};
  if (auto st = transport_->announce(a); !st) {
    log_->warn("{}: ANNOUNCE failed: {}", c.id, st.error().describe());
    c.phase = Phase::Waiting;
    set_timer(c, clock_->now() + config_.reannounce_delay);
    return;
  }
  set_timer(c, clock_->now() + config_.bid_window);
}

void Manager::maybe_close_bidding(Conversation& c) {
  // Everyone listening has answered: no reason to wait for the deadline.
  const std::size_t expected = transport_->contractors(c.operation);
  if (c.phase == Phase::Collecting && expected > 0 && c.answered.size() >= expected) {
    close_bidding(c);
  }
}

void Manager::close_bidding(Conversation& c) {
  std::vector<RankedBid> bids;
  for (const auto& [who, bid] : c.bids) {
    if (!c.lost.contains(who)) {
      bids.push_back({who, bid});
    }
  }
  c.candidates = rank(policy_, std::move(bids));
  award_next(c);
}

void Manager::award_next(Conversation& c) {
  while (!c.candidates.empty()) {
    const RankedBid next = c.candidates.front();
    c.candidates.erase(c.candidates.begin());
    if (c.lost.contains(next.contractor)) {
      continue;
    }
    c.contractor = next.contractor;
    c.last_award += 1;
    c.awarded[c.last_award] = c.contractor;
    c.phase = Phase::Awarding;
    const auto confirm_by = clock_->utc_now() + config_.confirm_window;
    if (auto st = send(c, c.contractor, Award{c.last_award, confirm_by}); !st) {
      continue;
    }
    ++stats_.awards;
    set_timer(c, clock_->now() + config_.confirm_window + config_.confirm_grace);
    return;
  }
  c.contractor.clear();
  no_contractor(c, c.bids.empty() ? "no bid" : "no bidder confirmed");
}

void Manager::no_contractor(Conversation& c, std::string_view why) {
  log_->info("{}: {} in round {}; announcing again", c.id, why, c.round);
  c.phase = Phase::Waiting;
  set_timer(c, clock_->now() + config_.reannounce_delay);
}

void Manager::withdraw(Conversation& c, std::string_view reason) {
  if (c.contractor.empty() || c.last_award == 0) {
    return;
  }
  ++stats_.cancels;
  (void)send(c, c.contractor, Cancel{c.last_award, std::string{reason.substr(0, kMaxText)}});
  c.contractor.clear();
}

void Manager::renegotiate(Conversation& c, std::string_view reason) {
  log_->info("{}: renegotiating ({})", c.id, reason);
  if (c.phase == Phase::Working && !c.contractor.empty()) {
    c.given_up[c.last_award] = c.contractor;
  }
  withdraw(c, reason);
  ++c.renegotiations;
  ++stats_.renegotiations;
  start_round(c);
}

void Manager::complete(Conversation& c) {
  finish(c, Phase::Done);
}

void Manager::fail(Conversation& c, std::string reason) {
  log_->warn("{}: failed: {}", c.id, reason);
  withdraw(c, "conversation failed");
  c.failure = std::move(reason);
  finish(c, Phase::Failed);
}

void Manager::finish(Conversation& c, Phase phase) {
  c.phase = phase;
  clear_timer(c);
  transport_->close(c.operation, c.id);
  // Out of the map before the callback, which may start new conversations.
  auto node = conversations_.extract(c.id);
  if (phase == Phase::Done) {
    ++stats_.done;
    if (node.mapped().events.on_done) {
      node.mapped().events.on_done(node.mapped());
    }
  } else {
    ++stats_.failed;
    if (node.mapped().events.on_failed) {
      node.mapped().events.on_failed(node.mapped());
    }
  }
}

Status Manager::send(Conversation& c, const std::string& to, ManagerBody body) {
  ManagerMessage m{c.id, c.product, c.operation, to, c.round, std::move(body)};
  auto st = transport_->send(m);
  if (!st) {
    log_->warn("{}: sending {} failed: {}", c.id, describe(m), st.error().describe());
  }
  return st;
}

void Manager::on_contractor_message(const ContractorMessage& m) {
  Conversation* c = lookup(m.conversation);
  if (c == nullptr) {
    ignore(m, "unknown or finished conversation", true);
    return;
  }
  if (m.operation != c->operation) {
    ignore(m, fmt::format("operation {} does not match the conversation's {}", m.operation, c->operation));
    return;
  }
  std::visit(
      Overloaded{[&](const Bid& b) { on_bid(*c, m, b); }, [&](const Refuse& r) { on_refuse(*c, m, r); },
                 [&](const Confirm& k) { on_confirm(*c, m, k); },
                 [&](const InformDone& d) { on_inform_done(*c, m, d); },
                 [&](const Failure& f) { on_failure(*c, m, f); }},
      m.body);
}

void Manager::on_bid(Conversation& c, const ContractorMessage& m, const Bid& bid) {
  if (c.phase != Phase::Collecting || m.round != c.round) {
    ignore(m, m.round != c.round ? fmt::format("bid for round {}, current round is {}", m.round, c.round)
                                 : std::string{"bid after the deadline"});
    return;
  }
  if (clock_->now() >= c.timer) {
    ignore(m, "bid after the deadline");
    return;
  }
  if (!c.answered.insert(m.contractor).second) {
    ignore(m, "duplicate answer in this round");
    return;
  }
  c.lost.erase(m.contractor);
  c.bids[m.contractor] = bid;
  maybe_close_bidding(c);
}

void Manager::on_refuse(Conversation& c, const ContractorMessage& m, const Refuse& refuse) {
  if (refuse.award_id == 0) {  // declines the call for proposals
    if (c.phase != Phase::Collecting || m.round != c.round || !c.answered.insert(m.contractor).second) {
      ignore(m, "stale or duplicate decline");
      return;
    }
    maybe_close_bidding(c);
    return;
  }
  if (!is_live_award(c, m) || (c.phase != Phase::Awarding && c.phase != Phase::Directing)) {
    ignore(m, "refusal of an award that is not live");
    return;
  }
  log_->info("{}: {} refused award {}: {}", c.id, m.contractor, refuse.award_id, refuse.reason);
  c.contractor.clear();
  if (c.phase == Phase::Directing) {
    start_round(c);
  } else {
    award_next(c);
  }
}

void Manager::on_confirm(Conversation& c, const ContractorMessage& m, const Confirm& confirm) {
  if (is_live_award(c, m) && (c.phase == Phase::Awarding || c.phase == Phase::Directing)) {
    c.phase = Phase::Working;
    c.confirmed_at = clock_->now();
    ++stats_.confirmed;
    set_timer(c, config_.work_timeout.count() > 0 ? c.confirmed_at + config_.work_timeout
                                                  : Clock::time_point::max());
    if (c.events.on_confirmed) {
      c.events.on_confirmed(c);
    }
    return;
  }
  if (is_live_award(c, m) && c.phase == Phase::Working) {
    ignore(m, "duplicate confirmation");
    return;
  }
  ignore(m, "confirmation of an award that is not live");
  if (auto it = c.awarded.find(confirm.award_id); it != c.awarded.end() && it->second == m.contractor) {
    // One of our earlier awards, confirmed too late: make sure it is not worked.
    ++stats_.cancels;
    (void)send(c, m.contractor, Cancel{confirm.award_id, "award withdrawn"});
  }
}

void Manager::on_inform_done(Conversation& c, const ContractorMessage& m, const InformDone& done) {
  const bool live = is_live_award(c, m) && c.phase == Phase::Working;
  if (!live && !was_given_up(c, m)) {
    ignore(m, "INFORM-DONE for an award that is not being worked");
    return;
  }
  if (!live) {
    // Cut off, not gone: the work is done, and whoever has it now must not do it again.
    log_->info("{}: {} did award {} after all; ending the conversation with it", c.id, m.contractor,
               done.award_id);
    withdraw(c, "done by an earlier award");
    c.contractor = m.contractor;
  }
  log_->debug("{}: done by {}: {}", c.id, m.contractor, done.result);
  c.result = done.result;
  c.results = done.results;
  complete(c);
}

void Manager::on_failure(Conversation& c, const ContractorMessage& m, const Failure& failure) {
  if (!is_live_award(c, m) || c.phase != Phase::Working) {
    ignore(m, "FAILURE for an award that is not being worked");
    return;
  }
  renegotiate(c, fmt::format("FAILURE from {}: {}", m.contractor, failure.reason));
}

bool Manager::is_live_award(const Conversation& c, const ContractorMessage& m) const {
  return !c.contractor.empty() && m.contractor == c.contractor && award_of(m.body) == c.last_award;
}

bool Manager::was_given_up(const Conversation& c, const ContractorMessage& m) {
  const auto it = c.given_up.find(award_of(m.body));
  return it != c.given_up.end() && it->second == m.contractor;
}

void Manager::on_contractor_lost(const std::string& operation, const std::string& contractor) {
  std::vector<std::string> affected;
  for (const auto& [id, c] : conversations_) {
    if (c.operation == operation) {
      affected.push_back(id);
    }
  }
  for (const auto& id : affected) {
    Conversation* c = lookup(id);
    if (c == nullptr) {
      continue;
    }
    c->lost.insert(contractor);
    c->bids.erase(contractor);
    const bool awardee = c->contractor == contractor;
    if (c->phase == Phase::Collecting) {
      maybe_close_bidding(*c);
    } else if (awardee && c->phase == Phase::Awarding) {
      log_->info("{}: awardee {} lost", c->id, contractor);
      withdraw(*c, "contractor lost");
      award_next(*c);
    } else if (awardee && c->phase == Phase::Directing) {
      withdraw(*c, "contractor lost");
      start_round(*c);
    } else if (awardee && c->phase == Phase::Working && config_.lost_grace.count() > 0) {
      log_->info("{}: worker {} lost; waiting {} ms for it to come back", c->id, contractor,
                 std::chrono::duration_cast<std::chrono::milliseconds>(config_.lost_grace).count());
      set_timer(*c, std::min(c->timer, clock_->now() + config_.lost_grace));
    } else if (awardee && c->phase == Phase::Working) {
      renegotiate(*c, fmt::format("contractor {} lost", contractor));
    }
  }
}

void Manager::on_contractor_alive(const std::string& operation, const std::string& contractor) {
  for (auto& [id, c] : conversations_) {
    if (c.operation == operation && c.lost.erase(contractor) > 0 && c.contractor == contractor &&
        c.phase == Phase::Working) {
      log_->info("{}: worker {} is back", c.id, contractor);
    }
  }
}

// The Working timer: the lost grace of the worker or the work timeout, whichever came first. A
// worker back in time (on_contractor_alive, or a message from it) keeps its work.
void Manager::on_work_timer(Conversation& c) {
  if (c.lost.contains(c.contractor)) {
    renegotiate(c, fmt::format("contractor {} lost", c.contractor));
    return;
  }
  const auto work_deadline =
      config_.work_timeout.count() > 0 ? c.confirmed_at + config_.work_timeout : Clock::time_point::max();
  if (clock_->now() >= work_deadline) {
    renegotiate(c, "no INFORM-DONE within the work timeout");
    return;
  }
  set_timer(c, work_deadline);
}

void Manager::ignore(const ContractorMessage& m, std::string_view reason, bool expected) {
  ++stats_.ignored;
  last_ignored_ = std::string{reason};
  // Stale messages for finished conversations are normal traffic: debug only.
  if (expected) {
    log_->debug("ignored {}: {}", describe(m), reason);
  } else {
    log_->info("ignored {}: {}", describe(m), reason);
  }
}

}  // namespace sf::negotiation
