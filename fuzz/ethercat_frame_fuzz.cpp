// Fuzzes the EtherCAT frame codec with arbitrary bytes: decode() and
// datagram_views() must reject or accept without reading out of bounds, agree
// with each other, and a decoded frame must survive encode() → decode().
#include <cstddef>
#include <cstdint>

#include "sf/ethercat/frame.hpp"

namespace {

void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sf::ethercat;
  const sf::ByteSpan input(data, size);
  auto frame = decode(input);

  // The in-place view works on a mutable copy, as an ESC would.
  sf::Bytes buffer(input.begin(), input.end());
  auto views = datagram_views(buffer);
  if (views) {
    for (auto& v : *views) {
      (void)v.command();
      (void)v.address();
      (void)v.irq();
      (void)v.circulating();
      auto d = v.data();
      if (!d.empty()) {
        d[0] = static_cast<std::uint8_t>(d[0] ^ 0xFFU);
        d[d.size() - 1] = static_cast<std::uint8_t>(d[d.size() - 1] + 1U);
      }
      v.add_wkc(3);
      v.set_adp(static_cast<std::uint16_t>(v.adp() + 1U));
    }
  }
  if (!frame) {
    return 0;
  }
  // Every frame decode accepts has valid length fields, so the views exist too.
  check(views.ok() && views->size() == frame->datagrams.size());

  auto encoded = encode(*frame);
  if (encoded) {
    auto again = decode(*encoded);
    check(again.ok() && *again == *frame);
  }
  return 0;
}
