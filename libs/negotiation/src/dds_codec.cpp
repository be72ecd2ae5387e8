#include "dds_codec.hpp"

#include <cstring>
#include <string_view>

#include <fmt/format.h>

#include "support.hpp"

namespace sf::negotiation::codec {
namespace {

using detail::Overloaded;

template <std::size_t N>
Status put(char (&dst)[N], std::string_view src, std::string_view what) {
  if (src.size() >= N) {
    return Error{Errc::limit_exceeded, fmt::format("{} '{}' is longer than {} characters", what, src, N - 1)};
  }
  std::memcpy(dst, src.data(), src.size());
  dst[src.size()] = '\0';
  return {};
}

// Up to the first NUL or the array bound, whichever comes first.
template <std::size_t N>
std::string_view view(const char (&src)[N]) {
  const auto* end = static_cast<const char*>(std::memchr(src, '\0', N));
  return {src, end != nullptr ? static_cast<std::size_t>(end - src) : N};
}

template <std::size_t N>
std::string get(const char (&src)[N]) {
  return std::string{view(src)};
}

// A sample's key hash against the string it stands for: a mismatch is a malformed sample (a
// peer's bug), whose instance could be another conversation's.
Status check_hash(std::uint64_t hash, std::string_view text, std::string_view what) {
  if (hash != key_hash(text)) {
    return Error{Errc::malformed, fmt::format("{} hash {:#x} does not match '{}'", what, hash, text)};
  }
  return {};
}

std::int64_t ns(UtcTime t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

UtcTime utc(std::int64_t ns_since_epoch) {
  return UtcTime{std::chrono::duration_cast<UtcTime::duration>(std::chrono::nanoseconds{ns_since_epoch})};
}

Status put_params(sf_cnp_Params& seq, const std::vector<Param>& params, ParamStorage& storage) {
  if (params.size() > kMaxParams) {
    return Error{Errc::limit_exceeded, fmt::format("{} parameters, at most {}", params.size(), kMaxParams)};
  }
  storage.assign(params.size(), sf_cnp_Param{});
  for (std::size_t i = 0; i < params.size(); ++i) {
    SF_TRY(put(storage[i].name, params[i].name, "parameter name"));
    storage[i].value = params[i].value;
  }
  seq._buffer = storage.empty() ? nullptr : storage.data();
  seq._length = static_cast<std::uint32_t>(storage.size());
  seq._maximum = seq._length;
  seq._release = false;
  return {};
}

Result<std::vector<Param>> get_params(const sf_cnp_Params& seq) {
  if (seq._length > kMaxParams || (seq._length > 0 && seq._buffer == nullptr)) {
    return Error{Errc::malformed, fmt::format("parameter sequence of length {}", seq._length)};
  }
  std::vector<Param> out;
  for (std::uint32_t i = 0; i < seq._length; ++i) {
    out.push_back({get(seq._buffer[i].name), seq._buffer[i].value});
  }
  return out;
}

}  // namespace

bool addressed_to(const sf_cnp_ManagerMessage& s, std::string_view contractor) {
  return view(s.contractor) == contractor;
}

std::uint64_t key_hash(std::string_view text) {
  // FNV-1a, 64-bit: offset basis and prime of the FNV specification (draft-eastlake-fnv).
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

Result<sf_cnp_Announce> encode(const Announce& m, ParamStorage& storage) {
  sf_cnp_Announce s{};
  SF_TRY(put(s.conversation, m.conversation, "conversation"));
  s.conversation_hash = key_hash(m.conversation);
  SF_TRY(put(s.product, m.product, "product"));
  SF_TRY(put(s.operation, m.operation, "operation"));
  s.round = m.round;
  SF_TRY(put_params(s.params, m.params, storage));
  s.bid_deadline = ns(m.bid_deadline);
  return s;
}

Result<Announce> decode(const sf_cnp_Announce& s) {
  SF_TRY(check_hash(s.conversation_hash, view(s.conversation), "conversation"));
  auto params = get_params(s.params);
  if (!params) {
    return params.error();
  }
  return Announce{get(s.conversation), get(s.product),     get(s.operation), s.round,
                  std::move(*params),  utc(s.bid_deadline)};
}

Result<sf_cnp_ContractorMessage> encode(const ContractorMessage& m, ParamStorage& storage) {
  sf_cnp_ContractorMessage s{};
  SF_TRY(put(s.conversation, m.conversation, "conversation"));
  s.conversation_hash = key_hash(m.conversation);
  SF_TRY(put(s.contractor, m.contractor, "contractor"));
  s.contractor_hash = key_hash(m.contractor);
  SF_TRY(put(s.operation, m.operation, "operation"));
  s.round = m.round;
  auto& b = s.body;
  Status st = std::visit(
      Overloaded{[&](const Bid& x) -> Status {
                   b._d = sf_cnp_KIND_BID;
                   b._u.bid = {ns(x.estimated_start), ns(x.estimated_finish), x.cost, x.queue_length};
                   return {};
                 },
                 [&](const Refuse& x) -> Status {
                   b._d = sf_cnp_KIND_REFUSE;
                   b._u.refuse.award_id = x.award_id;
                   return put(b._u.refuse.reason, x.reason, "reason");
                 },
                 [&](const Confirm& x) -> Status {
                   b._d = sf_cnp_KIND_CONFIRM;
                   b._u.confirm.award_id = x.award_id;
                   return {};
                 },
                 [&](const InformDone& x) -> Status {
                   b._d = sf_cnp_KIND_INFORM_DONE;
                   b._u.inform_done.award_id = x.award_id;
                   SF_TRY(put(b._u.inform_done.result, x.result, "result"));
                   return put_params(b._u.inform_done.results, x.results, storage);
                 },
                 [&](const Failure& x) -> Status {
                   b._d = sf_cnp_KIND_FAILURE;
                   b._u.failure.award_id = x.award_id;
                   return put(b._u.failure.reason, x.reason, "reason");
                 }},
      m.body);
  if (!st) {
    return st.error();
  }
  return s;
}

Result<ContractorMessage> decode(const sf_cnp_ContractorMessage& s) {
  SF_TRY(check_hash(s.conversation_hash, view(s.conversation), "conversation"));
  SF_TRY(check_hash(s.contractor_hash, view(s.contractor), "contractor"));
  ContractorMessage m{get(s.conversation), get(s.contractor), get(s.operation), s.round, Bid{}};
  const auto& b = s.body;
  switch (b._d) {
    case sf_cnp_KIND_BID:
      m.body = Bid{utc(b._u.bid.estimated_start), utc(b._u.bid.estimated_finish), b._u.bid.cost,
                   b._u.bid.queue_length};
      break;
    case sf_cnp_KIND_REFUSE:
      m.body = Refuse{b._u.refuse.award_id, get(b._u.refuse.reason)};
      break;
    case sf_cnp_KIND_CONFIRM:
      m.body = Confirm{b._u.confirm.award_id};
      break;
    case sf_cnp_KIND_INFORM_DONE: {
      auto results = get_params(b._u.inform_done.results);
      if (!results) {
        return results.error();
      }
      m.body = InformDone{b._u.inform_done.award_id, get(b._u.inform_done.result), std::move(*results)};
      break;
    }
    case sf_cnp_KIND_FAILURE:
      m.body = Failure{b._u.failure.award_id, get(b._u.failure.reason)};
      break;
    default:
      return Error{Errc::malformed,
                   fmt::format("contractor message of unknown kind {}", static_cast<int>(b._d))};
  }
  return m;
}

Result<sf_cnp_ManagerMessage> encode(const ManagerMessage& m, ParamStorage& storage) {
  sf_cnp_ManagerMessage s{};
  SF_TRY(put(s.conversation, m.conversation, "conversation"));
  s.conversation_hash = key_hash(m.conversation);
  SF_TRY(put(s.product, m.product, "product"));
  SF_TRY(put(s.operation, m.operation, "operation"));
  SF_TRY(put(s.contractor, m.contractor, "contractor"));
  s.round = m.round;
  auto& b = s.body;
  Status st = std::visit(Overloaded{[&](const Award& x) -> Status {
                                      b._d = sf_cnp_KIND_AWARD;
                                      b._u.award = {x.award_id, ns(x.confirm_by)};
                                      return {};
                                    },
                                    [&](const DirectedAward& x) -> Status {
                                      b._d = sf_cnp_KIND_DIRECTED_AWARD;
                                      b._u.directed_award.award_id = x.award_id;
                                      b._u.directed_award.confirm_by = ns(x.confirm_by);
                                      return put_params(b._u.directed_award.params, x.params, storage);
                                    },
                                    [&](const Cancel& x) -> Status {
                                      b._d = sf_cnp_KIND_CANCEL;
                                      b._u.cancel.award_id = x.award_id;
                                      return put(b._u.cancel.reason, x.reason, "reason");
                                    }},
                         m.body);
  if (!st) {
    return st.error();
  }
  return s;
}

Result<ManagerMessage> decode(const sf_cnp_ManagerMessage& s) {
  SF_TRY(check_hash(s.conversation_hash, view(s.conversation), "conversation"));
  ManagerMessage m{get(s.conversation), get(s.product), get(s.operation),
                   get(s.contractor),   s.round,        Award{}};
  const auto& b = s.body;
  switch (b._d) {
    case sf_cnp_KIND_AWARD:
      m.body = Award{b._u.award.award_id, utc(b._u.award.confirm_by)};
      break;
    case sf_cnp_KIND_DIRECTED_AWARD: {
      auto params = get_params(b._u.directed_award.params);
      if (!params) {
        return params.error();
      }
      m.body = DirectedAward{b._u.directed_award.award_id, utc(b._u.directed_award.confirm_by),
                             std::move(*params)};
      break;
    }
    case sf_cnp_KIND_CANCEL:
      m.body = Cancel{b._u.cancel.award_id, get(b._u.cancel.reason)};
      break;
    default:
      return Error{Errc::malformed,
                   fmt::format("manager message of unknown kind {}", static_cast<int>(b._d))};
  }
  return m;
}

Result<sf_cnp_TransportRequest> encode(const TransportRequest& m) {
  sf_cnp_TransportRequest s{};
  SF_TRY(put(s.conversation, m.conversation, "conversation"));
  s.conversation_hash = key_hash(m.conversation);
  SF_TRY(put(s.product, m.product, "product"));
  SF_TRY(put(s.from, m.from, "from"));
  SF_TRY(put(s.to, m.to, "to"));
  s.earliest_start = ns(m.earliest_start);
  return s;
}

Result<TransportRequest> decode(const sf_cnp_TransportRequest& s) {
  SF_TRY(check_hash(s.conversation_hash, view(s.conversation), "conversation"));
  return TransportRequest{get(s.conversation), get(s.product), get(s.from), get(s.to), utc(s.earliest_start)};
}

Result<sf_cnp_TransportInform> encode(const TransportInform& m) {
  sf_cnp_TransportInform s{};
  SF_TRY(put(s.conversation, m.conversation, "conversation"));
  s.conversation_hash = key_hash(m.conversation);
  SF_TRY(put(s.conveyor, m.conveyor, "conveyor"));
  s.conveyor_hash = key_hash(m.conveyor);
  SF_TRY(put(s.from, m.from, "from"));
  SF_TRY(put(s.to, m.to, "to"));
  s.transit_time = m.transit_time.count();
  s.eta = ns(m.eta);
  s.hops = m.hops;
  return s;
}

Result<TransportInform> decode(const sf_cnp_TransportInform& s) {
  SF_TRY(check_hash(s.conversation_hash, view(s.conversation), "conversation"));
  SF_TRY(check_hash(s.conveyor_hash, view(s.conveyor), "conveyor"));
  if (s.hops == 0) {
    return Error{Errc::malformed, "INFORM of a conveyor that sends no segment (hops 0)"};
  }
  return TransportInform{
      get(s.conversation), get(s.conveyor), get(s.from), get(s.to), std::chrono::nanoseconds{s.transit_time},
      utc(s.eta),          s.hops};
}

sf_cnp_Announce announce_key(const std::string& conversation) {
  sf_cnp_Announce s{};
  s.conversation_hash = key_hash(conversation);
  return s;
}

sf_cnp_ManagerMessage manager_key(const std::string& conversation) {
  sf_cnp_ManagerMessage s{};
  s.conversation_hash = key_hash(conversation);
  return s;
}

sf_cnp_ContractorMessage contractor_key(const std::string& conversation, const std::string& contractor) {
  sf_cnp_ContractorMessage s{};
  s.conversation_hash = key_hash(conversation);
  s.contractor_hash = key_hash(contractor);
  return s;
}

sf_cnp_TransportRequest request_key(const std::string& conversation) {
  sf_cnp_TransportRequest s{};
  s.conversation_hash = key_hash(conversation);
  return s;
}

sf_cnp_TransportInform inform_key(const std::string& conversation, const std::string& conveyor) {
  sf_cnp_TransportInform s{};
  s.conversation_hash = key_hash(conversation);
  s.conveyor_hash = key_hash(conveyor);
  return s;
}

}  // namespace sf::negotiation::codec
