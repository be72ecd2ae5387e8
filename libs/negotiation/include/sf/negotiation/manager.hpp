// Manager: the Contract Net manager role (the paper's product, §IV.B). For
// each operation it needs, it runs one conversation:
//
//   ANNOUNCE ──bids until the bid deadline (or until every listening
//   contractor answered)──► rank by the selection policy ──► AWARD the best,
//   wait for its CONFIRM until confirm_by + grace ──► the contractor works ──►
//   INFORM-DONE ends the conversation (its instances are disposed).
//
// Rules (each has a unit test in test/manager_test.cpp):
// - No bid by the deadline: announce again (round + 1) after reannounce_delay,
//   at most max_rounds announcements (0 = no limit), then the conversation fails.
// - REFUSE of the award, no CONFIRM in time, or the awardee's liveliness lost:
//   the award is withdrawn (CANCEL) and the next-best bidder is awarded; with no
//   bidder left, the operation is announced again.
// - At most one live award per conversation: a new award is only made after
//   the previous one was refused, lapsed or withdrawn. A CONFIRM of a withdrawn
//   award is answered with CANCEL, so that contractor does not work.
// - The confirmed contractor lost (liveliness) or FAILURE: the operation is
//   negotiated again (renegotiation), the old award withdrawn. With lost_grace,
//   a lost worker has that long to come back (liveliness regained, or any message
//   from it) before its work is given up: a machine that only missed its lease
//   (a loaded host) may be moving a box, which a second award cannot undo.
// - A worker given up on (renegotiated while it worked) that reports INFORM-DONE
//   of its withdrawn award while the conversation is still open did the work: it
//   was cut off, not gone (a network partition longer than the grace). The
//   conversation ends with its result and a newer award is withdrawn (CANCEL):
//   doing the work again would do it twice. Its FAILURE changes nothing.
// - DIRECTEDAWARD: the award goes to a named contractor without a call; if it
//   refuses or does not confirm, the manager falls back to ANNOUNCE.
// - Bids after the deadline, for another round, duplicates, and messages for
//   unknown conversations or stale awards are ignored with a log line.
//
// Single-threaded: call everything from the thread that drains the transport.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/core/result.hpp"
#include "sf/negotiation/messages.hpp"
#include "sf/negotiation/selection.hpp"
#include "sf/negotiation/transport.hpp"

namespace sf::negotiation {

struct ManagerConfig {
  std::chrono::nanoseconds bid_window{std::chrono::milliseconds{500}};        // ANNOUNCE → bid deadline
  std::chrono::nanoseconds confirm_window{std::chrono::milliseconds{500}};    // AWARD → confirm_by
  std::chrono::nanoseconds confirm_grace{std::chrono::milliseconds{250}};     // CONFIRM still in flight
  std::chrono::nanoseconds reannounce_delay{std::chrono::milliseconds{200}};  // after a round without bids
  std::uint32_t max_rounds = 10;             // announcements per conversation; 0 = unlimited
  std::chrono::nanoseconds work_timeout{0};  // > 0: no INFORM-DONE by then → renegotiate
  std::chrono::nanoseconds lost_grace{0};    // > 0: a lost worker's time to come back
  std::uint32_t incarnation = 0;             // part of conversation ids; 0 = random
};

enum class Phase { Directing, Collecting, Waiting, Awarding, Working, Done, Failed };
std::string_view to_string(Phase phase);

struct OperationRequest {
  std::string product;
  std::string operation;
  std::vector<Param> params;
  std::string directed_to;  // non-empty: DIRECTEDAWARD to this contractor first
};

struct Conversation;
struct ConversationEvents {
  std::function<void(const Conversation&)> on_confirmed;  // may come again after a renegotiation
  std::function<void(const Conversation&)> on_done;
  std::function<void(const Conversation&)> on_failed;
};

struct Conversation {
  std::string id;
  std::string product;
  std::string operation;
  std::vector<Param> params;
  Phase phase = Phase::Collecting;
  std::uint32_t round = 0;  // current announcement round (0 before the first)
  std::uint32_t announcements = 0;
  std::uint32_t renegotiations = 0;
  std::uint32_t last_award = 0;                  // id of the most recent award (live or not)
  std::map<std::uint32_t, std::string> awarded;  // every award made: id → contractor
  std::string contractor;                        // addressee of the live award, then the confirmed contractor
  std::map<std::string, Bid> bids;               // this round
  std::set<std::string> answered;                // bid or declined this round
  std::vector<RankedBid> candidates;             // ranked bids not yet tried
  std::set<std::string> lost;                    // contractors whose liveliness was lost
  std::map<std::uint32_t, std::string> given_up;  // confirmed awards withdrawn while worked: id → contractor
  Clock::time_point started_at{};
  Clock::time_point confirmed_at{};
  Clock::time_point timer = Clock::time_point::max();
  std::string failure;
  std::string result;          // of the INFORM-DONE
  std::vector<Param> results;  // of the INFORM-DONE, typed
  ConversationEvents events;
};

// A conversation for `request` opened at `now` (Phase::Collecting), as a manager
// keeps it; a central dispatcher keeps its decisions the same way.
Conversation open_conversation(std::string id, OperationRequest request, ConversationEvents events,
                               Clock::time_point now);

struct ManagerStats {
  std::uint64_t started = 0;
  std::uint64_t announcements = 0;
  std::uint64_t awards = 0;
  std::uint64_t confirmed = 0;
  std::uint64_t done = 0;
  std::uint64_t failed = 0;
  std::uint64_t renegotiations = 0;
  std::uint64_t cancels = 0;
  std::uint64_t ignored = 0;
};

class Manager final : public ManagerInbox {
 public:
  Manager(ManagerTransport& transport, const Clock& clock, ManagerConfig config = {},
          SelectionPolicy policy = earliest_finish());

