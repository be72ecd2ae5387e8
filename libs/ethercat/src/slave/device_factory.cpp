#include <array>

#include <fmt/format.h>

#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::slave {

namespace {
constexpr std::array<std::string_view, 3> kKinds = {kSmartControllerKind, kServoKind, kDigitalIoKind};
}

std::span<const std::string_view> device_kinds() {
  return kKinds;
}

Result<std::unique_ptr<Device>> make_device(std::string_view kind, const DeviceOptions& options) {
  if (kind == kSmartControllerKind) {
    return std::unique_ptr<Device>(std::make_unique<SmartController>(options));
  }
  if (kind == kServoKind) {
    return std::unique_ptr<Device>(std::make_unique<Servo>(options));
  }
  if (kind == kDigitalIoKind) {
    return std::unique_ptr<Device>(std::make_unique<DigitalIo>(options));
  }
  return make_error(Errc::not_found,
                    fmt::format("unknown device kind \"{}\" (known: {})", kind, fmt::join(kKinds, ", ")));
}

}  // namespace sf::ethercat::slave
