// Working-counter rules (ET1100 datasheet section I, "Working Counter"; ETG.1000.4
// §5.4.2). One pure function serves both sides: the emulated ESC adds
// wkc_increment() to each datagram it processes, and the master compares the
// returned WKC with expected_wkc() to see whether every slave did its part.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sf/ethercat/frame.hpp"

namespace sf::ethercat {

// What one ESC did with one datagram: whether its read part and its write
// part succeeded (an address or FMMU matched and access was permitted).
struct WkcAccess {
  bool read = false;
  bool write = false;
};

// The increment one ESC adds to a datagram's WKC:
//   read commands (APRD FPRD BRD LRD):   +1 on a successful read
//   write commands (APWR FPWR BWR LWR):  +1 on a successful write
//   read-write (APRW FPRW BRW LRW):      +1 read, +2 write, +3 both
//   ARMW/FRMW: the addressed slave reads (+1), every other slave writes (+1)
//   NOP: 0
// A part the command does not have (e.g. write for APRD) is ignored.
std::uint16_t wkc_increment(Command command, WkcAccess access);

// The WKC the master expects back after the frame passed the whole segment:
// reading_slaves ESCs performed the read part, writing_slaves the write part.
// For LRW with r readers and w writers that is r + 2w; for ARMW/FRMW with one
// reference slave and n-1 others, expected_wkc(c, 1, n - 1) = n.
std::uint16_t expected_wkc(Command command, std::size_t reading_slaves, std::size_t writing_slaves);

}  // namespace sf::ethercat
