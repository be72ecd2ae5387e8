#include "sf/ethercat/slave/object_dictionary.hpp"

#include <algorithm>

#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat::slave {

namespace {

// In INIT and BOOT there is no CoE; checks use PREOP rights (the server is
// only reachable from PREOP on anyway).
std::uint16_t read_bit(AlState s) {
  switch (s) {
    case AlState::SafeOp:
      return access::kReadSafeOp;
    case AlState::Op:
      return access::kReadOp;
    default:
      return access::kReadPreOp;
  }
}

std::uint16_t write_bit(AlState s) {
  switch (s) {
    case AlState::SafeOp:
      return access::kWriteSafeOp;
    case AlState::Op:
      return access::kWriteOp;
    default:
      return access::kWritePreOp;
  }
}

Bytes initial_bytes(DataType type, std::uint64_t initial) {
  const std::size_t n = std::max<std::size_t>(1, (bit_length_of(type) + 7U) / 8U);
  Bytes b(n);
  for (std::size_t i = 0; i < n && i < 8; ++i) {
    b[i] = static_cast<std::uint8_t>(initial >> (8U * i));
  }
  return b;
}

}  // namespace

std::uint16_t bit_length_of(DataType type) {
  switch (type) {
    case DataType::Boolean:
      return 1;
    case DataType::Integer8:
    case DataType::Unsigned8:
      return 8;
    case DataType::Integer16:
    case DataType::Unsigned16:
      return 16;
    case DataType::Integer32:
    case DataType::Unsigned32:
    case DataType::Real32:
      return 32;
    case DataType::Integer64:
    case DataType::Unsigned64:
    case DataType::Real64:
      return 64;
    case DataType::VisibleString:
    case DataType::OctetString:
      return 0;
  }
  return 0;
}

bool OdEntry::readable(AlState state) const {
  return (access & read_bit(state)) != 0;
}
bool OdEntry::writable(AlState state) const {
  return (access & write_bit(state)) != 0;
}

OdEntry* OdObject::entry(std::uint8_t subindex) {
  auto it = std::lower_bound(entries_.begin(), entries_.end(), subindex,
                             [](const OdEntry& e, std::uint8_t s) { return e.subindex < s; });
  return it != entries_.end() && it->subindex == subindex ? &*it : nullptr;
}

const OdEntry* OdObject::entry(std::uint8_t subindex) const {
  return const_cast<OdObject*>(this)->entry(subindex);  // NOLINT: same lookup, const result
}

std::uint8_t OdObject::max_subindex() const {
  return entries_.empty() ? 0 : entries_.back().subindex;
}

std::uint8_t OdObject::count() const {
  if (code_ == ObjectCode::Var) {
    return 0;
  }
  const OdEntry* sub0 = entry(0);
  return sub0 != nullptr ? sub0->get<std::uint8_t>() : max_subindex();
}

OdEntry& OdObject::add(OdEntry entry) {
  auto it = std::lower_bound(entries_.begin(), entries_.end(), entry.subindex,
                             [](const OdEntry& e, std::uint8_t s) { return e.subindex < s; });
  if (it != entries_.end() && it->subindex == entry.subindex) {
    *it = std::move(entry);
    return *it;
  }
  return *entries_.insert(it, std::move(entry));
}

OdObject& ObjectDictionary::add(std::unique_ptr<OdObject> object) {
  auto& slot = objects_[object->index()];
  slot = std::move(object);
  return *slot;
}

OdEntry& ObjectDictionary::add_var(std::uint16_t index, std::string name, DataType type, std::uint16_t access,
                                   std::uint64_t initial) {
  auto& obj = add(std::make_unique<OdObject>(index, name, ObjectCode::Var));
  return obj.add(
      OdEntry{0, std::move(name), type, bit_length_of(type), access, initial_bytes(type, initial)});
}

OdEntry& ObjectDictionary::add_string(std::uint16_t index, std::string name, std::string_view text,
                                      std::uint16_t access, DataType type) {
  auto& obj = add(std::make_unique<OdObject>(index, name, ObjectCode::Var));
  // Capacity: the initial text or 64 bytes for writable strings, whichever is more.
  const std::size_t capacity =
      (access & access::kWrite) != 0 ? std::max<std::size_t>(64, text.size()) : text.size();
  return obj.add(OdEntry{0, std::move(name), type, static_cast<std::uint16_t>(8U * capacity), access,
                         Bytes(text.begin(), text.end())});
}

OdObject& ObjectDictionary::add_compound(std::uint16_t index, std::string name, ObjectCode code,
                                         std::uint16_t count_access) {
  auto& obj = add(std::make_unique<OdObject>(index, std::move(name), code));
  obj.add(OdEntry{0, "Number of entries", DataType::Unsigned8, 8, count_access, Bytes{0}});
  return obj;
}

OdEntry& ObjectDictionary::add_entry(OdObject& object, std::uint8_t subindex, std::string name, DataType type,
                                     std::uint16_t access, std::uint64_t initial) {
  OdEntry& e = object.add(
      OdEntry{subindex, std::move(name), type, bit_length_of(type), access, initial_bytes(type, initial)});
  if (OdEntry* sub0 = object.entry(0); sub0 != nullptr && subindex > sub0->get<std::uint8_t>()) {
    sub0->set<std::uint8_t>(subindex);
  }
  return e;
}

OdObject* ObjectDictionary::find(std::uint16_t index) {
  auto it = objects_.find(index);
  return it == objects_.end() ? nullptr : it->second.get();
}

