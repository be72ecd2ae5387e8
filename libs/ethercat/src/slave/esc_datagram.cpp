// Datagram processing of one ESC (ET1100 datasheet section I §3 "EtherCAT
// frame processing", §4 "addressing"; ETG.1000.4 §5.4): addressing, the 14
// commands, physical and logical (FMMU) memory access and the working counter.
#include <algorithm>
#include <cstring>

#include "bits.hpp"
#include "esc_core.hpp"
#include "sf/ethercat/wkc.hpp"

namespace sf::ethercat::slave::detail {

namespace {
constexpr std::uint8_t kLastCommand = static_cast<std::uint8_t>(Command::FRMW);
constexpr std::uint8_t kStationAliasEnable = 0x01;  // DL control bit 24 = 0x0103 bit 0
}  // namespace

void EscCore::process(DatagramView dg) {
  if (static_cast<std::uint8_t>(dg.command()) > kLastCommand) {
    return;  // reserved command: forwarded untouched
  }
  const Command cmd = dg.command();
  const std::uint16_t adp = dg.adp();
  switch (addressing_of(cmd)) {
    case Addressing::none:
      return;
    case Addressing::auto_increment:
      // Every ESC increments the position; the one that sees 0 is addressed.
      dg.set_adp(static_cast<std::uint16_t>(adp + 1U));
      physical(dg, cmd, adp == 0);
      break;
    case Addressing::configured: {
      const bool alias_enabled = (mem_.get<std::uint8_t>(reg::kDlControl + 3U) & kStationAliasEnable) != 0;
      const bool hit = adp == mem_.get<std::uint16_t>(reg::kStationAddress) ||
                       (alias_enabled && adp == mem_.get<std::uint16_t>(reg::kStationAlias));
      physical(dg, cmd, hit);
      break;
    }
    case Addressing::broadcast:
      dg.set_adp(static_cast<std::uint16_t>(adp + 1U));
      physical(dg, cmd, true);
      break;
    case Addressing::logical:
      logical(dg, cmd);
      break;
  }
  dispatch_writes();
  set_irq(dg);
}

void EscCore::set_irq(DatagramView& dg) {
  // The ESC ORs its masked ECAT event request into the IRQ field (section I §6.1).
  const auto mask = mem_.get<std::uint16_t>(reg::kEcatEventMask);
  if (mask == 0) {
    return;  // the usual case: no events wanted, nothing to compute
  }
  update_event_request();
  const auto events = static_cast<std::uint16_t>(mem_.get<std::uint16_t>(reg::kEcatEventRequest) & mask);
  if (events != 0) {
    std::uint8_t* irq = dg.data().data() - 2;  // IRQ: the last 2 bytes of the datagram header
    store_le<std::uint16_t>(irq, static_cast<std::uint16_t>(load_le<std::uint16_t>(irq) | events));
  }
}

void EscCore::physical(DatagramView& dg, Command cmd, bool addressed) {
  const bool rmw = cmd == Command::ARMW || cmd == Command::FRMW;
  if (!addressed && !rmw) {
    return;
  }
  MutableByteSpan data = dg.data();
  const std::uint16_t ado = dg.ado();
  WkcAccess access;
  if (rmw) {
    // The addressed ESC reads, every other one writes what it receives.
    if (addressed) {
      access.read = ecat_read(ado, data.data(), data.size());
    } else {
      access.write = ecat_write(ado, data.data(), data.size());
    }
  } else if (reads(cmd) && writes(cmd)) {
    std::uint8_t* old = scratch_.data();
    access.read = ecat_read(ado, old, data.size());
    // xPRW write to ADO + R/W offset (0x0108); broadcast writes in place.
    const std::uint32_t write_at =
        cmd == Command::BRW ? ado : ado + std::uint32_t{mem_.get<std::uint16_t>(reg::kPhysicalRwOffset)};
    access.write = ecat_write(write_at, data.data(), data.size());
    if (access.read) {
      for (std::size_t i = 0; i < data.size(); ++i) {
        // Broadcast reads OR the data of all ESCs; others replace it.
        data[i] = cmd == Command::BRW ? static_cast<std::uint8_t>(data[i] | old[i]) : old[i];
      }
    }
  } else if (cmd == Command::BRD) {
    std::uint8_t* mine = scratch_.data();
    access.read = ecat_read(ado, mine, data.size());
    if (access.read) {
      for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = static_cast<std::uint8_t>(data[i] | mine[i]);
      }
    }
  } else if (reads(cmd)) {
    access.read = ecat_read(ado, data.data(), data.size());
  } else {
    access.write = ecat_write(ado, data.data(), data.size());
  }
  dg.add_wkc(wkc_increment(cmd, access));
}

