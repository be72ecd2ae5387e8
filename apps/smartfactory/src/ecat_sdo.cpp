// `smartfactory ecat sdo list|read|write`: a slave's CoE object dictionary
// from the command line, as other masters' tools offer it (SOEM's
// `slaveinfo -sdo`, the IgH master's `ethercat sdos|upload|download`). Each
// command scans the segment, brings it to PREOP (the mailbox works from
// there) and leaves it in PREOP. A slave's SDO abort is printed with its
// code and text and ends the command with exit code 1.
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "ecat_session.hpp"
#include "sf/ethercat/master/dictionary.hpp"
#include "sf/ethercat/sdo_info.hpp"

namespace sf::app {
namespace {

namespace ecat = sf::ethercat;
using nlohmann::json;

struct SdoCliOptions {
  LinkChoice link;
  std::optional<std::size_t> slave;
  std::string index;
  std::string subindex = "0";
  std::string value;
  std::string type;
  bool complete = false;
  bool values = false;
  bool json = false;
};

// Scans the segment and brings it to PREOP; nullptr after printing why not.
std::unique_ptr<EcatSession> open_preop(const SdoCliOptions& o, std::string_view command) {
  auto session = EcatSession::open(o.link);
  if (!session) {
    std::cerr << "ecat sdo " << command << ": " << session.error().describe() << "\n";
    return nullptr;
  }
  auto& master = (*session)->master();
  auto count = master.scan();
  if (!count || *count == 0) {
    std::cerr << "ecat sdo " << command << ": " << (count ? "no slaves found" : count.error().describe())
              << "\n";
    return nullptr;
  }
  if (o.slave && *o.slave >= *count) {
    std::cerr << "ecat sdo " << command << ": --slave " << *o.slave << ": the segment has " << *count
              << " slaves\n";
    return nullptr;
  }
  if (auto st = master.request_state(ecat::AlState::PreOp); !st) {
    std::cerr << "ecat sdo " << command << ": PREOP: " << st.error().describe() << "\n";
    return nullptr;
  }
  return std::move(*session);
}

Result<std::uint32_t> parse_number(const std::string& text, std::uint32_t max, std::string_view what) {
  try {
    std::size_t used = 0;
    const unsigned long v = std::stoul(text, &used, 0);
    if (used == text.size() && v <= max) {
      return static_cast<std::uint32_t>(v);
    }
  } catch (const std::exception&) {  // NOLINT(bugprone-empty-catch): reported below
  }
  return make_error(Errc::invalid_argument,
                    fmt::format("{} '{}' is not a number up to 0x{:X}", what, text, max));
}

struct Address {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
};

// INDEX [SUBINDEX] or INDEX:SUBINDEX, numbers in C notation (0x6040).
Result<Address> parse_address(const SdoCliOptions& o) {
  std::string index = o.index;
  std::string subindex = o.subindex;
  if (const auto colon = index.find(':'); colon != std::string::npos) {
    subindex = index.substr(colon + 1);
    index.resize(colon);
  }
  auto i = parse_number(index, 0xFFFF, "index");
  if (!i) {
    return i.error();
  }
  auto s = parse_number(subindex, 0xFF, "subindex");
  if (!s) {
    return s.error();
  }
  return Address{static_cast<std::uint16_t>(*i), static_cast<std::uint8_t>(*s)};
}

// The data type to read or write the entry as: --type, else what the
// slave's SDO Information says; nullopt when neither tells.
Result<std::optional<std::uint16_t>> entry_type(ecat::master::Master& master, std::size_t slave,
                                                const SdoCliOptions& o, Address a) {
  if (!o.type.empty()) {
    auto type = ecat::data_type_from_name(o.type);
    if (!type) {
      return type.error();
    }
    return std::optional<std::uint16_t>{*type};
  }
  auto entry = master.sdo_info_entry(slave, a.index, a.subindex);
  if (!entry || std::holds_alternative<ecat::SdoAbort>(*entry)) {
    return std::optional<std::uint16_t>{};
  }
  return std::optional<std::uint16_t>{std::get<ecat::EntryDescription>(*entry).data_type};
}

int refused(std::string_view command, std::size_t slave, const ecat::SdoAbort& abort) {
  std::cerr << "ecat sdo " << command << ": slave " << slave << ": " << ecat::describe(abort) << "\n";
  return kExitFailure;
}

json entry_json(const ecat::master::DictionaryEntry& e) {
  const auto& d = e.description;
  json out{{"subindex", d.subindex},
           {"name", d.name},
           {"data_type", ecat::data_type_name(d.data_type)},
           {"bit_length", d.bit_length},
           {"access", ecat::access_text(d.object_access)}};
  if (e.value) {
    if (const auto* abort = std::get_if<ecat::SdoAbort>(&*e.value)) {
      out["abort"] = fmt::format("0x{:08X}", abort->code);
    } else {
      out["value"] = ecat::format_value(d.data_type, std::get<Bytes>(*e.value));
    }
  }
  return out;
}

void print_object(const ecat::master::DictionaryObject& o) {
  const auto& d = o.description;
  std::printf("0x%04X %-6s %-14s \"%s\"\n", d.index, ecat::object_code_name(d.object_code).c_str(),
              ecat::data_type_name(d.data_type).c_str(), d.name.c_str());
  for (const auto& e : o.entries) {
    const auto& ed = e.description;
    std::string value;
    if (e.value) {
      const auto* abort = std::get_if<ecat::SdoAbort>(&*e.value);
      value = abort != nullptr ? fmt::format(" = (abort 0x{:08X})", abort->code)
                               : " = " + ecat::format_value(ed.data_type, std::get<Bytes>(*e.value));
    }
    std::printf("    0x%04X:%02X %-14s %4u bit %-22s \"%s\"%s\n", d.index, ed.subindex,
                ecat::data_type_name(ed.data_type).c_str(), ed.bit_length,
                ecat::access_text(ed.object_access).c_str(), ed.name.c_str(), value.c_str());
  }
}

int run_list(const SdoCliOptions& o) {
  auto session = open_preop(o, "list");
  if (!session) {
    return kExitFailure;
  }
  auto& master = session->master();
  json out = json::array();
  int rc = kExitOk;
  for (std::size_t p = 0; p < master.slave_count(); ++p) {
    const auto& info = master.slave_info(p);
    if ((o.slave && *o.slave != p) || (!o.slave && !info.mailbox.coe())) {
      continue;
    }
    auto dictionary = ecat::master::read_dictionary(master, p, o.values);
    if (!dictionary) {
      std::cerr << "ecat sdo list: " << dictionary.error().describe() << "\n";
      rc = kExitFailure;
      continue;
    }
    if (!o.json) {
      std::printf("slave %zu (%s): %zu objects\n", p, info.name().c_str(), dictionary->size());
    }
    json objects = json::array();
    for (const auto& object : *dictionary) {
      if (o.json) {
        json entries = json::array();
        for (const auto& e : object.entries) {
          entries.push_back(entry_json(e));
        }
        objects.push_back({{"index", object.description.index},
                           {"name", object.description.name},
                           {"object_code", ecat::object_code_name(object.description.object_code)},
                           {"data_type", ecat::data_type_name(object.description.data_type)},
                           {"max_subindex", object.description.max_subindex},
                           {"entries", entries}});
      } else {
        print_object(object);
      }
    }
    out.push_back({{"slave", p}, {"name", info.name()}, {"objects", objects}});
  }
  if (o.json) {
    std::cout << out.dump(2) << "\n";
  }
  return rc;
}

// The entry a read or write is about, on a segment in PREOP, with the type
// to read or write it as (nullopt: unknown, read as hex).
struct EntryAccess {
  std::unique_ptr<EcatSession> session;
  std::size_t slave = 0;
  Address address;
  std::optional<std::uint16_t> type;
};

// The entry, or the exit code after printing why not. `need_type`: a write
// cannot go ahead without knowing the type.
std::variant<EntryAccess, int> open_entry(const SdoCliOptions& o, std::string_view command, bool need_type) {
  auto address = parse_address(o);
  if (!address) {
    std::cerr << "ecat sdo " << command << ": " << address.error().message << "\n";
    return kExitUsage;
  }
  EntryAccess entry{open_preop(o, command), o.slave.value_or(0), *address, std::nullopt};
  if (!entry.session) {
    return kExitFailure;
  }
  if (o.complete && !need_type) {
    return entry;  // a whole object: hex
  }
  auto type = entry_type(entry.session->master(), entry.slave, o, *address);
  if (!type || (need_type && !type->has_value())) {
    std::cerr << "ecat sdo " << command << ": "
              << (type ? "the slave does not describe this entry: give --type" : type.error().message)
              << "\n";
    return kExitUsage;
  }
  entry.type = *type;
  return entry;
}

int run_read(const SdoCliOptions& o) {
  auto opened = open_entry(o, "read", false);
  if (const int* rc = std::get_if<int>(&opened)) {
    return *rc;
  }
  auto& e = std::get<EntryAccess>(opened);
  auto answer =
      e.session->master().sdo_upload_answer(e.slave, e.address.index, e.address.subindex, o.complete);
  if (!answer) {
    std::cerr << "ecat sdo read: " << answer.error().describe() << "\n";
    return kExitFailure;
  }
  if (const auto* abort = std::get_if<ecat::SdoAbort>(&*answer)) {
    return refused("read", e.slave, *abort);
  }
  const auto& data = std::get<Bytes>(*answer);
  const std::string text = e.type ? ecat::format_value(*e.type, data) : to_hex(data, 4096);
  if (o.json) {
    std::cout << json{{"slave", e.slave},
                      {"index", e.address.index},
                      {"subindex", e.address.subindex},
                      {"data_type", e.type ? ecat::data_type_name(*e.type) : "OCTET_STRING"},
                      {"value", text},
                      {"hex", to_hex(data, 4096)}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("%s\n", text.c_str());
  }
  return kExitOk;
}

int run_write(const SdoCliOptions& o) {
  auto opened = open_entry(o, "write", true);
  if (const int* rc = std::get_if<int>(&opened)) {
    return *rc;
  }
  auto& e = std::get<EntryAccess>(opened);
  auto data = ecat::parse_value(*e.type, o.value);
  if (!data) {
    std::cerr << "ecat sdo write: VALUE: " << data.error().message << "\n";
    return kExitUsage;
  }
  auto answer = e.session->master().sdo_download_answer(e.slave, e.address.index, e.address.subindex, *data,
                                                        o.complete);
  if (!answer) {
    std::cerr << "ecat sdo write: " << answer.error().describe() << "\n";
    return kExitFailure;
  }
  if (*answer) {
    return refused("write", e.slave, **answer);
  }
  return kExitOk;
}

void add_common(CLI::App& command, SdoCliOptions& o, bool slave_required_text) {
  add_link_options(command, o.link);
  command.add_option("--slave", o.slave,
                     slave_required_text ? "Slave position in the segment (default 0)"
                                         : "Slave position in the segment (default: every slave with CoE)");
  command.add_flag("--json", o.json, "Print JSON instead of text");
}

void add_address(CLI::App& command, SdoCliOptions& o, bool write) {
  command.add_option("index", o.index, "Object index, e.g. 0x6040 (or 0x6040:0 with the subindex)")
      ->required();
  auto* sub = command.add_option("subindex", o.subindex, write ? "Subindex" : "Subindex (default 0)");
  if (write) {
    sub->required();
    command.add_option("value", o.value, "The value, as text of the entry's type (hex bytes for --type hex)")
        ->required();
  }
  command.add_option("--type", o.type,
                     "Data type of the entry: u8 u16 u32 u64 i8 i16 i32 i64 bool f32 f64 string hex "
                     "(default: as the slave's SDO Information describes the entry)");
  command.add_flag("--complete", o.complete,
                   "Complete access: the whole object from this subindex (0 or 1) on");
}

}  // namespace

void register_ecat_sdo(CLI::App& ecat_cmd, CommandResult& result) {
  auto* sdo =
      ecat_cmd.add_subcommand("sdo", "A slave's CoE object dictionary: list, read and write objects (SDO)");
  sdo->require_subcommand(1);
  sdo->footer(
      "Each command scans the segment and brings it to PREOP. An SDO abort is printed with its code and\n"
      "text (e.g. 0x06020000 Object does not exist) and the command exits 1.\n"
      "  smartfactory ecat sdo list --sim servo:1 --values\n"
      "  smartfactory ecat sdo read --sim servo:1 0x1018 1\n"
      "  smartfactory ecat sdo write --sim servo:1 0x6065 0 1000");

  auto list = std::make_shared<SdoCliOptions>();
  auto* list_cmd = sdo->add_subcommand(
      "list",
      "List every object and entry of a slave's dictionary (SDO Information: index, type, access, name)");
  add_common(*list_cmd, *list, false);
  list_cmd->add_flag("--values", list->values, "Read and print each readable entry's value too");
  list_cmd->callback([list, &result] { result.exit_code = run_list(*list); });

  auto read = std::make_shared<SdoCliOptions>();
  auto* read_cmd = sdo->add_subcommand("read", "Read one entry (SDO upload) and print its value");
  add_common(*read_cmd, *read, true);
  add_address(*read_cmd, *read, false);
  read_cmd->callback([read, &result] { result.exit_code = run_read(*read); });

  auto write = std::make_shared<SdoCliOptions>();
  auto* write_cmd = sdo->add_subcommand("write", "Write one entry (SDO download)");
  add_common(*write_cmd, *write, true);
  add_address(*write_cmd, *write, true);
  write_cmd->callback([write, &result] { result.exit_code = run_write(*write); });
}

}  // namespace sf::app