const OdObject* ObjectDictionary::find(std::uint16_t index) const {
  auto it = objects_.find(index);
  return it == objects_.end() ? nullptr : it->second.get();
}

OdEntry* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) {
  OdObject* o = find(index);
  return o == nullptr ? nullptr : o->entry(subindex);
}

const OdEntry* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) const {
  const OdObject* o = find(index);
  return o == nullptr ? nullptr : o->entry(subindex);
}

AbortCode ObjectDictionary::upload(std::uint16_t index, std::uint8_t subindex, bool complete_access,
                                   AlState state, Bytes& out) const {
  out.clear();
  const OdObject* obj = find(index);
  if (obj == nullptr) {
    return abort_code(SdoAbortCode::ObjectDoesNotExist);
  }
  if (!complete_access) {
    const OdEntry* e = obj->entry(subindex);
    if (e == nullptr) {
      return abort_code(SdoAbortCode::SubindexDoesNotExist);
    }
    if (!e->readable(state)) {
      return abort_code(SdoAbortCode::WriteOnly);
    }
    out = e->value;
    return 0;
  }
  // Complete access (ETG.1000.6 §5.6.2.1.1): only subindex 0 or 1 may start
  // it; subindex 0 is padded to 16 bits; entries up to the count follow.
  if (obj->code() == ObjectCode::Var || subindex > 1) {
    return abort_code(SdoAbortCode::UnsupportedAccess);
  }
  const std::uint8_t n = obj->count();
  if (subindex == 0) {
    out.push_back(n);
    out.push_back(0);
  }
  for (const OdEntry& e : obj->entries()) {
    if (e.subindex == 0 || e.subindex > n) {
      continue;
    }
    if (!e.readable(state)) {
      return abort_code(SdoAbortCode::WriteOnly);
    }
    out.insert(out.end(), e.value.begin(), e.value.end());
  }
  return 0;
}

AbortCode ObjectDictionary::download(std::uint16_t index, std::uint8_t subindex, bool complete_access,
                                     ByteSpan data, AlState state) {
  OdObject* obj = find(index);
  if (obj == nullptr) {
    return abort_code(SdoAbortCode::ObjectDoesNotExist);
  }
  if (complete_access) {
    return download_complete(*obj, subindex, data, state);
  }
  OdEntry* e = obj->entry(subindex);
  if (e == nullptr) {
    return abort_code(SdoAbortCode::SubindexDoesNotExist);
  }
  return download_entry(*obj, *e, data, state, true);
}

AbortCode ObjectDictionary::write_local(std::uint16_t index, std::uint8_t subindex, ByteSpan data) {
  OdObject* obj = find(index);
  OdEntry* e = obj == nullptr ? nullptr : obj->entry(subindex);
  if (e == nullptr) {
    return obj == nullptr ? abort_code(SdoAbortCode::ObjectDoesNotExist)
                          : abort_code(SdoAbortCode::SubindexDoesNotExist);
  }
  return download_entry(*obj, *e, data, AlState::PreOp, false);
}

AbortCode ObjectDictionary::download_entry(OdObject& object, OdEntry& entry, ByteSpan data, AlState state,
                                           bool check_access) {
  if (check_access && !entry.writable(state)) {
    return (entry.access & access::kWrite) == 0 ? abort_code(SdoAbortCode::ReadOnly)
                                                : abort_code(SdoAbortCode::CannotTransferDeviceState);
  }
  if (entry.is_string()) {
    if (data.size() > entry.bit_length / 8U) {
      return abort_code(SdoAbortCode::LengthTooHigh);
    }
  } else if (data.size() != entry.value.size()) {
    return abort_code(SdoAbortCode::LengthMismatch);
  }
  if (object.validator()) {
    if (AbortCode c = object.validator()(object, entry.subindex, data); c != 0) {
      return c;
    }
  }
  entry.value.assign(data.begin(), data.end());
  return 0;
}

AbortCode ObjectDictionary::download_complete(OdObject& object, std::uint8_t subindex, ByteSpan data,
                                              AlState state) {
  if (object.code() == ObjectCode::Var || subindex > 1) {
    return abort_code(SdoAbortCode::UnsupportedAccess);
  }
  ByteReader r(data);
  std::uint8_t n = object.count();
  OdEntry* sub0 = object.entry(0);
  if (subindex == 0) {
    n = r.u8();
    r.skip(1);  // padding of subindex 0 to 16 bits
    if (sub0 == nullptr || !r.ok()) {
      return abort_code(SdoAbortCode::LengthTooLow);
    }
    if (n > object.max_subindex()) {
      return abort_code(SdoAbortCode::ValueTooHigh);
    }
    // Like a client writing entry by entry: subindex 0 goes to 0 first, so
    // validators that guard the entries (PDO mapping) accept them.
    if (sub0->writable(state)) {
      sub0->set<std::uint8_t>(0);
    }
  }
  for (OdEntry& e : object.entries()) {
    if (e.subindex == 0 || e.subindex > n) {
      continue;
    }
    ByteSpan value = r.bytes(e.is_string() ? r.remaining() : e.value.size());
    if (!r.ok()) {
      return abort_code(SdoAbortCode::LengthTooLow);
    }
    if (AbortCode c = download_entry(object, e, value, state, true); c != 0) {
      return c;
    }
  }
  if (!r.at_end()) {
    return abort_code(SdoAbortCode::LengthTooHigh);
  }
  if (subindex == 0) {
    const std::uint8_t count_byte[1] = {n};
    return download_entry(object, *sub0, count_byte, state, sub0->writable(state) || n != object.count());
  }
  return 0;
}

}  // namespace sf::ethercat::slave
