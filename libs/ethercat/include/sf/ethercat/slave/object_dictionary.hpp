// CoE object dictionary of an emulated slave (CiA 301 §7.4, ETG.1000.6 §5.6).
// Objects are VAR, ARRAY or RECORD; every entry (subindex) keeps its value as
// little-endian bytes, exactly as an SDO or a PDO carries it, so the SDO
// server and the PDO mapping copy bytes without conversions. Device models
// keep OdEntry pointers to their own objects (stable for the dictionary's
// life: objects are heap-allocated and entries are never added after setup).
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::slave {

// CoE basic data types (ETG.1000.6 Table 64, CiA 301 §7.4.7).
enum class DataType : std::uint16_t {
  Boolean = 0x0001,
  Integer8 = 0x0002,
  Integer16 = 0x0003,
  Integer32 = 0x0004,
  Unsigned8 = 0x0005,
  Unsigned16 = 0x0006,
  Unsigned32 = 0x0007,
  Real32 = 0x0008,
  VisibleString = 0x0009,
  OctetString = 0x000A,
  Real64 = 0x0011,
  Integer64 = 0x0015,
  Unsigned64 = 0x001B,
};
// Bits of a fixed-size type, 0 for strings.
std::uint16_t bit_length_of(DataType type);

// Object access bits as in the SDO information entry description
// (ETG.1000.6 Table 49): read/write per state, PDO mappability.
namespace access {
inline constexpr std::uint16_t kReadPreOp = 1U << 0;
inline constexpr std::uint16_t kReadSafeOp = 1U << 1;
inline constexpr std::uint16_t kReadOp = 1U << 2;
inline constexpr std::uint16_t kWritePreOp = 1U << 3;
inline constexpr std::uint16_t kWriteSafeOp = 1U << 4;
inline constexpr std::uint16_t kWriteOp = 1U << 5;
inline constexpr std::uint16_t kRxPdo = 1U << 6;  // may be mapped into an RxPDO (outputs)
inline constexpr std::uint16_t kTxPdo = 1U << 7;  // may be mapped into a TxPDO (inputs)
inline constexpr std::uint16_t kRead = kReadPreOp | kReadSafeOp | kReadOp;
inline constexpr std::uint16_t kWrite = kWritePreOp | kWriteSafeOp | kWriteOp;
inline constexpr std::uint16_t kRO = kRead;
inline constexpr std::uint16_t kRW = kRead | kWrite;
inline constexpr std::uint16_t kRWPreOp = kRead | kWritePreOp;  // e.g. PDO mapping and assignment
}  // namespace access

enum class ObjectCode : std::uint8_t { Var = 7, Array = 8, Record = 9 };

struct OdEntry {
  std::uint8_t subindex = 0;
  std::string name;
  DataType type = DataType::Unsigned8;
  std::uint16_t bit_length = 8;  // strings: capacity in bits
  std::uint16_t access = access::kRO;
  Bytes value;  // little-endian; strings: the current text

  [[nodiscard]] bool readable(AlState state) const;
  [[nodiscard]] bool writable(AlState state) const;
  [[nodiscard]] bool is_string() const {
    return type == DataType::VisibleString || type == DataType::OctetString;
  }
  [[nodiscard]] std::size_t size() const { return value.size(); }

  template <typename T>
  requires std::is_arithmetic_v<T>
  [[nodiscard]] T get() const {
    if (value.size() < sizeof(T)) {
      std::uint8_t buf[sizeof(T)] = {};
      std::copy(value.begin(), value.end(), buf);
      return load_le<T>(buf);
    }
    return load_le<T>(value.data());
  }
  template <typename T>
  requires std::is_arithmetic_v<T>
  void set(T v) {
    std::uint8_t buf[sizeof(T)];
    store_le<T>(buf, v);
    std::copy(buf, buf + std::min(sizeof(T), value.size()), value.begin());
  }
};

class OdObject;
// Runs before a download is stored: returns 0 to accept or an SDO abort code.
// `subindex` is the entry being written; `data` its new value.
using OdValidator = std::function<std::uint32_t(const OdObject&, std::uint8_t subindex, ByteSpan data)>;

class OdObject {
 public:
  OdObject(std::uint16_t index, std::string name, ObjectCode code)
      : index_(index), name_(std::move(name)), code_(code) {}

  [[nodiscard]] std::uint16_t index() const { return index_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] ObjectCode code() const { return code_; }
  [[nodiscard]] const std::vector<OdEntry>& entries() const { return entries_; }
  [[nodiscard]] std::vector<OdEntry>& entries() { return entries_; }
  [[nodiscard]] OdEntry* entry(std::uint8_t subindex);
  [[nodiscard]] const OdEntry* entry(std::uint8_t subindex) const;
  // Highest subindex present (entries are kept sorted).
  [[nodiscard]] std::uint8_t max_subindex() const;
  // The number of entries a master sees in subindex 0 (ARRAY/RECORD).
  [[nodiscard]] std::uint8_t count() const;

  OdEntry& add(OdEntry entry);
  void set_validator(OdValidator v) { validator_ = std::move(v); }
  [[nodiscard]] const OdValidator& validator() const { return validator_; }

 private:
  std::uint16_t index_;
  std::string name_;
  ObjectCode code_;
  std::vector<OdEntry> entries_;
  OdValidator validator_;
};

// Result of an SDO-level access: 0 or an SDO abort code (sdo_abort_codes.hpp).
using AbortCode = std::uint32_t;

// The wire value of an SDO abort code (ETG.1000.6 5.6.2.7, Table 41).
constexpr AbortCode abort_code(SdoAbortCode c) {
  return static_cast<AbortCode>(c);
}

class ObjectDictionary {
 public:
  ObjectDictionary() = default;
  ObjectDictionary(const ObjectDictionary&) = delete;
  ObjectDictionary& operator=(const ObjectDictionary&) = delete;

  // Adds an object; replaces one with the same index.
  OdObject& add(std::unique_ptr<OdObject> object);
  // A VAR (subindex 0) of a fixed-size type with an initial value.
  OdEntry& add_var(std::uint16_t index, std::string name, DataType type, std::uint16_t access,
                   std::uint64_t initial = 0);
  // A VAR holding a string (VISIBLE_STRING / OCTET_STRING).
  OdEntry& add_string(std::uint16_t index, std::string name, std::string_view text,
                      std::uint16_t access = access::kRO, DataType type = DataType::VisibleString);
  // An ARRAY or RECORD with subindex 0 (UNSIGNED8, the count) already present.
  OdObject& add_compound(std::uint16_t index, std::string name, ObjectCode code,
                         std::uint16_t count_access = access::kRO);
  // Adds an entry to a compound (subindex 0 keeps counting the entries).
  OdEntry& add_entry(OdObject& object, std::uint8_t subindex, std::string name, DataType type,
                     std::uint16_t access, std::uint64_t initial = 0);

  [[nodiscard]] OdObject* find(std::uint16_t index);
  [[nodiscard]] const OdObject* find(std::uint16_t index) const;
  [[nodiscard]] OdEntry* find(std::uint16_t index, std::uint8_t subindex);
  [[nodiscard]] const OdEntry* find(std::uint16_t index, std::uint8_t subindex) const;
  [[nodiscard]] const std::map<std::uint16_t, std::unique_ptr<OdObject>>& objects() const { return objects_; }

  // SDO upload (read) of one entry or, with complete access, of the whole
  // object from `subindex` (0 or 1) on; subindex 0 then travels as 16 bits
  // (ETG.1000.6 §5.6.2.1.1). Access rights are checked for `state`.
  AbortCode upload(std::uint16_t index, std::uint8_t subindex, bool complete_access, AlState state,
                   Bytes& out) const;
  // SDO download (write); the size must match the entry (strings may be
  // shorter). Validators run before anything is stored.
  AbortCode download(std::uint16_t index, std::uint8_t subindex, bool complete_access, ByteSpan data,
                     AlState state);
  // Writes without access checks (device-side updates, tests).
  AbortCode write_local(std::uint16_t index, std::uint8_t subindex, ByteSpan data);

 private:
  AbortCode download_entry(OdObject& object, OdEntry& entry, ByteSpan data, AlState state, bool check_access);
  AbortCode download_complete(OdObject& object, std::uint8_t subindex, ByteSpan data, AlState state);

  std::map<std::uint16_t, std::unique_ptr<OdObject>> objects_;
};

}  // namespace sf::ethercat::slave
