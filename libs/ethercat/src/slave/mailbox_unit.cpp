#include "mailbox_unit.hpp"

namespace sf::ethercat::slave::detail {

void MailboxUnit::reset() {
  queue_.clear();
  fragments_.clear();
  in_mailbox_.reset();
  last_.reset();
  sdo_.reset();
  last_request_counter_ = 0;
}

void MailboxUnit::queue(Bytes message) {
  if (queue_.size() >= kMaxQueued) {
    queue_.pop_front();  // a master that never reads loses the oldest
  }
  queue_.push_back(std::move(message));
}

void MailboxUnit::error(MailboxError e) {
  queue(encode_mailbox_error(e, next_counter()));
}

void MailboxUnit::on_request(ByteSpan buffer, AlState state, std::size_t reply_capacity) {
  ++requests_;
  if (buffer.size() < kMailboxHeaderSize) {
    error(MailboxError::SizeTooShort);
    return;
  }
  auto message = decode_mailbox(buffer);
  if (!message) {
    error(MailboxError::InvalidSize);
    return;
  }
  // ETG.1000.4 §5.6: a write with the same counter as the previous one is
  // the master repeating a write whose frame got lost on the way back; the
  // service was done already and must not run twice. Counter 0: no check.
  const std::uint8_t counter = message->header.counter;
  if (counter != 0 && counter == last_request_counter_) {
    ++repeated_;
    return;
  }
  last_request_counter_ = counter;
  // Only CoE is offered, and not in BOOT (there only FoE would be).
  if (message->header.type != MailboxType::CoE || state == AlState::Bootstrap) {
    error(MailboxError::UnsupportedProtocol);
    return;
  }
  auto coe = decode_coe(buffer);
  if (!coe) {
    error(message->data.size() < kCoeHeaderSize ? MailboxError::SizeTooShort : MailboxError::InvalidHeader);
    return;
  }
  fragments_.clear();  // a new request ends an SDO Information response in progress
  switch (coe->coe.service) {
    case CoeService::SdoRequest:
      serve_sdo(coe->body, state, reply_capacity);
      return;
    case CoeService::SdoInformation:
      if (coe->body.size() < kSdoInfoHeaderSize) {
        error(MailboxError::SizeTooShort);
        return;
      }
      for (auto& fragment : sdo_info_.handle(coe->body, reply_capacity)) {
        fragments_.push_back(std::move(fragment));
      }
      return;
    default:
      // ETG.1000.4 Table 30: the CoE service (PDO by mailbox, a response
      // from the master, ...) is not offered.
      error(MailboxError::ServiceNotSupported);
      return;
  }
}

void MailboxUnit::serve_sdo(ByteSpan body, AlState state, std::size_t reply_capacity) {
  std::optional<SdoResponse> response;
  if (auto request = decode_sdo_request(body); request) {
    response = sdo_.handle(*request, state, reply_capacity);
  } else {
    response = sdo_.malformed(body);
  }
  if (!response) {
    return;
  }
  if (auto reply = make_sdo_response(*response, next_counter()); reply) {
    queue(std::move(*reply));
  } else {
    error(MailboxError::NoMoreMemory);
  }
}

const Bytes* MailboxUnit::next_reply() {
  if (queue_.empty() && !fragments_.empty()) {
    queue(encode_coe(MailboxHeader{0, 0, 0, 0, MailboxType::CoE, next_counter()},
                     CoeHeader{0, CoeService::SdoInformation}, fragments_.front()));
    fragments_.pop_front();
  }
  return queue_.empty() ? nullptr : &queue_.front();
}

void MailboxUnit::push_emergency(const CoeEmergency& emergency) {
  const Bytes body = emergency.encode();
  queue(encode_coe(MailboxHeader{0, 0, 0, 0, MailboxType::CoE, next_counter()},
                   CoeHeader{0, CoeService::Emergency}, body));
}

void MailboxUnit::put_done() {
  in_mailbox_ = std::move(queue_.front());
  queue_.pop_front();
}

void MailboxUnit::read_done() {
  if (in_mailbox_) {
    last_ = std::move(in_mailbox_);
    in_mailbox_.reset();
  }
}

const Bytes* MailboxUnit::repeat() {
  if (!last_) {
    return nullptr;
  }
  // An unread reply goes back to the front of the queue, unless it is itself
  // a copy of the last one (a second repeat request before the master read
  // the first repeat): queuing it would deliver the same message twice.
  if (in_mailbox_ && *in_mailbox_ != *last_) {
    queue_.push_front(std::move(*in_mailbox_));
  }
  in_mailbox_ = last_;
  return &*in_mailbox_;
}

}  // namespace sf::ethercat::slave::detail
