// The EtherCAT master. Like SOEM's ecx_contextt, a Master is the whole
// context: every operation is a member call, there are no globals, the master
// reaches the wire only through a Link and reads time only through a Clock.
//
// Typical start-up (bring_up() does all of it):
//   scan()                     count, address, ESC info, SII           (scan.cpp, sii.cpp)
//   request_state(PreOp)       mailbox SyncManagers, INIT → PREOP      (state.cpp)
//   configure_process_data()   PDO mapping, SM2/SM3, FMMUs, image      (pdo_mapping.cpp, configure.cpp)
//   configure_dc()             delays, offsets, drift compensation     (dc.cpp)
//   request_state(SafeOp/Op)                                           (state.cpp)
// then exchange() once per cycle (cyclic.cpp), maintain() after it to
// diagnose and recover slaves (recovery.cpp), or a CyclicRunner doing both.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/master/bus.hpp"
#include "sf/ethercat/master/process_image.hpp"
#include "sf/ethercat/master/slave_info.hpp"
#include "sf/ethercat/master/statistics.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/sdo_info.hpp"

namespace sf::ethercat::master {

struct MasterOptions {
  BusOptions bus;
  // Deadlines measured on the injected clock.
  std::chrono::nanoseconds state_timeout{std::chrono::seconds{5}};
  std::chrono::nanoseconds mailbox_timeout{std::chrono::seconds{2}};
  std::chrono::nanoseconds eeprom_timeout{std::chrono::milliseconds{100}};
  // Pause between two polls of a status register.
  std::chrono::nanoseconds poll_interval{std::chrono::microseconds{100}};
  // Where the process image starts in the logical address space.
  std::uint32_t logical_start = 0x00010000;
  // Map each slave's process-data watchdog status (0x0440) into the image.
  bool map_watchdog_status = true;
  // Process-data watchdog written to every slave (0x0420, 100 µs units with
  // the default divider); 0 leaves the slave's default.
  std::uint16_t watchdog_time = 0;
  // While something is wrong, maintain() diagnoses and probes at most this
  // often (each check costs a few acyclic frames).
  std::chrono::nanoseconds maintenance_interval{std::chrono::milliseconds{5}};
  // Diagnoses in a row a slave must miss before it counts as lost: one late answer (a loaded
  // host, an EtherCAT-in-UDP hop) is not a cut cable.
  std::uint32_t lost_after = 3;
  // Distributed clocks (dc.cpp).
  bool distributed_clocks = true;
  std::size_t dc_static_drift_frames = 15000;
  // Time between two static drift compensation frames.
  std::chrono::nanoseconds dc_static_drift_interval{std::chrono::microseconds{100}};
  // Static drift compensation skips lost frames (a sample less); this many lost in a row (each
  // after the bus's frame timeout) mean the reference is gone.
  std::size_t dc_static_drift_max_lost_in_row = 50;
  // SYNC0 cycle (0 = do not activate SYNC0); start after sync0_start_delay.
  std::chrono::nanoseconds sync0_cycle{0};
  std::chrono::nanoseconds sync0_start_delay{std::chrono::milliseconds{100}};
};

// The outcome of one cycle.
struct ExchangeResult {
  bool received = false;           // every cyclic frame came back
  std::uint16_t wkc = 0;           // sum over the process-data datagrams
  std::uint16_t expected_wkc = 0;  // what a segment with every slave in OP returns
  std::uint16_t responding = 0;    // slaves that answered the AL status broadcast
  std::uint16_t al_state_or = 0;   // the OR of every slave's AL status
  [[nodiscard]] bool ok() const { return received && wkc == expected_wkc; }
};

// Why a slave does not do its part of the cycle.
struct SlaveDiagnosis {
  std::size_t position = 0;
  bool lost = false;                 // does not answer at all
  AlStatus al_status;                // when it answers
  std::uint16_t al_status_code = 0;  // 0x0134
  std::string message;               // "slave 3 (servo): SAFEOP + ERROR, 0x001B Sync manager watchdog"
};

// What maintain() noticed about a slave, for applications that react to it
// (an HMI, the OPC UA model, a robot controller stopping its axes).
struct SlaveEvent {
  enum class Kind : std::uint8_t {
    lost,        // stopped answering
    left_state,  // answers, but fell out of the segment's state (e.g. watchdog)
    found,       // answers again at its place in the ring
    recovered,   // back in the segment's state
  };
  Kind kind = Kind::lost;
  std::size_t position = 0;
  std::string message;  // the same text as the log line
};
using SlaveEventHandler = std::function<void(const SlaveEvent&)>;

// What a slave answered to an SDO transfer: the value, or the abort it sent
// (ETG.1000.6 §5.6.2.7). Transfers that got no usable answer (timeouts,
// malformed messages) are the surrounding Result's error instead.
template <typename T>
using SdoAnswer = std::variant<T, SdoAbort>;

// "0x001B Sync manager watchdog" (the text from al_status_codes.hpp).
std::string describe_al_status_code(std::uint16_t code);

class Master {
 public:
  // Implementation details (src/master/cyclic_frame.hpp, recovery.hpp).
  struct CyclicFrame;
  struct Recovery;

