// Process-data configuration (ETG.1000.4 §6.6 FMMU, §6.7 SyncManager; ET1100
// datasheet II §11–12): lay the slaves' outputs, inputs and watchdog status
// one after the other into one logical address space, point a write FMMU at
// SM2 (outputs), a read FMMU at SM3 (inputs) and, where an FMMU is free, a
// read FMMU at the process-data watchdog status (0x0440), and build the
// frames that carry the image every cycle.
#include <algorithm>

#include <fmt/format.h>

#include "cyclic_frame.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/wkc.hpp"

namespace sf::ethercat::master {
namespace {

// Room for datagrams in one frame, after the Ethernet and EtherCAT headers.
constexpr std::size_t kFrameRoom = kMaxFrameSize - kEthernetHeaderSize - kEcatHeaderSize;

const SiiSyncManager* sii_sm(const SiiInfo& sii, SiiSyncManagerType type, unsigned& number) {
  for (std::size_t i = 0; i < sii.sync_managers.size(); ++i) {
    if (sii.sync_managers[i].type == type) {
      number = static_cast<unsigned>(i);
      return &sii.sync_managers[i];
    }
  }
  return nullptr;
}

// The FMMU to use for `usage`: the one the SII names for it, else the first
// that is neither named for something else nor taken.
std::optional<unsigned> pick_fmmu(const SlaveInfo& s, SiiFmmuUsage usage, std::vector<bool>& taken) {
  for (std::size_t i = 0; i < s.sii.fmmus.size() && i < taken.size(); ++i) {
    if (s.sii.fmmus[i] == usage && !taken[i]) {
      taken[i] = true;
      return static_cast<unsigned>(i);
    }
  }
  for (std::size_t i = 0; i < taken.size(); ++i) {
    const bool named = i < s.sii.fmmus.size() && s.sii.fmmus[i] != SiiFmmuUsage::unused;
    if (!taken[i] && !named) {
      taken[i] = true;
      return static_cast<unsigned>(i);
    }
  }
  return std::nullopt;
}

// Whole slaves from `first` on, as many as fit in `room`; returns the first
// slave left out and describes their LRW in `lrw`.
std::size_t plan_lrw(const std::vector<SlaveInfo>& slaves, std::size_t first, std::size_t room,
                     Master::CyclicFrame::Lrw& lrw) {
  std::size_t last = first;
  std::size_t readers = 0;
  std::size_t writers = 0;
  lrw.image_offset = first < slaves.size() ? slaves[first].image.begin() : 0;
  while (last < slaves.size() && slaves[last].image.end() - lrw.image_offset + kDatagramOverhead <= room) {
    const auto& img = slaves[last].image;
    writers += img.outputs.size > 0 ? 1U : 0U;
    readers += (img.inputs.size + img.status.size) > 0 ? 1U : 0U;
    for (const auto& r : {img.inputs, img.status}) {
      if (r.size > 0) {
        lrw.inputs.push_back(r);
      }
    }
    ++last;
  }
  lrw.size = last > first ? slaves[last - 1].image.end() - lrw.image_offset : 0;
  lrw.expected_wkc = expected_wkc(Command::LRW, readers, writers);
  return last;
}

// Encodes the frame once and notes where each datagram's data lies in it.
Result<Master::CyclicFrame> make_cyclic_frame(const Frame& f, Master::CyclicFrame::Lrw lrw) {
  Master::CyclicFrame frame;
  auto encoded = encode(f);
  if (!encoded) {
    return encoded.error().with_context("cyclic frame");
  }
  frame.tx = std::move(*encoded);
  auto views = datagram_views(frame.tx);
  if (!views) {
    return views.error();
  }
  for (const auto& v : *views) {
    const auto data_offset = static_cast<std::size_t>(v.data().data() - frame.tx.data());
    frame.headers.push_back(data_offset - kDatagramHeaderSize);
    if (v.command() == Command::BRD) {
      frame.state_data = data_offset;
    } else if (v.command() == Command::FRMW) {
      frame.dc_data = data_offset;
    } else {
      lrw.data_offset = data_offset;
    }
  }
  if (lrw.size > 0) {
    frame.lrw = std::move(lrw);
  }
  return frame;
}

}  // namespace

Status Master::configure_process_data() {
  std::scoped_lock lock(control_mutex_, bus_.mutex());
  if (slaves_.empty()) {
    return make_error(Errc::state, "no slaves: scan first");
  }
  for (std::size_t p = 0; p < slaves_.size(); ++p) {
    auto mapping = read_pdo_mapping(p);
    if (!mapping) {
      return mapping.error().with_context(fmt::format("slave {} PDO mapping", p));
    }
    slaves_[p].pdo = std::move(*mapping);
  }
  SF_TRY(layout_image());
  for (std::size_t p = 0; p < slaves_.size(); ++p) {
    auto st = write_process_data_config(p);
    if (!st) {
      return st.error().with_context(fmt::format("slave {} ({})", p, slaves_[p].name()));
    }
  }
  SF_TRY(build_cyclic_frames());
  process_data_configured_ = true;
  log_->info("process image: {} bytes in {} frame(s), expected WKC {}", image_.size(), frames_.size(),
             expected_wkc());
  return {};
}

Status Master::layout_image() {
  std::uint32_t offset = 0;
  for (auto& s : slaves_) {
    s.image = SlaveImage{};
    s.image.outputs = ImageRegion{offset, s.pdo.output_bytes()};
    offset += s.image.outputs.size;
    s.image.inputs = ImageRegion{offset, s.pdo.input_bytes()};
    offset += s.image.inputs.size;
    const std::size_t fmmus_needed = (s.image.outputs.size ? 1U : 0U) + (s.image.inputs.size ? 1U : 0U);
    const bool status =
        options_.map_watchdog_status && s.image.outputs.size > 0 && s.esc.fmmus > fmmus_needed;
    s.image.status = ImageRegion{offset, status ? 1U : 0U};
    offset += s.image.status.size;
    if (s.image.end() - s.image.begin() > kFrameRoom - 3 * kDatagramOverhead - 10) {
      return make_error(Errc::limit_exceeded,
                        fmt::format("slave {}: {} bytes of process data do not fit a frame", s.position,
                                    s.image.end() - s.image.begin()));
    }
  }
  image_.assign(offset, 0);
  return {};
}

Status Master::write_process_data_config(std::size_t position) {
  const auto& s = slaves_[position];
  std::vector<bool> taken(s.esc.fmmus, false);
  struct Part {
    ImageRegion region;
    SiiSyncManagerType sm_type = SiiSyncManagerType::unused;
    SiiFmmuUsage usage = SiiFmmuUsage::unused;
    std::uint8_t fmmu_type = 0;
  };
  for (const auto& part :
       {Part{s.image.outputs, SiiSyncManagerType::outputs, SiiFmmuUsage::outputs, kFmmuWrite},
        Part{s.image.inputs, SiiSyncManagerType::inputs, SiiFmmuUsage::inputs, kFmmuRead}}) {
    unsigned sm_number = 0;
    const auto* sm = sii_sm(s.sii, part.sm_type, sm_number);
    if (sm == nullptr) {
      if (part.region.size == 0) {
        continue;
      }
      return make_error(Errc::unsupported, "SII has no SyncManager for its process data");
    }
    const bool out = part.sm_type == SiiSyncManagerType::outputs;
    auto config = SyncManagerConfig::make(
        sm->start, static_cast<std::uint16_t>(part.region.size), SyncManagerMode::buffered,
        out ? SyncManagerDirection::write : SyncManagerDirection::read, part.region.size > 0);
    if (sm->control != 0) {
      config.control = sm->control;
    }
    SF_TRY(bus_.write_one(Command::FPWR, s.station, reg::sync_manager(sm_number), config.encode()));
    if (part.region.size == 0) {
      continue;
    }
    auto fmmu = pick_fmmu(s, part.usage, taken);
    if (!fmmu) {
      return make_error(Errc::unsupported, fmt::format("not enough FMMUs ({})", s.esc.fmmus));
    }
    const auto f = FmmuConfig::bytes(options_.logical_start + part.region.offset, sm->start,
                                     static_cast<std::uint16_t>(part.region.size), part.fmmu_type);
    SF_TRY(bus_.write_one(Command::FPWR, s.station, reg::fmmu(*fmmu), f.encode()));
  }
  if (s.image.status.size > 0) {
    auto fmmu = pick_fmmu(s, SiiFmmuUsage::sm_status, taken);
    if (fmmu) {
      const auto f = FmmuConfig::bytes(options_.logical_start + s.image.status.offset,
                                       reg::kWatchdogStatusProcessData, 1, kFmmuRead);
      SF_TRY(bus_.write_one(Command::FPWR, s.station, reg::fmmu(*fmmu), f.encode()));
    }
  }
  if (options_.watchdog_time != 0) {
    SF_TRY(bus_.fpwr<std::uint16_t>(s.station, reg::kWatchdogTimeProcessData, options_.watchdog_time));
  }
  return {};
}

Status Master::build_cyclic_frames() {
  frames_.clear();
  std::size_t first = 0;  // first slave not yet in a frame
  do {
    Frame f;
    f.source = link_.mac();
    std::size_t room = kFrameRoom;
    if (frames_.empty()) {
      // AL status of every slave, ORed (BRD), and the reference clock's time
      // for the others (FRMW 0x0910, ETG.1000.4 §9.1.3.6 drift compensation).
      f.datagrams.push_back(
          Datagram{Command::BRD, 0, Datagram::physical(0, reg::kAlStatus), 0, false, Bytes(2), 0});
      room -= 2 + kDatagramOverhead;
      if (dc_reference_) {
        f.datagrams.push_back(Datagram{
            Command::FRMW, 0, Datagram::physical(slaves_[*dc_reference_].station, reg::kDcSystemTime), 0,
            false, Bytes(8), 0});
        room -= 8 + kDatagramOverhead;
      }
    }
    CyclicFrame::Lrw lrw;
    const std::size_t last = plan_lrw(slaves_, first, room, lrw);
    if (last == first && first < slaves_.size() &&
        slaves_[first].image.end() > slaves_[first].image.begin()) {
      return make_error(Errc::limit_exceeded,
                        fmt::format("slave {}'s process data does not fit a frame", first));
    }
    first = last;
    if (lrw.size > 0) {
      f.datagrams.push_back(
          Datagram{Command::LRW, 0, options_.logical_start + lrw.image_offset, 0, false, Bytes(lrw.size), 0});
    }
    if (f.datagrams.empty()) {
      continue;  // slaves without process data at the end
    }
    auto frame = make_cyclic_frame(f, lrw);
    if (!frame) {
      return frame.error();
    }
    frames_.push_back(std::move(*frame));
  } while (first < slaves_.size());
  return {};
}

std::uint16_t Master::expected_wkc() const {
  std::uint32_t sum = 0;
  for (const auto& f : frames_) {
    sum += f.lrw ? f.lrw->expected_wkc : 0U;
  }
  return static_cast<std::uint16_t>(sum);
}

}  // namespace sf::ethercat::master
