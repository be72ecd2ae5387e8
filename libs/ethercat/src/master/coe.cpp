// CoE SDO client (ETG.1000.6 §5.6.2, the CiA 301 SDO protocol in a mailbox):
//   upload:   initiate upload → expedited (≤ 4 bytes inline) or normal
//             (complete size + first data), then upload segments until the
//             last one, toggling bit 4 each time;
//   download: expedited for ≤ 4 bytes, else normal with as much as fits in
//             the first message and download segments for the rest.
// An abort from the slave (CoE service 2, ETG.1000.6 §5.6.2.7.1; service 3
// from slaves that get that wrong) ends the transfer: the *_answer functions
// return it typed, sdo_upload/sdo_download as an Errc::remote error with the
// code's text and the code (kSdoAbortTable).
#include <algorithm>
#include <optional>
#include <variant>

#include <fmt/format.h>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

std::string object_name(std::uint16_t index, std::uint8_t subindex) {
  return fmt::format("0x{:04x}:{:02x}", index, subindex);
}

// The slave's answer to an SDO request in a CoE message: an SDO response
// (service 3) or an abort (service 2). nullopt: not an answer (an emergency,
// another service), skipped while waiting.
std::optional<Result<SdoResponse>> sdo_answer(const CoeMessage& coe) {
  if (coe.coe.service == CoeService::SdoResponse) {
    return decode_sdo_response(coe.body);
  }
  if (coe.coe.service == CoeService::SdoRequest) {
    auto request = decode_sdo_request(coe.body);
    if (!request) {
      return Result<SdoResponse>{request.error()};
    }
    if (const auto* abort = std::get_if<SdoAbort>(&*request)) {
      return Result<SdoResponse>{SdoResponse{*abort}};
    }
  }
  return std::nullopt;
}

// Sends one SDO request and returns the slave's SDO response or abort.
Result<SdoResponse> sdo_exchange(Master& m, std::size_t position, const SdoRequest& request,
                                 std::uint16_t index, std::uint8_t subindex) {
  const auto counter = m.next_mailbox_counter(position);
  auto message = make_sdo_request(request, counter);
  if (!message) {
    return message.error();
  }
  SF_TRY(m.mailbox_write(position, *message));
  auto buffer = m.read_coe_answer(position, [](const CoeMessage& c) { return sdo_answer(c).has_value(); });
  if (!buffer) {
    return buffer.error().with_context(fmt::format("SDO {}", object_name(index, subindex)));
  }
  auto answer = *sdo_answer(decode_coe(*buffer).value());
  if (!answer) {
    return answer.error().with_context(
        fmt::format("slave {} SDO {}", position, object_name(index, subindex)));
  }
  return answer;
}

}  // namespace

Result<SdoAnswer<Bytes>> Master::sdo_upload_answer(std::size_t position, std::uint16_t index,
                                                   std::uint8_t subindex, bool complete_access) {
  if (position >= slaves_.size() || !slaves_[position].mailbox.coe()) {
    return make_error(Errc::unsupported, fmt::format("slave {} has no CoE mailbox", position));
  }
  std::lock_guard lock(control_mutex_);
  auto first = sdo_exchange(*this, position, SdoInitiateUploadRequest{index, subindex, complete_access},
                            index, subindex);
  if (!first) {
    return first.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*first)) {
    return SdoAnswer<Bytes>{*abort};
  }
  const auto* initiate = std::get_if<SdoInitiateUploadResponse>(&*first);
  if (initiate == nullptr || initiate->index != index || initiate->subindex != subindex) {
    return make_error(Errc::malformed, fmt::format("slave {}: unexpected answer to upload of {}", position,
                                                   object_name(index, subindex)));
  }
  Bytes data = initiate->data;
  if (initiate->expedited || data.size() >= initiate->complete_size) {
    return SdoAnswer<Bytes>{std::move(data)};
  }
  // Segmented: upload segments until the last one (ETG.1000.6 §5.6.2.5).
  const std::uint32_t total = initiate->complete_size;
  bool toggle = false;
  while (true) {
    auto next = sdo_exchange(*this, position, SdoUploadSegmentRequest{toggle}, index, subindex);
    if (!next) {
      return next.error();
    }
    if (const auto* abort = std::get_if<SdoAbort>(&*next)) {
      return SdoAnswer<Bytes>{*abort};
    }
    const auto* segment = std::get_if<SdoUploadSegmentResponse>(&*next);
    if (segment == nullptr || segment->toggle != toggle) {
      return make_error(Errc::malformed, fmt::format("slave {}: bad upload segment for {}", position,
                                                     object_name(index, subindex)));
    }
    data.insert(data.end(), segment->data.begin(), segment->data.end());
    if (data.size() > total) {
      return make_error(Errc::malformed,
                        fmt::format("slave {}: upload of {} sent {} bytes, announced {}", position,
                                    object_name(index, subindex), data.size(), total));
    }
    if (segment->last) {
      break;
    }
    toggle = !toggle;
  }
  if (data.size() != total) {
    return make_error(Errc::malformed,
                      fmt::format("slave {}: upload of {} ended after {} of {} bytes", position,
                                  object_name(index, subindex), data.size(), total));
  }
  return SdoAnswer<Bytes>{std::move(data)};
}

