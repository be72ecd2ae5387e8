// A compact open-addressing hash map (linear probing, backward-shift deletion) for the triple
// store's indexes: small trivially copyable keys and values, no per-entry allocation.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace sf::knowledge::detail {

// Traits: static Key empty(); static std::size_t hash(const Key&).
template <typename Key, typename Value, typename Traits>
class FlatMap {
 public:
  [[nodiscard]] const Value* find(const Key& key) const {
    if (count_ == 0) {
      return nullptr;
    }
    for (std::size_t i = Traits::hash(key) & mask_;; i = (i + 1) & mask_) {
      if (slots_[i].key == key) {
        return &slots_[i].value;
      }
      if (slots_[i].key == Traits::empty()) {
        return nullptr;
      }
    }
  }
  Value* find(const Key& key) { return const_cast<Value*>(std::as_const(*this).find(key)); }

  // The value for key, default-constructed (and `inserted` set) when it was absent.
  Value& get_or_insert(const Key& key, bool& inserted) {
    if ((count_ + 1) * 8 > slots_.size() * 5) {
      grow();
    }
    std::size_t i = Traits::hash(key) & mask_;
    for (; !(slots_[i].key == Traits::empty()); i = (i + 1) & mask_) {
      if (slots_[i].key == key) {
        inserted = false;
        return slots_[i].value;
      }
    }
    slots_[i].key = key;
    slots_[i].value = Value{};
    ++count_;
    inserted = true;
    return slots_[i].value;
  }

  bool erase(const Key& key) {
    if (count_ == 0) {
      return false;
    }
    std::size_t i = Traits::hash(key) & mask_;
    for (; !(slots_[i].key == key); i = (i + 1) & mask_) {
      if (slots_[i].key == Traits::empty()) {
        return false;
      }
    }
    // Backward-shift: move later entries of the probe run into the hole.
    for (std::size_t j = (i + 1) & mask_; !(slots_[j].key == Traits::empty()); j = (j + 1) & mask_) {
      const std::size_t home = Traits::hash(slots_[j].key) & mask_;
      if (((j - home) & mask_) >= ((j - i) & mask_)) {
        slots_[i] = slots_[j];
        i = j;
      }
    }
    slots_[i].key = Traits::empty();
    --count_;
    return true;
  }

  template <typename F>
  void for_each(F&& f) {
    for (auto& s : slots_) {
      if (!(s.key == Traits::empty())) {
        f(s.key, s.value);
      }
    }
  }

  void clear() {
    for (auto& s : slots_) {
      s.key = Traits::empty();
    }
    count_ = 0;
  }

  [[nodiscard]] std::size_t size() const { return count_; }
  [[nodiscard]] std::size_t memory_bytes() const { return slots_.capacity() * sizeof(Slot); }

 private:
  struct Slot {
    Key key = Traits::empty();
    Value value{};
  };

  void grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    slots_.assign(old.empty() ? 64 : old.size() * 2, Slot{});
    mask_ = slots_.size() - 1;
    for (const Slot& s : old) {
      if (!(s.key == Traits::empty())) {
        std::size_t i = Traits::hash(s.key) & mask_;
        while (!(slots_[i].key == Traits::empty())) {
          i = (i + 1) & mask_;
        }
        slots_[i] = s;
      }
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t count_ = 0;
};

inline std::uint64_t mix64(std::uint64_t x) {
  // splitmix64 finaliser
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

struct U64Traits {
  static constexpr std::uint64_t empty() { return ~std::uint64_t{0}; }
  static std::size_t hash(std::uint64_t k) { return static_cast<std::size_t>(mix64(k)); }
};

}  // namespace sf::knowledge::detail
