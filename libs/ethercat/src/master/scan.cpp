// Scan: reset the segment, count the slaves, address them by position and
// read what identifies them (ETG.1000.4 §5.3 addressing; ET1100 datasheet II).
#include <array>

#include <fmt/format.h>

#include "cyclic_frame.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

constexpr std::size_t kMaxSlaves = 1024;

}  // namespace

std::string SlaveInfo::name() const {
  auto n = sii.name();
  return n.empty() ? fmt::format("slave {}", position) : n;
}

Status Master::reset_segment() {
  // Every slave to INIT with the error indication acknowledged, FMMUs and
  // SyncManagers cleared, SYNC signals off, the EEPROM owned by EtherCAT
  // (0x0500 = 0) and the DC drift filters restarted (0x0930, datasheet II
  // §13.3: writing the speed counter start resets the filters).
  const std::uint16_t init_ack = AlControl::of(AlState::Init, true).encode();
  const Bytes fmmus(reg::kFmmuSize * reg::kMaxFmmus, 0);
  const Bytes sms(reg::kSyncManagerSize * reg::kMaxSyncManagers, 0);
  std::array<std::uint8_t, 2> al{};
  store_le(al.data(), init_ack);
  std::array<std::uint8_t, 2> speed{};
  store_le<std::uint16_t>(speed.data(), 0x1000);
  const std::array<std::uint8_t, 1> zero{0};
  const std::array<std::pair<std::uint16_t, ByteSpan>, 6> writes{{
      {reg::kAlControl, al},
      {reg::kFmmuBase, fmmus},
      {reg::kSyncManagerBase, sms},
      {reg::kDcActivation, zero},
      {reg::kSiiConfiguration, zero},
      {reg::kDcSpeedCounterStart, speed},
  }};
  for (const auto& [ado, data] : writes) {
    auto wkc = bus_.write(Command::BWR, Datagram::physical(0, ado), data);
    if (!wkc) {
      return wkc.error().with_context("reset");
    }
  }
  return {};
}

Result<std::size_t> Master::scan() {
  std::scoped_lock lock(control_mutex_, bus_.mutex());
  slaves_.clear();
  frames_.clear();
  image_.clear();
  process_data_configured_ = false;
  dc_reference_.reset();
  target_state_ = AlState::Init;

  SF_TRY(reset_segment());
  std::array<std::uint8_t, 2> type{};
  auto count = bus_.read(Command::BRD, Datagram::physical(0, reg::kType), type);
  if (!count) {
    return count.error().with_context("counting slaves");
  }
  if (*count > kMaxSlaves) {
    return make_error(Errc::limit_exceeded,
                      fmt::format("{} slaves answered, at most {} supported", *count, kMaxSlaves));
  }
  log_->info("scan: {} slaves", *count);

  slaves_.resize(*count);
  for (std::size_t p = 0; p < slaves_.size(); ++p) {
    auto& s = slaves_[p];
    s.position = static_cast<std::uint16_t>(p);
    s.station = station_address_of(p);
    std::array<std::uint8_t, 2> addr{};
    store_le(addr.data(), s.station);
    SF_TRY(bus_.write_one(Command::APWR, Bus::auto_increment_address(p), reg::kStationAddress, addr));
  }
  for (auto& s : slaves_) {
    auto st = read_esc_info(s);
    if (st) {
      st = read_sii_info(s);
    }
    if (!st) {
      return st.error().with_context(fmt::format("slave {}", s.position));
    }
    log_->info("slave {}: {} vendor 0x{:08x} product 0x{:08x} station 0x{:04x}{}{}", s.position, s.name(),
               s.sii.identity.vendor_id, s.sii.identity.product_code, s.station,
               s.mailbox.coe() ? " CoE" : "", s.esc.dc_supported() ? " DC" : "");
  }
  return slaves_.size();
}

Status Master::read_esc_info(SlaveInfo& s) {
  std::array<std::uint8_t, 10> info{};
  SF_TRY(bus_.read_one(Command::FPRD, s.station, reg::kType, info));
  s.esc.type = info[0];
  s.esc.revision = info[1];
  s.esc.build = load_le<std::uint16_t>(&info[2]);
  s.esc.fmmus = info[4];
  s.esc.sync_managers = info[5];
  s.esc.ram_kib = info[6];
  s.esc.port_descriptor = info[7];
  s.esc.features = load_le<std::uint16_t>(&info[8]);

  auto alias = bus_.fprd<std::uint16_t>(s.station, reg::kStationAlias);
  auto dl = bus_.fprd<std::uint16_t>(s.station, reg::kDlStatus);
  auto al = bus_.fprd<std::uint16_t>(s.station, reg::kAlStatus);
  for (const auto* r : {&alias, &dl, &al}) {
    if (!*r) {
      return r->error();
    }
  }
  s.alias = *alias;
  s.dl_status = DlStatus{*dl};
  s.al_status = AlStatus::decode(*al);
  s.dc.supported = s.esc.dc_supported();
  return {};
}

Status Master::read_sii_info(SlaveInfo& s) {
  auto image = read_sii_image(s.position);
  if (!image) {
    return image.error();
  }
  auto info = parse_sii(*image);
  if (!info) {
    return info.error().with_context("SII");
  }
  s.sii = std::move(*info);
  s.mailbox.rx_offset = s.sii.standard_mailbox.rx_offset;
  s.mailbox.rx_size = s.sii.standard_mailbox.rx_size;
  s.mailbox.tx_offset = s.sii.standard_mailbox.tx_offset;
  s.mailbox.tx_size = s.sii.standard_mailbox.tx_size;
  s.mailbox.protocols = s.sii.mailbox_protocols;
  s.mailbox.counter = 0;
  s.startup_sdos.clear();
  return {};
}

}  // namespace sf::ethercat::master