  Master(Link& link, Clock& clock, MasterOptions options = {});
  ~Master();
  Master(const Master&) = delete;
  Master& operator=(const Master&) = delete;

  // ---- scan.cpp ------------------------------------------------------------
  // Resets the segment to INIT, counts the slaves (BRD 0x0000), gives slave
  // n the station address 0x1001 + n, reads ESC info, DL status and SII.
  Result<std::size_t> scan();
  [[nodiscard]] std::size_t slave_count() const { return slaves_.size(); }
  [[nodiscard]] const std::vector<SlaveInfo>& slaves() const { return slaves_; }
  // An empty SlaveInfo for a position that does not exist.
  [[nodiscard]] const SlaveInfo& slave_info(std::size_t position) const;
  static std::uint16_t station_address_of(std::size_t position) {
    return static_cast<std::uint16_t>(0x1001U + position);
  }

  // ---- sii.cpp -------------------------------------------------------------
  // Reads `words` 16-bit words of a slave's SII EEPROM from word_address,
  // through registers 0x0500–0x050F.
  Result<Bytes> read_sii(std::size_t position, std::uint32_t word_address, std::size_t words);
  // Reads the whole SII (header and category chain up to the end marker).
  Result<Bytes> read_sii_image(std::size_t position);

  // ---- coe.cpp -------------------------------------------------------------
  // CoE SDO client (ETG.1000.6 §5.6.2): expedited, normal and segmented
  // transfers are chosen by size. The *_answer forms return the slave's
  // abort typed (the transfer itself worked, the slave refused); the others
  // make it an Errc::remote error whose message carries the code and its text
  // and whose protocol_code is {kSdoAbortTable, code}.
  Result<SdoAnswer<Bytes>> sdo_upload_answer(std::size_t position, std::uint16_t index, std::uint8_t subindex,
                                             bool complete_access = false);
  // nullopt: the slave took the data.
  Result<std::optional<SdoAbort>> sdo_download_answer(std::size_t position, std::uint16_t index,
                                                      std::uint8_t subindex, ByteSpan data,
                                                      bool complete_access = false);
  Result<Bytes> sdo_upload(std::size_t position, std::uint16_t index, std::uint8_t subindex,
                           bool complete_access = false);
  Status sdo_download(std::size_t position, std::uint16_t index, std::uint8_t subindex, ByteSpan data,
                      bool complete_access = false);
  template <typename T>
  requires std::is_arithmetic_v<T> Result<T> sdo_read(std::size_t position, std::uint16_t index,
                                                      std::uint8_t subindex) {
    auto data = sdo_upload(position, index, subindex);
    if (!data) {
      return data.error();
    }
    if (data->size() < sizeof(T)) {
      return make_error(Errc::malformed, "SDO upload returned fewer bytes than the requested type");
    }
    return load_le<T>(data->data());
  }
  template <typename T>
  requires std::is_arithmetic_v<T> Status sdo_write(std::size_t position, std::uint16_t index,
                                                    std::uint8_t subindex, T value) {
    std::array<std::uint8_t, sizeof(T)> buf{};
    store_le<T>(buf.data(), value);
    return sdo_download(position, index, subindex, buf);
  }

  // ---- sdo_info.cpp ----------------------------------------------------------
  // SDO Information (ETG.1000.6 §5.6.3): the indices in an OD list, an
  // object's and an entry's description. An SDO Info Error is the slave's
  // abort; a slave whose SII does not announce the service is refused here.
  Result<SdoAnswer<std::vector<std::uint16_t>>> sdo_info_od_list(std::size_t position,
                                                                 OdListType list = OdListType::All);
  Result<SdoAnswer<ObjectDescription>> sdo_info_object(std::size_t position, std::uint16_t index);
  Result<SdoAnswer<EntryDescription>> sdo_info_entry(std::size_t position, std::uint16_t index,
                                                     std::uint8_t subindex, std::uint8_t value_info = 0);

