// SDO Information client (ETG.1000.6 §5.6.3): one request, then the
// response's fragments as the slave puts them into its read mailbox one
// after the other; an SDO Info Error comes back as the slave's abort.
#include <fmt/format.h>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/sdo_info.hpp"

namespace sf::ethercat::master {
namespace {

// The next SDO Information message body from the slave's read mailbox.
Result<Bytes> next_info_body(Master& m, std::size_t position) {
  auto buffer = m.read_coe_answer(
      position, [](const CoeMessage& c) { return c.coe.service == CoeService::SdoInformation; });
  if (!buffer) {
    return buffer.error();
  }
  const auto body = decode_coe(*buffer).value().body;
  return Bytes(body.begin(), body.end());
}

}  // namespace

Result<SdoAnswer<SdoInfoMessage>> Master::sdo_info_exchange(std::size_t position,
                                                            const SdoInfoMessage& request,
                                                            std::uint16_t index, std::uint8_t subindex) {
  if (position >= slaves_.size() || !slaves_[position].mailbox.coe()) {
    return make_error(Errc::unsupported, fmt::format("slave {} has no CoE mailbox", position));
  }
  const auto& general = slaves_[position].sii.general;
  if (general && (general->coe_details & sii::coe_details::kSdoInfo) == 0) {
    return make_error(Errc::unsupported,
                      fmt::format("slave {} does not offer SDO Information (SII CoE details)", position));
  }
  std::lock_guard lock(control_mutex_);
  SF_TRY(mailbox_write(position, make_sdo_info(request, next_mailbox_counter(position))));
  const auto expected = static_cast<std::uint8_t>(static_cast<unsigned>(opcode_of(request)) + 1U);
  SdoInfoReassembly reassembly;
  while (true) {
    auto body = next_info_body(*this, position);
    if (!body) {
      return body.error();
    }
    auto message = reassembly.add(*body);
    if (!message) {
      return message.error().with_context(fmt::format("slave {}", position));
    }
    if (!*message) {
      continue;  // more fragments to come
    }
    if (const auto* error = std::get_if<SdoInfoError>(&**message)) {
      return SdoAnswer<SdoInfoMessage>{SdoAbort{index, subindex, error->code}};
    }
    if (static_cast<std::uint8_t>(opcode_of(**message)) != expected) {
      return make_error(Errc::malformed,
                        fmt::format("slave {}: SDO Information answered opcode {}, expected {}", position,
                                    static_cast<unsigned>(opcode_of(**message)), expected));
    }
    return SdoAnswer<SdoInfoMessage>{std::move(**message)};
  }
}

namespace {

// Narrows an SDO Information answer to the response type T.
template <typename T>
Result<SdoAnswer<T>> narrow(Result<SdoAnswer<SdoInfoMessage>> answer) {
  if (!answer) {
    return answer.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*answer)) {
    return SdoAnswer<T>{*abort};
  }
  return SdoAnswer<T>{std::get<T>(std::get<SdoInfoMessage>(std::move(*answer)))};
}

}  // namespace

Result<SdoAnswer<std::vector<std::uint16_t>>> Master::sdo_info_od_list(std::size_t position,
                                                                       OdListType list) {
  auto answer = narrow<OdListResponse>(sdo_info_exchange(position, OdListRequest{list}, 0, 0));
  if (!answer) {
    return answer.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*answer)) {
    return SdoAnswer<std::vector<std::uint16_t>>{*abort};
  }
  return SdoAnswer<std::vector<std::uint16_t>>{std::get<OdListResponse>(std::move(*answer)).indices};
}

Result<SdoAnswer<ObjectDescription>> Master::sdo_info_object(std::size_t position, std::uint16_t index) {
  return narrow<ObjectDescription>(sdo_info_exchange(position, ObjectDescriptionRequest{index}, index, 0));
}

Result<SdoAnswer<EntryDescription>> Master::sdo_info_entry(std::size_t position, std::uint16_t index,
                                                           std::uint8_t subindex, std::uint8_t value_info) {
  return narrow<EntryDescription>(
      sdo_info_exchange(position, EntryDescriptionRequest{index, subindex, value_info}, index, subindex));
}

}  // namespace sf::ethercat::master
