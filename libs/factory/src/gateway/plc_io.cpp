// PlcIo (plc_io.hpp): the register mirror, the writes and the tags.
#include "plc_io.hpp"

#include <algorithm>

namespace sf::factory::gateway {

using modbus::Table;

namespace {

TagType table_type(Table table) {
  return table == Table::coils || table == Table::discrete_inputs ? TagType::bit : TagType::unsigned_word;
}

bool is_bits(Table table) {
  return table == Table::coils || table == Table::discrete_inputs;
}

}  // namespace

std::vector<TagSpec> tag_specs(std::span<const line::RegisterEntry> map, const std::vector<Repeat>& repeats,
                               const std::vector<std::pair<std::string_view, TagType>>& types,
                               const std::vector<std::string_view>& skip) {
  std::vector<TagSpec> out;
  for (const auto& e : map) {
    if (std::find(skip.begin(), skip.end(), e.name) != skip.end()) {
      continue;
    }
    TagType type = table_type(e.table);
    for (const auto& [name, t] : types) {
      type = name == e.name ? t : type;
    }
    auto repeat =
        std::find_if(repeats.begin(), repeats.end(), [&](const Repeat& r) { return r.entry == e.name; });
    if (repeat == repeats.end()) {
      out.push_back({std::string(e.name), e.table, e.address, type});
      continue;
    }
    const std::string base(e.name.substr(0, e.name.find('[')));
    const std::size_t n = std::min<std::size_t>(repeat->labels.size(), line::kMaxRepeats);
    for (std::size_t i = 0; i < n; ++i) {
      std::string name = repeat->numbered ? base + std::to_string(i) : base + "." + repeat->labels[i];
      out.push_back({std::move(name), e.table, static_cast<std::uint16_t>(e.address + i), type});
    }
  }
  return out;
}

PlcIo::PlcIo(modbus::Client& client, std::string prefix, std::vector<TagSpec> specs)
    : client_(&client), prefix_(std::move(prefix)), specs_(std::move(specs)) {
  for (const auto& s : specs_) {
    Block& b = block(s.table);
    if (b.count == 0) {
      b.start = s.address;
      b.count = 1;
      continue;
    }
    const auto end = std::max<int>(b.start + b.count, s.address + 1);
    b.start = std::min(b.start, s.address);
    b.count = static_cast<std::uint16_t>(end - b.start);
  }
  for (auto& b : blocks_) {
    b.values.assign(b.count, 0);
  }
}

modbus::ClientStatus PlcIo::read() {
  std::array<std::vector<std::uint16_t>, 4> fresh;
  for (std::size_t t = 0; t < blocks_.size(); ++t) {
    const Block& b = blocks_[t];
    if (b.count == 0) {
      continue;
    }
    const auto table = static_cast<Table>(t);
    if (is_bits(table)) {
      auto bits = table == Table::coils ? client_->read_coils(b.start, b.count)
                                        : client_->read_discrete_inputs(b.start, b.count);
      if (!bits) {
        return bits.error();
      }
      fresh[t].assign(bits->begin(), bits->end());
    } else {
      auto words = table == Table::holding_registers ? client_->read_holding_registers(b.start, b.count)
                                                     : client_->read_input_registers(b.start, b.count);
      if (!words) {
        return words.error();
      }
      fresh[t] = std::move(*words);
    }
  }
  // Before the first read there is no poll before: nothing is steady yet.
  last_input_registers_ = read_once_ ? block(Table::input_registers).values
                                     : std::vector<std::uint16_t>(block(Table::input_registers).count, 0);
  for (std::size_t t = 0; t < blocks_.size(); ++t) {
    if (blocks_[t].count != 0) {
      blocks_[t].values = std::move(fresh[t]);
    }
  }
  read_once_ = true;
  return {};
}

bool PlcIo::bit(Table table, std::uint16_t address) const {
  return word(table, address) != 0;
}

std::uint16_t PlcIo::word(Table table, std::uint16_t address) const {
  const Block& b = block(table);
  if (address < b.start || address >= b.start + b.count) {
    return 0;
  }
  return b.values[address - b.start];
}

std::uint16_t PlcIo::steady_input_register(std::uint16_t address) const {
  const Block& b = block(Table::input_registers);
  const std::uint16_t now = word(Table::input_registers, address);
  if (address < b.start || address >= b.start + b.count || last_input_registers_.size() != b.count) {
    return 0;
  }
  return last_input_registers_[address - b.start] == now ? now : 0;
}

void PlcIo::store(Table table, std::uint16_t address, std::uint16_t value) {
  Block& b = block(table);
  if (address >= b.start && address < b.start + b.count) {
    b.values[address - b.start] = value;
  }
}

void PlcIo::write_coil(std::uint16_t address, bool on) {
  if (write_error_) {
    return;
  }
  if (auto s = client_->write_single_coil(address, on); !s) {
    write_error_ = s.error();
    return;
  }
  store(Table::coils, address, on ? 1 : 0);
}

void PlcIo::ensure_coil(std::uint16_t address, bool on) {
  if (coil(address) != on) {
    write_coil(address, on);
  }
}

void PlcIo::write_registers(std::uint16_t address, std::span<const std::uint16_t> values) {
  if (write_error_) {
    return;
  }
  if (auto s = client_->write_multiple_registers(address, values); !s) {
    write_error_ = s.error();
    return;
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    store(Table::holding_registers, static_cast<std::uint16_t>(address + i), values[i]);
  }
}

std::optional<modbus::ClientError> PlcIo::take_write_error() {
  return std::exchange(write_error_, std::nullopt);
}

std::vector<Tag> PlcIo::tags(Tag::Quality quality, const std::string& reason) const {
  std::vector<Tag> out;
  out.reserve(specs_.size());
  for (const auto& s : specs_) {
    Tag tag{prefix_ + "." + s.name, false, quality, reason, s.unit};
    const std::uint16_t raw = word(s.table, s.address);
    switch (s.type) {
      case TagType::bit:
        tag.value = raw != 0;
        break;
      case TagType::unsigned_word:
        tag.value = std::int64_t{raw};
        break;
      case TagType::signed_word:
        tag.value = std::int64_t{static_cast<std::int16_t>(raw)};
        break;
      case TagType::tenths:
        tag.value = raw / 10.0;
        break;
    }
    out.push_back(std::move(tag));
  }
  return out;
}

}  // namespace sf::factory::gateway
