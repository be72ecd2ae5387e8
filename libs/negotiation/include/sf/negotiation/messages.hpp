// The Contract Net messages as C++ values (the IDL in idl/cnp_messages.idl is
// their wire form; src/dds_codec.cpp converts). Kinds follow the paper
// (§IV.B): ANNOUNCE, BID, AWARD / DIRECTEDAWARD, REQUEST / INFORM, plus the
// replies a contractor owes after an award: REFUSE, CONFIRM, INFORM-DONE,
// FAILURE, and the manager's CANCEL of an award it withdrew.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"

namespace sf::negotiation {

using UtcTime = Clock::utc_time;

// Bounds of the IDL strings and sequences.
inline constexpr std::size_t kMaxName = 31;
inline constexpr std::size_t kMaxConversation = 63;
inline constexpr std::size_t kMaxText = 95;
inline constexpr std::size_t kMaxParams = 8;

struct Param {
  std::string name;
  double value = 0.0;
  friend bool operator==(const Param&, const Param&) = default;
};

struct Announce {
  std::string conversation;
  std::string product;
  std::string operation;
  std::uint32_t round = 1;
  std::vector<Param> params;
  UtcTime bid_deadline{};
};

// --- contractor -> manager, on OPx_BID ---------------------------------------
struct Bid {
  UtcTime estimated_start{};
  UtcTime estimated_finish{};
  double cost = 0.0;
  std::uint32_t queue_length = 0;
};
struct Refuse {
  std::uint32_t award_id = 0;  // 0: declines the call for proposals
  std::string reason;
};
struct Confirm {
  std::uint32_t award_id = 0;
};
struct InformDone {
  std::uint32_t award_id = 0;
  std::string result;
  std::vector<Param> results{};  // typed results: an uploaded box's id, an inspection's counts
};
struct Failure {
  std::uint32_t award_id = 0;
  std::string reason;
};
using ContractorBody = std::variant<Bid, Refuse, Confirm, InformDone, Failure>;

struct ContractorMessage {
  std::string conversation;
  std::string contractor;
  std::string operation;
  std::uint32_t round = 0;
  ContractorBody body;
};

// --- manager -> contractors, on OPx_AWARD ------------------------------------
struct Award {
  std::uint32_t award_id = 0;
  UtcTime confirm_by{};
};
struct DirectedAward {
  std::uint32_t award_id = 0;
  UtcTime confirm_by{};
  std::vector<Param> params;
};
struct Cancel {
  std::uint32_t award_id = 0;
  std::string reason;
};
using ManagerBody = std::variant<Award, DirectedAward, Cancel>;

struct ManagerMessage {
  std::string conversation;
  std::string product;
  std::string operation;
  std::string contractor;  // the addressee
  std::uint32_t round = 0;
  ManagerBody body;
};

// --- ConveyingDomain ---------------------------------------------------------
struct TransportRequest {
  std::string conversation;
  std::string product;
  std::string from;
  std::string to;
  UtcTime earliest_start{};
};

struct TransportInform {
  std::string conversation;
  std::string conveyor;
  std::string from;
  std::string to;
  std::chrono::nanoseconds transit_time{0};
  UtcTime eta{};
  std::uint16_t hops = 1;  // INFORMs (segments) this conveyor sends for the request, this one included
};

// `text` cut to the IDL's Text bound (kMaxText bytes, not inside a UTF-8 sequence): a reason or
// result too long for the wire is shortened rather than its message lost.
std::string fit_text(std::string_view text);

// "BID", "REFUSE", "CONFIRM", "INFORM-DONE", "FAILURE"
std::string_view kind_name(const ContractorBody& body);
// "AWARD", "DIRECTEDAWARD", "CANCEL"
std::string_view kind_name(const ManagerBody& body);
// The award a contractor message refers to (0 for a BID).
std::uint32_t award_of(const ContractorBody& body);
std::uint32_t award_of(const ManagerBody& body);
// One line for logs: "CONFIRM P1/OP1/1a2b.3 from M2 round 1 award 1".
std::string describe(const ContractorMessage& m);
std::string describe(const ManagerMessage& m);

// Topic names (paper §IV.B, Fig. 4).
std::string announce_topic(std::string_view operation);
std::string bid_topic(std::string_view operation);
std::string award_topic(std::string_view operation);
inline constexpr std::string_view kRequestTopic = "REQUEST";
inline constexpr std::string_view kInformTopic = "INFORM";

// A name that fits the IDL bound (1..31 characters of [A-Za-z0-9_.-]); an
// operation type also becomes part of topic names, so it is further limited
// to [A-Za-z0-9_] and 22 characters ("_ANNOUNCE" must still fit in 31).
Status validate_name(std::string_view what, std::string_view name);
// A location of the conveyor graph (a machine, a place such as Input, a belt's station
// "conveyor3/toshiba"): a name that may also hold '/'. Locations never become topic names or
// conversation ids.
Status validate_location(std::string_view location);
Status validate_operation(std::string_view operation);
Result<std::vector<std::string>> parse_operations(std::string_view comma_separated);

}  // namespace sf::negotiation
