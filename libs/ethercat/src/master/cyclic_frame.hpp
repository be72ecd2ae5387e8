// The cyclic frame(s), built once by configure_process_data() and reused
// every cycle (private to the master).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {

struct Master::CyclicFrame {
  // The one LRW of this frame: a contiguous slice of the process image
  // holding whole slaves.
  struct Lrw {
    std::size_t data_offset = 0;  // of the LRW data in tx
    std::uint32_t image_offset = 0;
    std::uint32_t size = 0;
    std::uint16_t expected_wkc = 0;
    std::vector<ImageRegion> inputs;  // image regions to copy back (inputs, status)
  };

  Bytes tx;                          // the encoded frame
  std::vector<std::size_t> headers;  // offset of each datagram header in tx
  std::optional<Lrw> lrw;
  std::optional<std::size_t> dc_data;     // data offset of FRMW 0x0910 (first frame only)
  std::optional<std::size_t> state_data;  // data offset of BRD 0x0130 (first frame only)
  std::uint8_t index = 0;
  bool received = false;
};

}  // namespace sf::ethercat::master