  // Starts a conversation for one operation; returns its id.
  Result<std::string> negotiate(OperationRequest request, ConversationEvents events = {});

  void on_contractor_message(const ContractorMessage& message) override;
  void on_contractor_lost(const std::string& operation, const std::string& contractor) override;
  void on_contractor_alive(const std::string& operation, const std::string& contractor) override;

  // Fires due timers (bid deadlines, confirmation timeouts, re-announcements).
  void tick();
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const;

  // An active conversation (nullptr once done or failed).
  [[nodiscard]] const Conversation* find(std::string_view id) const;
  [[nodiscard]] std::size_t active() const { return conversations_.size(); }
  [[nodiscard]] const ManagerStats& stats() const { return stats_; }
  // Why the most recent message was ignored (for tests and diagnostics).
  [[nodiscard]] const std::string& last_ignored() const { return last_ignored_; }
  [[nodiscard]] const ManagerConfig& config() const { return config_; }

 private:
  Conversation* lookup(const std::string& id);
  void on_work_timer(Conversation& c);
  void set_timer(Conversation& c, Clock::time_point at);
  void clear_timer(Conversation& c);
  void on_timer(Conversation& c);

  void start_round(Conversation& c);
  void maybe_close_bidding(Conversation& c);
  void close_bidding(Conversation& c);
  void award_next(Conversation& c);
  void no_contractor(Conversation& c, std::string_view why);
  void withdraw(Conversation& c, std::string_view reason);
  void renegotiate(Conversation& c, std::string_view reason);
  void complete(Conversation& c);
  void fail(Conversation& c, std::string reason);
  void finish(Conversation& c, Phase phase);
  Status send(Conversation& c, const std::string& to, ManagerBody body);

  void on_bid(Conversation& c, const ContractorMessage& m, const Bid& bid);
  void on_refuse(Conversation& c, const ContractorMessage& m, const Refuse& refuse);
  void on_confirm(Conversation& c, const ContractorMessage& m, const Confirm& confirm);
  void on_inform_done(Conversation& c, const ContractorMessage& m, const InformDone& done);
  void on_failure(Conversation& c, const ContractorMessage& m, const Failure& failure);
  [[nodiscard]] bool is_live_award(const Conversation& c, const ContractorMessage& m) const;
  [[nodiscard]] static bool was_given_up(const Conversation& c, const ContractorMessage& m);
  void ignore(const ContractorMessage& m, std::string_view reason, bool expected = false);

  ManagerTransport* transport_;
  const Clock* clock_;
  ManagerConfig config_;
  SelectionPolicy policy_;
  std::uint64_t next_seq_ = 0;
  std::map<std::string, Conversation, std::less<>> conversations_;
  std::multimap<Clock::time_point, std::string> timers_;
  ManagerStats stats_;
  std::string last_ignored_;
  log::Logger log_;
};

}  // namespace sf::negotiation