void EscCore::logical(DatagramView& dg, Command cmd) {
  const auto mappings = fmmus_.active();
  if (mappings.empty()) {
    return;
  }
  MutableByteSpan data = dg.data();
  const std::uint64_t first = std::uint64_t{dg.address()} * 8U;
  const std::uint64_t end = first + 8U * data.size();
  // All reads see memory before this datagram's writes (an LRW returns the
  // old inputs even if a write FMMU maps the same bytes); writes take the
  // data as received, not what the reads put in.
  WkcAccess access;
  bool copied = false;
  for (const FmmuMapping& m : mappings) {
    const std::uint64_t lo = std::max(first, m.logical_bit);
    const std::uint64_t hi = std::min(end, m.logical_bit + m.bits);
    if (lo >= hi || !m.read || !reads(cmd)) {
      continue;
    }
    if (!copied) {
      std::memcpy(scratch_.data(), data.data(), data.size());
      copied = true;
    }
    access.read |= read_bits(m.physical_bit + (lo - m.logical_bit), hi - lo, scratch_.data(), lo - first);
  }
  for (const FmmuMapping& m : mappings) {
    const std::uint64_t lo = std::max(first, m.logical_bit);
    const std::uint64_t hi = std::min(end, m.logical_bit + m.bits);
    if (lo >= hi || !m.write || !writes(cmd)) {
      continue;
    }
    access.write |= write_bits(m.physical_bit + (lo - m.logical_bit), hi - lo, data.data(), lo - first);
  }
  if (access.read) {
    std::memcpy(data.data(), scratch_.data(), data.size());
  }
  dg.add_wkc(wkc_increment(cmd, access));
}

bool EscCore::read_bits(std::uint64_t physical_bit, std::uint64_t bits, std::uint8_t* dst,
                        std::uint64_t dst_bit) {
  if (physical_bit % 8 == 0 && bits % 8 == 0 && dst_bit % 8 == 0) {
    return ecat_read(static_cast<std::uint32_t>(physical_bit / 8), dst + dst_bit / 8, bits / 8);
  }
  const auto from = static_cast<std::uint32_t>(physical_bit / 8);
  const std::size_t n = (physical_bit + bits - 1) / 8 - from + 1;
  if (!ecat_read(from, scratch_bits_.data(), n)) {
    return false;
  }
  copy_bits(scratch_bits_.data(), physical_bit % 8, dst, dst_bit, bits);
  return true;
}

bool EscCore::write_bits(std::uint64_t physical_bit, std::uint64_t bits, const std::uint8_t* src,
                         std::uint64_t src_bit) {
  if (physical_bit % 8 == 0 && bits % 8 == 0 && src_bit % 8 == 0) {
    return ecat_write(static_cast<std::uint32_t>(physical_bit / 8), src + src_bit / 8, bits / 8);
  }
  // Bit-wise write: merge into what the bytes hold now (through any
  // SyncManager buffer redirection), then write whole bytes.
  const auto from = static_cast<std::uint32_t>(physical_bit / 8);
  const std::size_t n = (physical_bit + bits - 1) / 8 - from + 1;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t a = from + static_cast<std::uint32_t>(i);
    const auto hit = sms_.lookup(a, a + 1U);
    const std::uint32_t at = hit.sm >= 0 ? sms_.ecat_address(static_cast<unsigned>(hit.sm), a) : a;
    scratch_bits_[i] = at < EscMemory::kSize ? mem_.bytes[at] : 0;
  }
  copy_bits(src, src_bit, scratch_bits_.data(), physical_bit % 8, bits);
  return ecat_write(from, scratch_bits_.data(), n);
}

bool EscCore::ecat_read(std::uint32_t address, std::uint8_t* dst, std::size_t n) {
  if (n == 0) {
    return true;
  }
  before_read(address, n);
  const std::uint32_t end = address + static_cast<std::uint32_t>(n);
  bool any = false;
  for (std::uint32_t a = address; a < end;) {
    std::uint8_t* out = dst + (a - address);
    if (a >= EscMemory::kSize) {  // past the 64 KiB address space: nothing there
      std::memset(out, 0, end - a);
      any = true;
      break;
    }
    const auto hit = sms_.lookup(a, std::min<std::uint32_t>(end, EscMemory::kSize));
    if (hit.sm >= 0) {
      any |= sms_.ecat_read(mem_, static_cast<unsigned>(hit.sm), a, out, hit.end - a);
    } else {
      std::memcpy(out, mem_.at(a), hit.end - a);
      any = true;
    }
    a = hit.end;
  }
  sm_read_ = static_cast<std::uint16_t>(sm_read_ | sms_.take_read());
  after_read(address, n);
  return any;
}

