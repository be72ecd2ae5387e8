#include "sdo_info_server.hpp"

#include <algorithm>
#include <array>

#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::slave::detail {
namespace {

SdoInfoError refuse(SdoAbortCode code) {
  return SdoInfoError{static_cast<std::uint32_t>(code)};
}

bool any_entry(const OdObject& o, std::uint16_t access_bits) {
  return std::any_of(o.entries().begin(), o.entries().end(),
                     [&](const OdEntry& e) { return (e.access & access_bits) != 0; });
}

bool in_list(const OdObject& o, OdListType type) {
  switch (type) {
    case OdListType::All:
      return true;
    case OdListType::RxPdoMappable:
      return any_entry(o, access::kRxPdo);
    case OdListType::TxPdoMappable:
      return any_entry(o, access::kTxPdo);
    default:  // no object is marked for backup or as a start-up parameter
      return false;
  }
}

// An object's data type: a VAR's own, an ARRAY's element type; a RECORD has
// no single type (0: no structure definition in this dictionary).
std::uint16_t object_data_type(const OdObject& o) {
  const OdEntry* e = o.entry(o.code() == ObjectCode::Var ? 0 : 1);
  if (e == nullptr || o.code() == ObjectCode::Record) {
    return 0;
  }
  return static_cast<std::uint16_t>(e->type);
}

}  // namespace

namespace {

// The requests a client sends (Get OD List, Get Object/Entry Description);
// anything else is not a service this server offers.
bool is_request(std::uint8_t opcode) {
  using enum SdoInfoOpCode;
  return opcode == static_cast<std::uint8_t>(GetOdListRequest) ||
         opcode == static_cast<std::uint8_t>(GetObjectDescriptionRequest) ||
         opcode == static_cast<std::uint8_t>(GetEntryDescriptionRequest);
}

}  // namespace

std::vector<Bytes> SdoInfoServer::handle(ByteSpan body, std::size_t mailbox_size) const {
  SdoInfoMessage response = refuse(SdoAbortCode::InvalidCommandSpecifier);
  if (auto header = SdoInfoHeader::decode(body); header && is_request(header->opcode)) {
    auto request = decode_sdo_info_data(header->opcode, body.subspan(kSdoInfoHeaderSize));
    response = request ? answer(*request) : SdoInfoMessage{refuse(SdoAbortCode::LengthTooLow)};
  }
  return sdo_info_fragments(response, mailbox_size);
}

SdoInfoMessage SdoInfoServer::answer(const SdoInfoMessage& request) const {
  if (const auto* r = std::get_if<OdListRequest>(&request)) {
    return od_list(r->list_type);
  }
  if (const auto* r = std::get_if<ObjectDescriptionRequest>(&request)) {
    return object_description(r->index);
  }
  if (const auto* r = std::get_if<EntryDescriptionRequest>(&request)) {
    return entry_description(*r);
  }
  return refuse(SdoAbortCode::InvalidCommandSpecifier);
}

SdoInfoMessage SdoInfoServer::od_list(OdListType type) const {
  if (static_cast<std::uint16_t>(type) > kOdListTypeMax) {
    return refuse(SdoAbortCode::UnsupportedAccess);
  }
  OdListResponse response{type, {}};
  if (type == OdListType::Lengths) {
    for (std::uint16_t list = 1; list <= kOdListTypeMax; ++list) {
      const auto n = std::count_if(od_->objects().begin(), od_->objects().end(), [&](const auto& o) {
        return in_list(*o.second, static_cast<OdListType>(list));
      });
      response.indices.push_back(static_cast<std::uint16_t>(n));
    }
    return response;
  }
  for (const auto& [index, object] : od_->objects()) {
    if (in_list(*object, type)) {
      response.indices.push_back(index);
    }
  }
  return response;
}

SdoInfoMessage SdoInfoServer::object_description(std::uint16_t index) const {
  const OdObject* o = od_->find(index);
  if (o == nullptr) {
    return refuse(SdoAbortCode::ObjectDoesNotExist);
  }
  return ObjectDescription{index, object_data_type(*o),
                           o->code() == ObjectCode::Var ? std::uint8_t{0} : o->max_subindex(),
                           static_cast<std::uint8_t>(o->code()), o->name()};
}

SdoInfoMessage SdoInfoServer::entry_description(const EntryDescriptionRequest& r) const {
  const OdObject* o = od_->find(r.index);
  if (o == nullptr) {
    return refuse(SdoAbortCode::ObjectDoesNotExist);
  }
  const OdEntry* e = o->entry(r.subindex);
  if (e == nullptr) {
    return refuse(SdoAbortCode::SubindexDoesNotExist);
  }
  // No unit, default, minimum or maximum are kept: value info 0 says the
  // response carries none of them.
  return EntryDescription{r.index,       r.subindex, 0,  static_cast<std::uint16_t>(e->type),
                          e->bit_length, e->access,  {}, e->name};
}

}  // namespace sf::ethercat::slave::detail
