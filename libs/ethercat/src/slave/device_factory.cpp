// The device models a segment spec can name, in one table.
#include <array>

#include <fmt/format.h>

#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::slave {

namespace {

template <typename Model>
std::unique_ptr<Device> make(const DeviceOptions& options) {
  return std::make_unique<Model>(options);
}

constexpr auto kModels = std::to_array<DeviceKind>({
    {kSmartControllerKind, "the paper's slave: 8 CiA 402 axes, 32 DI, 32 DO, CoE, DC",
     &make<SmartController>},
    {kServoKind, "one CiA 402 axis, CoE, DC", &make<Servo>},
    {kDigitalIoKind, "8 DI, 8 DO, no mailbox", &make<DigitalIo>},
});

constexpr auto kNames = [] {
  std::array<std::string_view, kModels.size()> names{};
  for (std::size_t i = 0; i < kModels.size(); ++i) {
    names.at(i) = kModels.at(i).name;
  }
  return names;
}();

}  // namespace

std::span<const DeviceKind> device_models() {
  return kModels;
}

std::span<const std::string_view> device_kinds() {
  return kNames;
}

Result<const DeviceKind*> find_device_model(std::string_view kind) {
  for (const auto& model : kModels) {
    if (model.name == kind) {
      return &model;
    }
  }
  return make_error(Errc::not_found,
                    fmt::format("unknown device kind \"{}\" (known: {})", kind, fmt::join(kNames, ", ")));
}

Result<std::unique_ptr<Device>> make_device(std::string_view kind, const DeviceOptions& options) {
  auto model = find_device_model(kind);
  if (!model) {
    return model.error();
  }
  return (*model)->make(options);
}

}  // namespace sf::ethercat::slave
