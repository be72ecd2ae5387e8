// The box uploader's and downloader's gateways: one handshake per job
// (registers.hpp, transfer_plc). The uploader's job puts an empty box of a
// catalog type on the line and reports its id; the downloader's takes the box
// at its station off and reports the inspection (weight, candies per type).
#include <fmt/format.h>

#include "device_logic.hpp"
#include "handshake.hpp"
#include "sf/factory/conveying.hpp"

namespace sf::factory::gateway {

namespace {

namespace tp = line::transfer_plc;
using line::FaultCode;

class TransferLogic final : public DeviceLogic {
 public:
  explicit TransferLogic(const LogicContext& c)
      : config_(c.config),
        layout_(c.layout),
        upload_(c.config.kind == GatewayKind::uploader),
        spec_(upload_ ? c.layout.uploader : c.layout.downloader),
        handshake_(tp::kFaultCode) {}

  [[nodiscard]] std::vector<std::string> operations() const override {
    return {std::string(upload_ ? kUpload : kDownload)};
  }

  [[nodiscard]] std::vector<TagSpec> tags() const override {
    std::vector<std::string> candies;
    for (const auto& c : layout_.catalog.candy_types) {
      candies.push_back(c.name);
    }
    // Each machine shows the registers its map documents for it.
    const std::vector<std::string_view> skip =
        upload_ ? std::vector<std::string_view>{"weight", "candy_total", "candy_count[c]"}
                : std::vector<std::string_view>{"box_type"};
    return tag_specs(tp::map(), {{"candy_count[c]", candies}}, {{"weight", TagType::tenths}}, skip);
  }

  [[nodiscard]] Result<std::chrono::nanoseconds> duration(const Operation& op) const override {
    if (upload_) {
      auto type =
          int_param(op, "box_type", 0, static_cast<std::int64_t>(layout_.catalog.box_types.size()) - 1);
      if (!type) {
        return type.error();
      }
    } else {
      auto box = int_param(op, "box", 1, 0xFFFF);
      if (!box) {
        return box.error();
      }
    }
    // The machine's cycle (the layout's), and the poll that notices its end.
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::duration<double>(spec_.cycle_s)) +
           config_.modbus.poll_period;
  }

  // The uploader puts a box only on a free place; the downloader takes off only its job's
  // box (many boxes share the line: the one at its station may be another order's).
  [[nodiscard]] bool ready(const Operation& op, const PlcIo& io) const override {
    if (upload_) {
      return !io.input(tp::kBoxPresent) && io.input_register(tp::kStationBox) == 0;
    }
    return box_read(op, io, tp::kStationBox);
  }

  void begin(const Operation& op) override {
    box_type_ = static_cast<std::uint16_t>(op.param("box_type").value_or(0));
    box_ = static_cast<std::uint16_t>(op.param("box").value_or(0));
    started_ = false;
  }

  std::optional<JobResult> step(PlcIo& io, bool go) override {
    if (!started_) {
      if (!go) {
        return std::nullopt;
      }
      const std::uint16_t type = box_type_ + 1;  // the register counts catalog types from 1
      started_ = handshake_.start(io, [&](PlcIo& plc) {
        if (upload_) {
          plc.write_registers(tp::kBoxType, std::span(&type, 1));
        }
      });
      return std::nullopt;
    }
    auto code = handshake_.follow(io);
    if (!code) {
      return std::nullopt;
    }
    if (*code != FaultCode::none) {
      return JobResult{false, fmt::format("{}: {}", spec_.name, describe(*code)), {}, std::nullopt};
    }
    return upload_ ? uploaded(io) : downloaded(io);
  }

  [[nodiscard]] bool settled() const override { return !handshake_.running(); }

  [[nodiscard]] JobResult interrupted(const std::string& why) const override {
    return {false, fmt::format("{} {}", spec_.name, why), {}, std::nullopt};
  }

  void halt(PlcIo& io) override {
    handshake_.abandon(io);
    started_ = false;
  }

  bool reset(PlcIo& io) override { return handshake_.reset(io); }

  [[nodiscard]] std::string fault_text(const PlcIo& io) const override {
    return latched_fault(io, tp::kFault, tp::kFaultCode);
  }

 private:
  JobResult uploaded(const PlcIo& io) const {
    const std::uint16_t id = io.input_register(tp::kBoxId);
    const auto& type = layout_.catalog.box_types.at(box_type_);
    return {
        true, fmt::format("box {} ({}) at {}", id, type.name, spec_.station), {{"box", id}}, std::nullopt};
  }

  JobResult downloaded(const PlcIo& io) const {
    const std::uint16_t id = io.input_register(tp::kBoxId);
    const double weight = io.input_register(tp::kWeight) / 10.0;
    JobResult r{true, fmt::format("box {}: {:.1f} g", id, weight), {}, std::nullopt};
    r.results = {{"box", id}, {"weight_g", weight}, {"candy_total", io.input_register(tp::kCandyTotal)}};
    for (std::size_t c = 0; c < layout_.catalog.candy_types.size() && c < line::kMaxRepeats; ++c) {
      const auto count = io.input_register(static_cast<std::uint16_t>(tp::kCandyCount + c));
      r.results["count." + layout_.catalog.candy_types[c].name] = count;
      if (count != 0) {
        r.detail += fmt::format(", {} {}", count, layout_.catalog.candy_types[c].name);
      }
    }
    if (id != box_) {  // the box standing at the station was another one (ready() keeps this from happening)
      r.ok = false;
      r.detail = fmt::format("took box {} off instead of box {} ({})", id, box_, r.detail);
    }
    return r;
  }

  const GatewayConfig& config_;
  const line::Layout& layout_;
  bool upload_;
  const line::TransferSpec& spec_;
  Handshake handshake_;
  std::uint16_t box_type_ = 0;
  std::uint16_t box_ = 0;
  bool started_ = false;
};

}  // namespace

std::unique_ptr<DeviceLogic> make_transfer(const LogicContext& context) {
  return std::make_unique<TransferLogic>(context);
}

}  // namespace sf::factory::gateway
