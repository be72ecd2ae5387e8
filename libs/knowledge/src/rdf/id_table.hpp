// An open-addressing set of 32-bit ids whose keys live elsewhere: the caller supplies the hash
// and an equality test against the stored id. Linear probing; ids are never removed.
#pragma once

#include <cstdint>
#include <vector>

namespace sf::knowledge::detail {

class IdTable {
 public:
  // Returns the stored id for which equal(id) holds, or 0.
  template <typename Equal>
  [[nodiscard]] std::uint32_t find(std::size_t hash, Equal&& equal) const {
    if (slots_.empty()) {
      return 0;
    }
    for (std::size_t i = hash & mask_;; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.id == 0) {
        return 0;
      }
      if (s.hash == static_cast<std::uint32_t>(hash) && equal(s.id)) {
        return s.id;
      }
    }
  }

  void insert(std::size_t hash, std::uint32_t id) {
    if ((count_ + 1) * 4 > slots_.size() * 3) {
      grow();
    }
    place(Slot{static_cast<std::uint32_t>(hash), id});
    ++count_;
  }

  [[nodiscard]] std::size_t memory_bytes() const { return slots_.capacity() * sizeof(Slot); }

 private:
  struct Slot {
    std::uint32_t hash = 0;  // low bits of the full hash (enough for probing and a quick reject)
    std::uint32_t id = 0;
  };

  void place(Slot slot) {
    for (std::size_t i = slot.hash & mask_;; i = (i + 1) & mask_) {
      if (slots_[i].id == 0) {
        slots_[i] = slot;
        return;
      }
    }
  }

  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    slots_.assign(old.empty() ? 1024 : old.size() * 2, Slot{});
    mask_ = slots_.size() - 1;
    for (const Slot& s : old) {
      if (s.id != 0) {
        place(s);
      }
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t count_ = 0;
};

}  // namespace sf::knowledge::detail
