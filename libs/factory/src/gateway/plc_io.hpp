// PlcIo: a gateway's view of its device's registers (registers.hpp). Every
// poll reads each table the register map covers in one request, so the
// mirror holds the inputs and the coils read back; the logic's writes go
// straight to the device and into the mirror. The mirrored entries become the
// machine's typed Tags ("plc.exit_eye", "robot.joint3").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "sf/factory/machine.hpp"
#include "sf/line/registers.hpp"
#include "sf/modbus/client.hpp"

namespace sf::factory::gateway {

// How a register is shown: coils and discrete inputs as bool, registers as
// unsigned or signed 16-bit integers, or tenths as a double (0.1 g → g).
enum class TagType : std::uint8_t { bit, unsigned_word, signed_word, tenths };

struct TagSpec {
  std::string name;  // without the prefix: "exit_eye", "station_box.scara1", "joint3"
  modbus::Table table = modbus::Table::coils;
  std::uint16_t address = 0;
  TagType type = TagType::bit;
  std::string unit{};  // Tag::unit of the value as shown (after scaling)
};

// An entry repeated per station, candy type or joint (kRepeatBase + index):
// `name[k]` becomes "name.<label>" per label, or "name<index>" when numbered.
struct Repeat {
  std::string_view entry;  // "station_eye[k]"
  std::vector<std::string> labels;
  bool numbered = false;
};

// The tags of a register map: every entry once, repeated entries expanded,
// `skip` left out, `types` overriding the table's own type.
std::vector<TagSpec> tag_specs(std::span<const line::RegisterEntry> map, const std::vector<Repeat>& repeats,
                               const std::vector<std::pair<std::string_view, TagType>>& types = {},
                               const std::vector<std::string_view>& skip = {});

class PlcIo {
 public:
  PlcIo(modbus::Client& client, std::string prefix, std::vector<TagSpec> specs);

  // Reads every table the tags cover, one request each; the first failure ends the read and
  // leaves the mirror as it was.
  modbus::ClientStatus read();
  [[nodiscard]] bool has_values() const { return read_once_; }

  [[nodiscard]] bool bit(modbus::Table table, std::uint16_t address) const;
  [[nodiscard]] std::uint16_t word(modbus::Table table, std::uint16_t address) const;
  [[nodiscard]] bool input(std::uint16_t address) const {
    return bit(modbus::Table::discrete_inputs, address);
  }
  [[nodiscard]] bool coil(std::uint16_t address) const { return bit(modbus::Table::coils, address); }
  [[nodiscard]] std::uint16_t input_register(std::uint16_t address) const {
    return word(modbus::Table::input_registers, address);
  }
  // An input register that read the same on the last two polls, else 0: a tag
  // reader's reading, so a box passing by on a running belt is not taken as in place.
  [[nodiscard]] std::uint16_t steady_input_register(std::uint16_t address) const;

  // Writes. After a failed write the others of the same poll are skipped; write_error() says why.
  void write_coil(std::uint16_t address, bool on);
  // Writes the coil only when the mirror (the value read back) differs.
  void ensure_coil(std::uint16_t address, bool on);
  void write_registers(std::uint16_t address, std::span<const std::uint16_t> values);
  [[nodiscard]] bool write_failed() const { return write_error_.has_value(); }
  // The first failed write since the last call, and forgets it.
  std::optional<modbus::ClientError> take_write_error();

  // The mirrored values, named "<prefix>.<tag>", with the quality given.
  [[nodiscard]] std::vector<Tag> tags(Tag::Quality quality, const std::string& reason) const;

 private:
  struct Block {
    std::uint16_t start = 0;
    std::uint16_t count = 0;
    std::vector<std::uint16_t> values;  // bits as 0/1
  };
  [[nodiscard]] const Block& block(modbus::Table table) const {
    return blocks_[static_cast<std::size_t>(table)];
  }
  Block& block(modbus::Table table) { return blocks_[static_cast<std::size_t>(table)]; }
  void store(modbus::Table table, std::uint16_t address, std::uint16_t value);

  modbus::Client* client_;
  std::string prefix_;
  std::vector<TagSpec> specs_;
  std::array<Block, 4> blocks_{};
  std::vector<std::uint16_t> last_input_registers_;  // the poll before, for steady_input_register()
  std::optional<modbus::ClientError> write_error_;
  bool read_once_ = false;
};

}  // namespace sf::factory::gateway
