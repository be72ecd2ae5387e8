// Fuzzes the mailbox, CoE, SDO, SDO Information and SII decoders with arbitrary bytes. Besides
// "no crash, no out-of-bounds read", whatever decodes must encode and decode
// back to the same value.
#include <cstddef>
#include <cstdint>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/sdo_info.hpp"
#include "sf/ethercat/sii.hpp"

namespace {

using namespace sf::ethercat;

void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}

void sdo_round_trips(sf::ByteSpan body) {
  if (auto req = decode_sdo_request(body)) {
    auto bytes = encode_sdo_request(*req);
    check(bytes.ok());
    auto again = decode_sdo_request(*bytes);
    check(again.ok() && *again == *req);
  }
  if (auto resp = decode_sdo_response(body)) {
    auto bytes = encode_sdo_response(*resp);
    check(bytes.ok());
    auto again = decode_sdo_response(*bytes);
    check(again.ok() && *again == *resp);
  }
}

// SDO Information: whatever decodes encodes back to the same service data
// (names lose trailing NULs, so compare re-decoded values); the body also
// goes through the reassembly, split after its first byte.
void sdo_info_round_trips(sf::ByteSpan body) {
  if (auto header = SdoInfoHeader::decode(body)) {
    if (auto m = decode_sdo_info_data(header->opcode, body.subspan(kSdoInfoHeaderSize))) {
      const sf::Bytes data = encode_sdo_info_data(*m);
      auto again = decode_sdo_info_data(header->opcode, data);
      check(again.ok() && *again == *m);
      for (const auto& fragment : sdo_info_fragments(*m, 24)) {
        check(fragment.size() <= 24 - kMailboxHeaderSize - kCoeHeaderSize);
      }
    }
  }
  SdoInfoReassembly reassembly;
  if (!body.empty()) {
    (void)reassembly.add(body.first(1));
  }
  (void)reassembly.add(body);
  (void)reassembly.add(body);
}

void sii_round_trips(sf::ByteSpan image) {
  (void)sii_image_length(image);
  auto info = parse_sii(image, SiiParseOptions{false});
  if (!info) {
    return;
  }
  auto bytes = encode_sii(*info);
  if (!bytes) {
    return;  // e.g. several Strings categories adding up to more than 255 strings
  }
  auto again = parse_sii(*bytes);
  check(again.ok());
  if (info->size == 0) {
    again->size = 0;  // encode_sii derives a zero size word from the image length
  }
  check(*again == *info);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sf::ByteSpan input(data, size);

  if (auto msg = decode_mailbox(input)) {
    if (msg->header.type == MailboxType::Err) {
      (void)decode_mailbox_error(msg->data);
    }
  }
  if (auto coe = decode_coe(input)) {
    sdo_round_trips(coe->body);
    sdo_info_round_trips(coe->body);
    if (auto e = CoeEmergency::decode(coe->body)) {
      auto again = CoeEmergency::decode(e->encode());
      check(again.ok() && *again == *e);
    }
  }
  // The raw bytes as an SDO body too, so the fuzzer need not find a valid
  // mailbox header first.
  sdo_round_trips(input);
  sdo_info_round_trips(input);

  if (auto f = FmmuConfig::decode(input)) {
    check(FmmuConfig::decode(f->encode()).value() == *f);
  }
  if (auto s = SyncManagerConfig::decode(input)) {
    check(SyncManagerConfig::decode(s->encode()).value() == *s);
  }
  sii_round_trips(input);
  return 0;
}
