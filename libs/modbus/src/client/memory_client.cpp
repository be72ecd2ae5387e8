#include "sf/modbus/memory_client.hpp"

#include <fmt/format.h>

#include "request_path.hpp"

namespace sf::modbus {

ClientResult<Client::Reply> MemoryClient::transact(const Transaction& transaction) {
  detail::PduBuffer pdu{};
  const std::size_t length = detail::encode_request(transaction, pdu);
  const detail::Decoded decoded =
      detail::decode_request(options_.unit_id, std::span<const std::uint8_t>(pdu.data(), length));
  Reply reply;
  detail::Verdict verdict;
  {
    const std::lock_guard lock(device_.mutex());
    verdict = detail::admit(device_, decoded);
    if (verdict.kind == detail::Verdict::Kind::answer) {
      detail::apply(device_.bank(), decoded.request, reply);
      if (decoded.request.writes()) {
        device_.after_write(decoded.request);
      }
    }
  }
  switch (verdict.kind) {
    case detail::Verdict::Kind::answer:
      return reply;
    case detail::Verdict::Kind::exception:
      return ClientError::from_exception(verdict.exception, decoded.request.describe());
    case detail::Verdict::Kind::silent:
      break;
  }
  // The device does not answer: the request costs the response timeout, as over TCP.
  if (options_.clock != nullptr) {
    options_.clock->sleep_until(options_.clock->now() + options_.response_timeout);
  }
  return ClientError(Errc::timeout, fmt::format("{}: no response within {} ms", decoded.request.describe(),
                                                options_.response_timeout.count()));
}

}  // namespace sf::modbus
