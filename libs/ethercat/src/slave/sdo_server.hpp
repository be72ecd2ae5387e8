// CoE SDO server (ETG.1000.6 §5.6.2): expedited, normal and segmented
// download and upload, complete access, and the abort codes of Table 41,
// over an ObjectDictionary. One transfer at a time, as on a real slave: a new
// initiate request abandons a segmented transfer in progress.
#pragma once

#include <cstdint>
#include <optional>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/slave/object_dictionary.hpp"

namespace sf::ethercat::slave::detail {

class SdoServer {
 public:
  explicit SdoServer(ObjectDictionary& od) : od_(&od) {}

  // The response to one request, or nothing (the client aborted).
  // `mailbox_size` is the size of the slave→master mailbox (SM1).
  std::optional<SdoResponse> handle(const SdoRequest& request, AlState state, std::size_t mailbox_size);
  // A request whose body did not decode.
  SdoResponse malformed(ByteSpan body);
  void reset();

 private:
  SdoResponse initiate_download(const SdoInitiateDownloadRequest& r, AlState state);
  SdoResponse download_segment(const SdoDownloadSegmentRequest& r, AlState state);
  SdoResponse initiate_upload(const SdoInitiateUploadRequest& r, AlState state, std::size_t mailbox_size);
  SdoResponse upload_segment(const SdoUploadSegmentRequest& r, std::size_t mailbox_size);
  // Checks that a download to index:subindex may start (before segments come).
  AbortCode probe_download(std::uint16_t index, std::uint8_t subindex, bool complete_access,
                           std::uint32_t size, AlState state) const;
  SdoAbort abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code);

  ObjectDictionary* od_;
  struct Transfer {
    bool active = false;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    bool complete_access = false;
    std::uint32_t size = 0;
    std::size_t offset = 0;  // upload: bytes sent so far
    bool toggle = false;     // expected toggle of the next segment
    Bytes data;
  };
  Transfer download_;
  Transfer upload_;
};

}  // namespace sf::ethercat::slave::detail