bool EscCore::ecat_write(std::uint32_t address, const std::uint8_t* src, std::size_t n) {
  if (n == 0) {
    return true;
  }
  const std::uint32_t end =
      std::min<std::uint32_t>(address + static_cast<std::uint32_t>(n), EscMemory::kSize);
  bool any = address >= EscMemory::kSize;  // writes past the address space are accepted and lost
  for (std::uint32_t a = address; a < end;) {
    const auto hit = sms_.lookup(a, end);
    const std::uint8_t* in = src + (a - address);
    if (hit.sm >= 0) {
      const bool protect = (mem_.get<std::uint8_t>(reg::kEscWriteProtection) & 1U) != 0 && !esc_write_enable_;
      any |= !protect && sms_.ecat_write(mem_, static_cast<unsigned>(hit.sm), a, in, hit.end - a);
    } else {
      write_plain(a, in, hit.end - a);
      any = true;
    }
    a = hit.end;
  }
  sm_written_ = static_cast<std::uint16_t>(sm_written_ | sms_.take_written());
  return any;
}

void EscCore::write_plain(std::uint32_t address, const std::uint8_t* src, std::size_t n) {
  const std::uint32_t end = address + static_cast<std::uint32_t>(n);
  if (address < kRegisterAreaSize) {
    const std::uint32_t reg_end = std::min<std::uint32_t>(end, kRegisterAreaSize);
    write_registers(address, src, reg_end - address);
    src += reg_end - address;
    address = reg_end;
  }
  if (address >= end || address >= ram_end_) {
    return;  // beyond the process RAM nothing is stored
  }
  if ((mem_.get<std::uint8_t>(reg::kEscWriteProtection) & 1U) != 0 && !esc_write_enable_) {
    return;
  }
  std::memcpy(mem_.at(address), src, std::min(end, ram_end_) - address);
}

void EscCore::write_registers(std::uint32_t address, const std::uint8_t* src, std::size_t n) {
  // Write protection (section I §17.3): 0x0020/0x0030 stay writable; register
  // protection covers 0x0000–0x0F7F, ESC protection everything.
  const bool esc_protected =
      (mem_.get<std::uint8_t>(reg::kEscWriteProtection) & 1U) != 0 && !esc_write_enable_;
  const bool reg_protected =
      (mem_.get<std::uint8_t>(reg::kRegisterWriteProtection) & 1U) != 0 && !register_write_enable_;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t a = address + static_cast<std::uint32_t>(i);
    const RegGroup group = map_->group[a];
    const bool enable_register = a == reg::kRegisterWriteEnable || a == reg::kEscWriteEnable;
    if (!enable_register && (esc_protected || (reg_protected && a < kUserRam))) {
      continue;
    }
    if (group != RegGroup::none && write_blocked(a, group)) {
      continue;
    }
    last_written_[a] = src[i];
    const std::uint8_t mask = map_->write_mask[a];
    mem_.bytes[a] = static_cast<std::uint8_t>((mem_.bytes[a] & ~mask) | (src[i] & mask));
    if (group != RegGroup::none) {
      touched_ |= 1U << static_cast<unsigned>(group);
      if (group == RegGroup::fmmu) {
        touched_fmmu_ = static_cast<std::uint16_t>(touched_fmmu_ | (1U << ((a - reg::kFmmuBase) / 16U)));
      } else if (group == RegGroup::sm_config || group == RegGroup::sm_activate) {
        touched_sm_ = static_cast<std::uint16_t>(touched_sm_ | (1U << ((a - reg::kSyncManagerBase) / 8U)));
      }
    }
  }
  // The enable bits act for the rest of this frame.
  if ((touched_ & (1U << static_cast<unsigned>(RegGroup::register_write_enable))) != 0) {
    register_write_enable_ = (mem_.get<std::uint8_t>(reg::kRegisterWriteEnable) & 1U) != 0;
  }
  if ((touched_ & (1U << static_cast<unsigned>(RegGroup::esc_write_enable))) != 0) {
    esc_write_enable_ = (mem_.get<std::uint8_t>(reg::kEscWriteEnable) & 1U) != 0;
  }
}

}  // namespace sf::ethercat::slave::detail