  // ---- mailbox.cpp: raw mailbox messages over SM0 / SM1 ---------------------
  Status mailbox_write(std::size_t position, ByteSpan message);
  Result<Bytes> mailbox_read(std::size_t position, std::chrono::nanoseconds timeout);
  std::uint8_t next_mailbox_counter(std::size_t position);
  // Mailbox reads that were lost and fetched again with a repeat request.
  [[nodiscard]] std::uint64_t mailbox_repeats() const { return mailbox_repeats_; }
  // The next CoE message from the slave that `wanted` accepts (a complete
  // mailbox buffer); others (emergencies, stale answers) are skipped until
  // the mailbox timeout. A mailbox error reply is an Errc::remote error.
  Result<Bytes> read_coe_answer(std::size_t position, const std::function<bool(const CoeMessage&)>& wanted);

  // ---- pdo_mapping.cpp -----------------------------------------------------
  // The PDO mapping from CoE (0x1C12/0x1C13 and 0x16xx/0x1Axx) when the slave
  // has a CoE mailbox, else from the SII RxPDO/TxPDO categories; also from the
  // SII when the slave aborts the read of 0x1C12/0x1C13 with 0x06020000
  // (object does not exist: a fixed mapping).
  Result<PdoMapping> read_pdo_mapping(std::size_t position);
  Result<PdoMapping> read_pdo_mapping_coe(std::size_t position);
  Result<PdoMapping> read_pdo_mapping_sii(std::size_t position) const;

  // ---- configure.cpp -------------------------------------------------------
  // Reads every slave's PDO mapping, lays out the process image, writes SM2/
  // SM3 and the FMMUs (slaves must be in PREOP), builds the cyclic frames.
  Status configure_process_data();
  // Mailbox SyncManagers SM0/SM1 from SII (before INIT → PREOP).
  Status configure_mailbox(std::size_t position);

  // ---- state.cpp -----------------------------------------------------------
  // Brings every slave to `target`, one state at a time, doing what each
  // transition needs; a failure names the slave and its AL status code.
  Status request_state(AlState target);
  Status request_state(std::size_t position, AlState target);
  Result<AlStatus> read_state(std::size_t position);
  // Clears a slave's error indication (AL control error acknowledge).
  Status acknowledge_error(std::size_t position);
  // scan + PREOP + process data + DC + `target`.
  Status bring_up(AlState target = AlState::Op);

  // ---- dc.cpp --------------------------------------------------------------
  // Measures the propagation delays, picks the reference clock, writes
  // delays and offsets and runs the static drift compensation.
  Status configure_dc();
  [[nodiscard]] std::optional<std::size_t> dc_reference() const { return dc_reference_; }
  // A slave's system time difference (0x092C) as signed nanoseconds.
  Result<std::int32_t> read_dc_difference(std::size_t position);
  // The reference clock's system time as last seen in a cyclic frame.
  [[nodiscard]] std::uint64_t dc_time() const { return dc_time_; }

  // ---- cyclic.cpp ----------------------------------------------------------
  // One cycle: send the LRW frame(s) (+ FRMW 0x0910 + BRD 0x0130), receive,
  // copy inputs into the image, check the WKC, update statistics.
  ExchangeResult exchange();
  [[nodiscard]] const ExchangeResult& last_exchange() const { return last_; }
  [[nodiscard]] const CycleStatistics& statistics() const { return stats_; }
  CycleStatistics& statistics() { return stats_; }
  [[nodiscard]] std::uint16_t expected_wkc() const;
  // Bytes of the cyclic frames (Ethernet header included, no FCS), one entry
  // per frame; empty before configure_process_data().
  [[nodiscard]] std::vector<std::size_t> cyclic_frame_sizes() const;

  // ---- recovery.cpp --------------------------------------------------------
  // Reads every slave's AL status (one frame) and says who is missing or not
  // in the segment's state, by position.
  std::vector<SlaveDiagnosis> diagnose();
  // After exchange(): when the cycle was not ok, diagnoses, marks lost slaves
  // and advances their recovery (a few datagrams per call, never blocking),
  // bringing them back to the state the segment runs in.
  void maintain();
  // Called from maintain() (the cyclic thread, bus lock held): keep it short.
  void on_slave_event(SlaveEventHandler handler) { event_handler_ = std::move(handler); }
  // Slaves currently lost (by position).
  [[nodiscard]] std::vector<std::size_t> lost_slaves() const;

