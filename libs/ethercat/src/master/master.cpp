#include "sf/ethercat/master/master.hpp"

#include "cyclic_frame.hpp"
#include "recovery.hpp"

namespace sf::ethercat::master {

Master::Master(Link& link, Clock& clock, MasterOptions options)
    : link_(link),
      clock_(clock),
      options_(options),
      bus_(link, clock, options.bus),
      log_(log::get("ethercat")),
      rx_(kMaxFrameSize + 64, 0) {}

Master::~Master() = default;

const SlaveInfo& Master::slave_info(std::size_t position) const {
  static const SlaveInfo none{};
  return position < slaves_.size() ? slaves_[position] : none;
}

SlaveView Master::slave(std::size_t position) {
  if (position >= slaves_.size() || !process_data_configured_) {
    return SlaveView{MutableByteSpan{}, ByteSpan{}, nullptr};
  }
  const auto& s = slaves_[position];
  return SlaveView{MutableByteSpan{image_.data() + s.image.outputs.offset, s.image.outputs.size},
                   ByteSpan{image_.data() + s.image.inputs.offset, s.image.inputs.size}, &s.pdo};
}

std::optional<bool> Master::watchdog_expired(std::size_t position) const {
  if (position >= slaves_.size() || !process_data_configured_ || slaves_[position].image.status.size == 0) {
    return std::nullopt;
  }
  return (image_[slaves_[position].image.status.offset] & 0x01U) == 0;
}

}  // namespace sf::ethercat::master
