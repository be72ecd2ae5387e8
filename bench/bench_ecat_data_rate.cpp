// Usable data rate of one EtherCAT cycle frame (paper §III.A, Fig. 2).
//
// For N slaves with 8 bytes of process data each, the paper's formula is
// 8N / (84 + 8N): 22.22 % at N = 3, over 90 % as N grows; a time-slice
// protocol (one frame per slave and direction, 4 bytes each) stays at
// 4 / (84 + 4) = 4.55 %. We print those next to the rate of the frame our
// codec really encodes: one LRW datagram for the whole process image, and
// the same frame with the FRMW datagram our master adds for distributed
// clocks. Wire bytes = encoded frame (padded to 60) + FCS 4 + preamble/SFD 8
// + inter-frame gap 12, i.e. the 84-byte overhead of the paper for a
// minimal frame.
#include <cstdio>
#include <vector>

#include "sf/ethercat/frame.hpp"

namespace ecat = sf::ethercat;

namespace {

constexpr std::size_t kWireExtra = 4 + 8 + 12;  // FCS, preamble + SFD, IFG

std::size_t wire_bytes(const ecat::Frame& frame) {
  auto bytes = ecat::encode(frame);
  if (!bytes) {
    std::fprintf(stderr, "encode failed: %s\n", bytes.error().describe().c_str());
    return 0;
  }
  return bytes->size() + kWireExtra;
}

ecat::Frame cycle_frame(std::size_t data_bytes, bool with_dc) {
  ecat::Frame f;
  f.datagrams.push_back({ecat::Command::LRW, 1, 0x00010000, 0, false, sf::Bytes(data_bytes), 0});
  if (with_dc) {
    f.datagrams.push_back(
        {ecat::Command::FRMW, 2, ecat::Datagram::physical(0x1001, 0x0910), 0, false, sf::Bytes(8), 0});
  }
  return f;
}

}  // namespace

int main() {
  std::printf("EtherCAT usable data rate, N slaves x 8 bytes (paper section III.A)\n");
  std::printf("%6s %8s %11s %9s %18s %9s\n", "slaves", "bytes", "wire bytes", "ours %", "paper 8N/(84+8N) %",
              "ours+DC %");
  for (std::size_t n : {1U, 2U, 3U, 4U, 8U, 16U, 32U, 64U, 128U, 180U}) {
    const std::size_t data = 8 * n;
    if (data > ecat::kMaxDatagramData - 12) {
      break;
    }
    const std::size_t wire = wire_bytes(cycle_frame(data, false));
    const std::size_t wire_dc = wire_bytes(cycle_frame(data, true));
    const double ours = 100.0 * static_cast<double>(data) / static_cast<double>(wire);
    const double paper = 100.0 * static_cast<double>(data) / static_cast<double>(84 + data);
    const double ours_dc = 100.0 * static_cast<double>(data) / static_cast<double>(wire_dc);
    std::printf("%6zu %8zu %11zu %9.2f %18.2f %9.2f\n", n, data, wire, ours, paper, ours_dc);
  }
  // Time slicing: every slave gets its own minimal frame per direction.
  ecat::Frame single;
  single.datagrams.push_back({ecat::Command::FPRW, 1, 0, 0, false, sf::Bytes(4), 0});
  const std::size_t slice_wire = wire_bytes(single);
  std::printf(
      "time-slice, 4 bytes per frame: paper 4/(84+4) = %.2f %%, minimal frame of %zu wire bytes = %.2f %%\n",
      100.0 * 4 / 88, slice_wire, 100.0 * 4 / static_cast<double>(slice_wire));
  return 0;
}
