// Contractor: the Contract Net contractor role (the paper's machine, §IV.B).
// It bids on announced operations it can do, confirms awards addressed to it,
// works them one after another (a simulated job queue timed by the Clock) and
// reports INFORM-DONE or FAILURE.
//
// Rules (each has a unit test in test/contractor_test.cpp):
// - ANNOUNCE of an operation it cannot do, past its bid deadline, or a round
//   already answered: ignored with a log line. A full queue: REFUSE (declines).
// - BID: estimated start = when its queue is free, finish = start + duration /
//   speed, cost = duration in seconds x the skill's cost rate, queue length.
// - Work starts only after it CONFIRMed an AWARD (or DIRECTEDAWARD) addressed to
//   it; an award past its confirm_by, for a round it did not bid in, or that it
//   cannot take (queue full) is REFUSEd; a duplicate award is ignored.
// - CANCEL of its award, a re-announcement of a conversation it works (the
//   manager gave up on it), or the conversation's end: the job is dropped
//   (aborted if it had started).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/core/result.hpp"
#include "sf/negotiation/messages.hpp"
#include "sf/negotiation/transport.hpp"

namespace sf::negotiation {

struct Skill {
  std::string operation;
  std::chrono::nanoseconds duration{std::chrono::milliseconds{100}};  // at speed 1
  double cost_rate = 1.0;                                             // cost per second of work
};

struct Job;

// What a contractor estimates for an announced operation when a WorkBackend
// does its work.
struct WorkEstimate {
  std::chrono::nanoseconds start_in{0};  // until the machine could start it
  std::chrono::nanoseconds duration{0};
  std::uint32_t queue_length = 0;
};

// Where a contractor's work really happens (a shop-floor controller, the
// factory module). Without one, the contractor simulates its jobs with its
// skills' durations. With one, bids come from the backend's estimates, a
// confirmed job is handed to it at once (it keeps its own queue), and the
// job ends when the backend calls Contractor::report(). All calls come from
// the contractor's thread; the backend reports from that thread too.
class WorkBackend {
 public:
  virtual ~WorkBackend() = default;
  // An estimate, or nullopt to decline the call for proposals (why_not says
  // why: held, faulted, no stock of that candy, ...).
  virtual std::optional<WorkEstimate> estimate(const std::string& operation, const std::vector<Param>& params,
                                               std::string& why_not) = 0;
  // A confirmed job with the parameters of its announcement. An error fails
  // it at once (FAILURE with the message).
  virtual Status start(const Job& job, const std::vector<Param>& params) = 0;
  // The job was withdrawn (CANCEL, re-announcement, the manager gone).
  virtual void abort(const Job& job, const std::string& why) = 0;
};

struct ContractorConfig {
  std::string name;
  std::vector<Skill> skills;
  double speed = 1.0;                  // durations are divided by it
  std::size_t capacity = 64;           // jobs queued or running; beyond: REFUSE
  std::chrono::nanoseconds jitter{0};  // each job takes up to this much longer (random)
  double failure_probability = 0.0;    // a job ends in FAILURE instead of INFORM-DONE
  std::uint64_t seed = 1;
  std::chrono::nanoseconds bid_memory{std::chrono::seconds{60}};  // forget bids never closed
  WorkBackend* backend = nullptr;  // real work (see WorkBackend); must outlive the contractor
};

struct Job {
  std::string conversation;
  std::string product;
  std::string operation;
  std::uint32_t award_id = 0;
  std::uint32_t round = 0;
  std::chrono::nanoseconds duration{0};
  Clock::time_point accepted_at{};
  std::optional<Clock::time_point> started_at;  // set when it reaches the head of the queue
};

struct ContractorEvents {
  std::function<void(const Announce&)> on_bid;            // after a BID was sent
  std::function<void(const ManagerMessage&)> on_awarded;  // an award to us arrived
  std::function<void(const Job&)> on_confirmed;           // after CONFIRM was sent
  std::function<void(const Job&)> on_work_started;
  std::function<void(const Job&, bool ok)> on_work_finished;  // INFORM-DONE (ok) or FAILURE sent
  std::function<void(const Job&, const std::string& why)> on_work_aborted;
};

struct ContractorStats {
  std::uint64_t bids = 0;
  std::uint64_t declines = 0;
  std::uint64_t confirms = 0;
  std::uint64_t refusals = 0;
  std::uint64_t done = 0;
  std::uint64_t failures = 0;
  std::uint64_t aborted = 0;
  std::uint64_t ignored = 0;
};

class Contractor final : public ContractorInbox {
 public:
  static Result<Contractor> create(ContractorTransport& transport, const Clock& clock,
                                   ContractorConfig config, ContractorEvents events = {});

