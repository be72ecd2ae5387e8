#include "sdo_server.hpp"

#include <algorithm>
#include <variant>

#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::slave::detail {

namespace {
constexpr std::uint32_t code(SdoAbortCode c) {
  return static_cast<std::uint32_t>(c);
}
}  // namespace

void SdoServer::reset() {
  download_ = Transfer{};
  upload_ = Transfer{};
}

SdoAbort SdoServer::abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t abort_code) {
  reset();
  return SdoAbort{index, subindex, abort_code};
}

SdoResponse SdoServer::malformed(ByteSpan body) {
  const std::uint16_t index = body.size() >= 3 ? load_le<std::uint16_t>(body.data() + 1) : 0;
  const std::uint8_t subindex = body.size() >= 4 ? body[3] : 0;
  return abort(index, subindex, code(SdoAbortCode::InvalidCommandSpecifier));
}

std::optional<SdoResponse> SdoServer::handle(const SdoRequest& request, AlState state,
                                             std::size_t mailbox_size) {
  if (const auto* r = std::get_if<SdoInitiateDownloadRequest>(&request)) {
    return initiate_download(*r, state);
  }
  if (const auto* r = std::get_if<SdoDownloadSegmentRequest>(&request)) {
    return download_segment(*r, state);
  }
  if (const auto* r = std::get_if<SdoInitiateUploadRequest>(&request)) {
    return initiate_upload(*r, state, mailbox_size);
  }
  if (const auto* r = std::get_if<SdoUploadSegmentRequest>(&request)) {
    return upload_segment(*r, mailbox_size);
  }
  reset();  // the client aborted: no answer
  return std::nullopt;
}

AbortCode SdoServer::probe_download(std::uint16_t index, std::uint8_t subindex, bool complete_access,
                                    std::uint32_t size, AlState state) const {
  const OdObject* obj = od_->find(index);
  if (obj == nullptr) {
    return code(SdoAbortCode::ObjectDoesNotExist);
  }
  if (complete_access) {
    return obj->code() == ObjectCode::Var || subindex > 1 ? code(SdoAbortCode::UnsupportedAccess) : 0;
  }
  const OdEntry* e = obj->entry(subindex);
  if (e == nullptr) {
    return code(SdoAbortCode::SubindexDoesNotExist);
  }
  if (!e->writable(state)) {
    return (e->access & access::kWrite) == 0 ? code(SdoAbortCode::ReadOnly)
                                             : code(SdoAbortCode::CannotTransferDeviceState);
  }
  if (e->is_string() ? size > e->bit_length / 8U : size != e->value.size()) {
    return e->is_string() ? code(SdoAbortCode::LengthTooHigh) : code(SdoAbortCode::LengthMismatch);
  }
  return 0;
}

SdoResponse SdoServer::initiate_download(const SdoInitiateDownloadRequest& r, AlState state) {
  reset();
  ByteSpan data = r.data;
  if (r.expedited && !r.size_indicated) {
    // Size not indicated: the object's own size tells how many bytes count.
    if (const OdEntry* e = od_->find(r.index, r.subindex); e != nullptr && !e->is_string()) {
      data = data.first(std::min(data.size(), e->value.size()));
    }
  }
  const auto size = r.expedited ? static_cast<std::uint32_t>(data.size()) : r.complete_size;
  if (AbortCode c = probe_download(r.index, r.subindex, r.complete_access, size, state); c != 0) {
    return abort(r.index, r.subindex, c);
  }
  if (r.expedited || r.data.size() == r.complete_size) {
    if (AbortCode c = od_->download(r.index, r.subindex, r.complete_access, data, state); c != 0) {
      return abort(r.index, r.subindex, c);
    }
    return SdoInitiateDownloadResponse{r.index, r.subindex};
  }
  download_ = Transfer{true, r.index, r.subindex, r.complete_access, r.complete_size, 0, false, r.data};
  download_.data.reserve(r.complete_size);
  return SdoInitiateDownloadResponse{r.index, r.subindex};
}

SdoResponse SdoServer::download_segment(const SdoDownloadSegmentRequest& r, AlState state) {
  if (!download_.active) {
    return abort(0, 0, code(SdoAbortCode::InvalidCommandSpecifier));
  }
  const std::uint16_t index = download_.index;
  const std::uint8_t subindex = download_.subindex;
  if (r.toggle != download_.toggle) {
    return abort(index, subindex, code(SdoAbortCode::ToggleBitNotChanged));
  }
  if (download_.data.size() + r.data.size() > download_.size) {
    return abort(index, subindex, code(SdoAbortCode::LengthTooHigh));
  }
  download_.data.insert(download_.data.end(), r.data.begin(), r.data.end());
  const bool toggle = download_.toggle;
  download_.toggle = !download_.toggle;
  if (!r.last) {
    return SdoDownloadSegmentResponse{toggle};
  }
  if (download_.data.size() != download_.size) {
    return abort(index, subindex, code(SdoAbortCode::LengthTooLow));
  }
  const AbortCode c = od_->download(index, subindex, download_.complete_access, download_.data, state);
  download_ = Transfer{};
  if (c != 0) {
    return abort(index, subindex, c);
  }
  return SdoDownloadSegmentResponse{toggle};
}

SdoResponse SdoServer::initiate_upload(const SdoInitiateUploadRequest& r, AlState state,
                                       std::size_t mailbox_size) {
  reset();
  Bytes value;
  if (AbortCode c = od_->upload(r.index, r.subindex, r.complete_access, state, value); c != 0) {
    return abort(r.index, r.subindex, c);
  }
  auto response = SdoInitiateUploadResponse::make(r.index, r.subindex, value,
                                                  sdo_initiate_capacity(mailbox_size), r.complete_access);
  if (!response.expedited && response.data.size() < value.size()) {
    upload_ = Transfer{true,
                       r.index,
                       r.subindex,
                       r.complete_access,
                       static_cast<std::uint32_t>(value.size()),
                       response.data.size(),
                       false,
                       std::move(value)};
  }
  return response;
}

SdoResponse SdoServer::upload_segment(const SdoUploadSegmentRequest& r, std::size_t mailbox_size) {
  if (!upload_.active) {
    return abort(0, 0, code(SdoAbortCode::InvalidCommandSpecifier));
  }
  if (r.toggle != upload_.toggle) {
    return abort(upload_.index, upload_.subindex, code(SdoAbortCode::ToggleBitNotChanged));
  }
  const std::size_t capacity = std::max<std::size_t>(sdo_segment_capacity(mailbox_size), 1);
  const std::size_t n = std::min(capacity, upload_.data.size() - upload_.offset);
  SdoUploadSegmentResponse response;
  response.toggle = upload_.toggle;
  response.data.assign(upload_.data.begin() + static_cast<std::ptrdiff_t>(upload_.offset),
                       upload_.data.begin() + static_cast<std::ptrdiff_t>(upload_.offset + n));
  upload_.offset += n;
  upload_.toggle = !upload_.toggle;
  response.last = upload_.offset == upload_.data.size();
  if (response.last) {
    upload_ = Transfer{};
  }
  return response;
}

}  // namespace sf::ethercat::slave::detail
