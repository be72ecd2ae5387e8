#include "sf/negotiation/messages.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "support.hpp"

namespace sf::negotiation {
namespace {

using detail::Overloaded;

bool name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
         c == '.';
}

}  // namespace

std::string_view kind_name(const ContractorBody& body) {
  return std::visit(Overloaded{[](const Bid&) { return std::string_view{"BID"}; },
                               [](const Refuse&) { return std::string_view{"REFUSE"}; },
                               [](const Confirm&) { return std::string_view{"CONFIRM"}; },
                               [](const InformDone&) { return std::string_view{"INFORM-DONE"}; },
                               [](const Failure&) { return std::string_view{"FAILURE"}; }},
                    body);
}

std::string_view kind_name(const ManagerBody& body) {
  return std::visit(Overloaded{[](const Award&) { return std::string_view{"AWARD"}; },
                               [](const DirectedAward&) { return std::string_view{"DIRECTEDAWARD"}; },
                               [](const Cancel&) { return std::string_view{"CANCEL"}; }},
                    body);
}

std::uint32_t award_of(const ContractorBody& body) {
  return std::visit(
      Overloaded{[](const Bid&) { return std::uint32_t{0}; }, [](const auto& m) { return m.award_id; }},
      body);
}

std::uint32_t award_of(const ManagerBody& body) {
  return std::visit([](const auto& m) { return m.award_id; }, body);
}

std::string describe(const ContractorMessage& m) {
  return fmt::format("{} {} from {} ({} round {} award {})", kind_name(m.body), m.conversation, m.contractor,
                     m.operation, m.round, award_of(m.body));
}

std::string describe(const ManagerMessage& m) {
  return fmt::format("{} {} to {} ({} round {} award {})", kind_name(m.body), m.conversation, m.contractor,
                     m.operation, m.round, award_of(m.body));
}

std::string fit_text(std::string_view text) {
  if (text.size() <= kMaxText) {
    return std::string{text};
  }
  std::size_t cut = kMaxText;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0U) == 0x80U) {
    --cut;  // text[cut] continues a UTF-8 sequence: cut before the sequence
  }
  return std::string{text.substr(0, cut)};
}

std::string announce_topic(std::string_view operation) {
  return fmt::format("{}_ANNOUNCE", operation);
}
std::string bid_topic(std::string_view operation) {
  return fmt::format("{}_BID", operation);
}
std::string award_topic(std::string_view operation) {
  return fmt::format("{}_AWARD", operation);
}

Status validate_name(std::string_view what, std::string_view name) {
  if (name.empty() || name.size() > kMaxName || !std::all_of(name.begin(), name.end(), name_char)) {
    return Error{Errc::invalid_argument,
                 fmt::format("{} '{}' must be 1..{} characters of A-Z a-z 0-9 _ . -", what, name, kMaxName)};
  }
  return {};
}

Status validate_location(std::string_view location) {
  const bool ok =
      !location.empty() && location.size() <= kMaxName &&
      std::all_of(location.begin(), location.end(), [](char c) { return name_char(c) || c == '/'; });
  if (!ok) {
    return Error{
        Errc::invalid_argument,
        fmt::format("location '{}' must be 1..{} characters of A-Z a-z 0-9 _ . - /", location, kMaxName)};
  }
  return {};
}

Status validate_operation(std::string_view operation) {
  constexpr std::size_t kMaxOperation = kMaxName - 9;  // room for "_ANNOUNCE"
  const bool ok = !operation.empty() && operation.size() <= kMaxOperation &&
                  std::all_of(operation.begin(), operation.end(),
                              [](char c) { return name_char(c) && c != '-' && c != '.'; });
  if (!ok) {
    return Error{Errc::invalid_argument,
                 fmt::format("operation type '{}' must be 1..{} characters of A-Z a-z 0-9 _", operation,
                             kMaxOperation)};
  }
  return {};
}

Result<std::vector<std::string>> parse_operations(std::string_view list) {
  std::vector<std::string> ops;
  std::size_t start = 0;
  while (start <= list.size()) {
    const auto end = std::min(list.find(',', start), list.size());
    const auto op = list.substr(start, end - start);
    SF_TRY(validate_operation(op));
    if (std::find(ops.begin(), ops.end(), op) != ops.end()) {
      return Error{Errc::invalid_argument, fmt::format("operation type '{}' listed twice", op)};
    }
    ops.emplace_back(op);
    start = end + 1;
  }
  return ops;
}

}  // namespace sf::negotiation
