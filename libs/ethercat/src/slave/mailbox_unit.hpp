// The slave's mailbox protocol layer (ETG.1000.4 §5.6, ETG.1000.6 §5.6): takes
// the message the master wrote into the write mailbox (SM0), answers CoE SDO
// requests through the SdoServer, SDO Information requests through the
// SdoInfoServer and everything else with a mailbox error, and queues replies
// (and emergencies) for the read mailbox (SM1). The fragments of a long SDO
// Information response are queued one at a time, as the master reads them.
// The last delivered reply is kept for the repeat procedure (ETG.1000.4
// §5.6.1.2).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "sdo_info_server.hpp"
#include "sdo_server.hpp"
#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/registers.hpp"

namespace sf::ethercat::slave::detail {

class MailboxUnit {
 public:
  static constexpr std::size_t kMaxQueued = 16;

  explicit MailboxUnit(ObjectDictionary& od) : sdo_(od), sdo_info_(od) {}

  // Drops queued replies and transfers (leaving PREOP, power-on).
  void reset();
  // One message from the master. `reply_capacity` is the SM1 size.
  void on_request(ByteSpan buffer, AlState state, std::size_t reply_capacity);
  void push_emergency(const CoeEmergency& emergency);

  // Delivery into SM1: the next reply to put there (nullptr if none); once
  // it is in SM1, put_done(); when the master has read it, read_done().
  const Bytes* next_reply();
  void put_done();
  void drop_front() { queue_.pop_front(); }
  void read_done();
  // Repeat request: the reply to write into SM1 again (the last one read,
  // which the master did not get), or nullptr. A reply still unread in SM1
  // goes back to the front of the queue.
  const Bytes* repeat();
  [[nodiscard]] std::size_t queued() const { return queue_.size(); }
  [[nodiscard]] std::uint64_t requests() const { return requests_; }
  [[nodiscard]] std::uint64_t repeated_requests() const { return repeated_; }

 private:
  void queue(Bytes message);
  void error(MailboxError e);
  void serve_sdo(ByteSpan body, AlState state, std::size_t reply_capacity);
  std::uint8_t next_counter() { return counter_ = next_mailbox_counter(counter_); }

  SdoServer sdo_;
  SdoInfoServer sdo_info_;
  std::deque<Bytes> queue_;
  std::deque<Bytes> fragments_;      // SDO Information fragments (CoE bodies) still to queue
  std::optional<Bytes> in_mailbox_;  // put into SM1, not yet read
  std::optional<Bytes> last_;        // last reply the master read
  std::uint8_t counter_ = 0;
  std::uint8_t last_request_counter_ = 0;  // repeat detection (0: none yet)
  std::uint64_t requests_ = 0;
  std::uint64_t repeated_ = 0;
};

}  // namespace sf::ethercat::slave::detail