  void on_announce(const Announce& announce) override;
  void on_manager_message(const ManagerMessage& message) override;
  void on_conversation_closed(const std::string& operation, const std::string& conversation) override;

  // Finishes jobs whose time is up and starts the next; forgets old bids.
  void tick();
  // With a WorkBackend: the job of this conversation ended; INFORM-DONE (ok,
  // with `detail` as its result and `results` typed) or FAILURE (detail as
  // the reason) goes to the manager. Errc::not_found when no such job is queued.
  Status report(const std::string& conversation, bool ok, const std::string& detail,
                std::vector<Param> results = {});
  // The same for one award of the conversation: the report of a job that was cancelled (the
  // manager renegotiated) does not end a newer award of the same conversation to this contractor.
  Status report(const std::string& conversation, std::uint32_t award_id, bool ok, const std::string& detail,
                std::vector<Param> results = {});
  [[nodiscard]] std::optional<Clock::time_point> next_deadline() const;

  [[nodiscard]] const std::string& name() const { return config_.name; }
  [[nodiscard]] const ContractorConfig& config() const { return config_; }
  [[nodiscard]] const std::deque<Job>& jobs() const { return jobs_; }
  // Conversations it still remembers (bid in, or awarded); closed ones are forgotten.
  [[nodiscard]] std::size_t conversations() const { return offers_.size(); }
  [[nodiscard]] const ContractorStats& stats() const { return stats_; }
  [[nodiscard]] const std::string& last_ignored() const { return last_ignored_; }
  [[nodiscard]] bool supports(const std::string& operation) const { return skill(operation) != nullptr; }

 private:
  // What this contractor remembers of a conversation it bid in.
  struct Offer {
    std::string operation;
    std::string product;
    std::uint32_t round = 0;
    bool bid = false;
    std::uint32_t handled_award = 0;  // highest award id answered
    Clock::time_point forget_at{};
    std::vector<Param> params;  // of the announcement, for a WorkBackend
  };

  Contractor(ContractorTransport& transport, const Clock& clock, ContractorConfig config,
             ContractorEvents events);

  [[nodiscard]] const Skill* skill(const std::string& operation) const;
  [[nodiscard]] Clock::time_point free_at() const;
  [[nodiscard]] std::chrono::nanoseconds work_time(const Skill& s);
  [[nodiscard]] UtcTime to_utc(Clock::time_point t) const;

  // `directed`: the parameters of a DIRECTEDAWARD (no announcement preceded it); null for an AWARD.
  void on_award(const ManagerMessage& m, std::uint32_t award_id, UtcTime confirm_by,
                const std::vector<Param>* directed);
  void on_cancel(const ManagerMessage& m, std::uint32_t award_id, const std::string& reason);
  [[nodiscard]] std::optional<std::string> backend_declines(const ManagerMessage& m,
                                                            const std::vector<Param>* directed) const;
  void accept(const ManagerMessage& m, std::uint32_t award_id, const Skill& s);
  void refuse(const ManagerMessage& m, std::uint32_t award_id, std::string reason);
  void drop_job(const std::string& conversation, const std::string& why);
  void start_head(Clock::time_point at);
  void finish_head();
  void bid_from_backend(const Announce& a, Offer& offer);
  void end_job(const std::deque<Job>::iterator& it, bool ok, const std::string& detail,
               std::vector<Param> results = {});
  // Finishes the jobs whose work is over at `now` (tick; and at once a job that takes no time).
  void finish_due(Clock::time_point now);
  Status send(const std::string& conversation, const std::string& operation, std::uint32_t round,
              ContractorBody body);
  void ignore(std::string_view what, std::string_view reason);

  ContractorTransport* transport_;
  const Clock* clock_;
  ContractorConfig config_;
  ContractorEvents events_;
  std::unordered_map<std::string, Offer> offers_;  // by conversation id
  std::deque<Job> jobs_;
  Clock::time_point next_purge_{};
  std::mt19937_64 rng_;
  ContractorStats stats_;
  std::string last_ignored_;
  log::Logger log_;
};

}  // namespace sf::negotiation