Result<std::optional<SdoAbort>> Master::sdo_download_answer(std::size_t position, std::uint16_t index,
                                                            std::uint8_t subindex, ByteSpan data,
                                                            bool complete_access) {
  if (position >= slaves_.size() || !slaves_[position].mailbox.coe()) {
    return make_error(Errc::unsupported, fmt::format("slave {} has no CoE mailbox", position));
  }
  if (data.empty()) {
    return make_error(Errc::invalid_argument, "SDO download of no data");
  }
  std::lock_guard lock(control_mutex_);
  const std::size_t mailbox_size = slaves_[position].mailbox.rx_size;
  SdoInitiateDownloadRequest request;
  request.index = index;
  request.subindex = subindex;
  request.complete_access = complete_access;
  request.complete_size = static_cast<std::uint32_t>(data.size());
  request.expedited = data.size() <= 4;
  request.size_indicated = true;
  const std::size_t first_part =
      request.expedited ? data.size() : std::min(data.size(), sdo_initiate_capacity(mailbox_size));
  request.data.assign(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(first_part));
  auto answer = sdo_exchange(*this, position, request, index, subindex);
  if (!answer) {
    return answer.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*answer)) {
    return std::optional<SdoAbort>{*abort};
  }
  const auto* initiate = std::get_if<SdoInitiateDownloadResponse>(&*answer);
  if (initiate == nullptr || initiate->index != index || initiate->subindex != subindex) {
    return make_error(Errc::malformed, fmt::format("slave {}: unexpected answer to download of {}", position,
                                                   object_name(index, subindex)));
  }
  // Segmented: the rest in download segments (ETG.1000.6 §5.6.2.3).
  const std::size_t segment_size = std::max<std::size_t>(1, sdo_segment_capacity(mailbox_size));
  bool toggle = false;
  for (std::size_t at = first_part; at < data.size(); at += segment_size) {
    SdoDownloadSegmentRequest segment;
    segment.toggle = toggle;
    const auto n = std::min(segment_size, data.size() - at);
    segment.last = at + n == data.size();
    segment.data.assign(data.begin() + static_cast<std::ptrdiff_t>(at),
                        data.begin() + static_cast<std::ptrdiff_t>(at + n));
    auto next = sdo_exchange(*this, position, segment, index, subindex);
    if (!next) {
      return next.error();
    }
    if (const auto* abort = std::get_if<SdoAbort>(&*next)) {
      return std::optional<SdoAbort>{*abort};
    }
    const auto* ack = std::get_if<SdoDownloadSegmentResponse>(&*next);
    if (ack == nullptr || ack->toggle != toggle) {
      return make_error(Errc::malformed, fmt::format("slave {}: bad download segment answer for {}", position,
                                                     object_name(index, subindex)));
    }
    toggle = !toggle;
  }
  if (!process_data_configured_) {
    // Start-up configuration (e.g. a PDO remapping): the slave loses it with
    // its power, the recovery writes it again.
    slaves_[position].startup_sdos.push_back(
        StartupSdo{index, subindex, complete_access, Bytes(data.begin(), data.end())});
  }
  return std::optional<SdoAbort>{};
}

Result<Bytes> Master::sdo_upload(std::size_t position, std::uint16_t index, std::uint8_t subindex,
                                 bool complete_access) {
  auto answer = sdo_upload_answer(position, index, subindex, complete_access);
  if (!answer) {
    return answer.error();
  }
  if (const auto* abort = std::get_if<SdoAbort>(&*answer)) {
    return sdo_abort_error(*abort, fmt::format("slave {}", position));
  }
  return std::get<Bytes>(std::move(*answer));
}

Status Master::sdo_download(std::size_t position, std::uint16_t index, std::uint8_t subindex, ByteSpan data,
                            bool complete_access) {
  auto answer = sdo_download_answer(position, index, subindex, data, complete_access);
  if (!answer) {
    return answer.error();
  }
  if (*answer) {
    return sdo_abort_error(**answer, fmt::format("slave {}", position));
  }
  return {};
}

}  // namespace sf::ethercat::master