  // ---- process image -------------------------------------------------------
  // A view into the image; valid until the next configure_process_data().
  SlaveView slave(std::size_t position);
  // The slave's process-data watchdog as last seen in the image (0x0440 bit
  // 0 = 0: expired); nullopt when its status is not mapped.
  [[nodiscard]] std::optional<bool> watchdog_expired(std::size_t position) const;
  [[nodiscard]] MutableByteSpan image() { return image_; }
  [[nodiscard]] std::uint32_t logical_start() const { return options_.logical_start; }

  Bus& bus() { return bus_; }
  Clock& clock() { return clock_; }
  [[nodiscard]] const MasterOptions& options() const { return options_; }
  // The state the segment is meant to run in (the last request_state target).
  [[nodiscard]] AlState target_state() const { return target_state_; }

 private:
  // Where a slave is on its way back (recovery.cpp).
  enum class RecoveryStep : std::uint8_t {
    probe,        // lost: wait for it to answer in the ring again
    configure,    // found: SyncManagers, FMMUs, then request PREOP
    wait_preop,   // PREOP reached → process data, DC, request SAFEOP
    wait_safeop,  // SAFEOP reached → request OP
    wait_op,      // OP reached → done
    done,
  };

  // scan.cpp
  Status reset_segment();
  Status read_esc_info(SlaveInfo& s);
  Status read_sii_info(SlaveInfo& s);
  // state.cpp
  Status step_state(std::size_t position, AlState next);
  Status before_transition(std::size_t position, AlState from, AlState to);
  Status wait_state(std::size_t position, AlState target);
  Error state_error(std::size_t position, AlState target, const AlStatus& status);
  // sdo_info.cpp: one request and its (reassembled) response
  Result<SdoAnswer<SdoInfoMessage>> sdo_info_exchange(std::size_t position, const SdoInfoMessage& request,
                                                      std::uint16_t index, std::uint8_t subindex);
  // mailbox.cpp
  Status repeat_request(std::size_t position, std::chrono::nanoseconds timeout);
  // configure.cpp
  Status layout_image();
  Status write_process_data_config(std::size_t position);
  Status build_cyclic_frames();
  // dc.cpp
  Status latch_and_read_receive_times(std::vector<std::size_t>& dc_slaves);
  void compute_topology_and_delays(const std::vector<std::size_t>& dc_slaves);
  Status write_dc_offsets(const std::vector<std::size_t>& dc_slaves);
  Status static_drift_compensation();
  Status configure_sync0(const std::vector<std::size_t>& dc_slaves);
  Status restore_dc(std::size_t position);
  // recovery.cpp
  void recover_step(Recovery& r);
  void recovery_failed(Recovery& r, std::string_view why);
  void recovery_reached(Recovery& r, AlState reached, RecoveryStep next);
  void locate_lost_slaves();
  Result<std::vector<std::uint16_t>> read_ring();
  bool readdress(std::size_t position, std::size_t ring_position);
  void report(SlaveEvent::Kind kind, std::size_t position, std::string message);
  Status reconfigure_slave(std::size_t position);
  Result<bool> replay_startup_sdos(std::size_t position);
  Result<std::vector<std::pair<AlStatus, std::uint16_t>>> read_all_states(std::vector<bool>& answered);
  // cyclic.cpp
  std::size_t receive_cyclic(std::chrono::steady_clock::time_point sent_at, ExchangeResult& result);

  Link& link_;
  Clock& clock_;
  // Serialises set-up and mailbox transactions (which wait and poll) without
  // holding the bus lock in between, so a cyclic thread keeps running; lock
  // order: control, then bus.
  std::recursive_mutex control_mutex_;
  MasterOptions options_;
  Bus bus_;
  log::Logger log_;
  std::vector<SlaveInfo> slaves_;
  Bytes image_;
  Bytes rx_;  // receive buffer of the cyclic frames
  std::vector<CyclicFrame> frames_;
  std::vector<Recovery> recoveries_;
  std::optional<std::size_t> dc_reference_;
  std::uint64_t dc_time_ = 0;
  ExchangeResult last_;
  CycleStatistics stats_;
  AlState target_state_ = AlState::Init;
  bool process_data_configured_ = false;
  std::uint64_t mailbox_repeats_ = 0;
  Clock::time_point next_maintenance_{};
  SlaveEventHandler event_handler_;
};

}  // namespace sf::ethercat::master
