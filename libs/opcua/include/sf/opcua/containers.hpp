// Containers with the semantics OPC UA needs beyond the standard library's.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace sf::opcua {

// A one-dimensional OPC UA array (OPC 10000-6 §5.2.5): a std::vector that also remembers
// whether it was null (length -1) rather than empty (length 0). Encoders and decoders preserve
// that distinction (OPC 10000-6 §5.1.9). A default-constructed Array is empty, not null; an Array
// with elements is never null.
template <typename T>
class Array : public std::vector<T> {
 public:
  using std::vector<T>::vector;
  Array() = default;
  Array(std::vector<T> values) : std::vector<T>(std::move(values)) {}  // NOLINT(google-explicit-constructor)

  static Array null() {
    Array a;
    a.null_ = true;
    return a;
  }
  [[nodiscard]] bool is_null() const { return null_ && this->empty(); }
  void set_null() {
    std::vector<T>::clear();
    null_ = true;
  }
  // Marks the array as present (not null), keeping its elements.
  void set_present() { null_ = false; }
  // Empty and not null.
  void clear() {
    std::vector<T>::clear();
    null_ = false;
  }

  friend bool operator==(const Array& a, const Array& b) {
    return a.is_null() == b.is_null() &&
           static_cast<const std::vector<T>&>(a) == static_cast<const std::vector<T>&>(b);
  }

 private:
  bool null_ = false;
};

// IsArray<T>::value: T is an Array<E>; IsArray<T>::Element is E.
template <typename T>
struct IsArray : std::false_type {};
template <typename T>
struct IsArray<Array<T>> : std::true_type {
  using Element = T;
};

// An optional value held on the heap with value semantics (deep copy, deep comparison), for the
// recursive built-in types (DiagnosticInfo inside DiagnosticInfo, DataValue inside Variant) and
// to keep rarely used large alternatives out of Variant's inline storage.
template <typename T>
class Box {
 public:
  Box() = default;
  explicit Box(T value) : p_(std::make_unique<T>(std::move(value))) {}
  Box(const Box& other) : p_(other.p_ ? std::make_unique<T>(*other.p_) : nullptr) {}
  Box(Box&&) noexcept = default;
  Box& operator=(const Box& other) {
    if (this != &other) {
      p_ = other.p_ ? std::make_unique<T>(*other.p_) : nullptr;
    }
    return *this;
  }
  Box& operator=(Box&&) noexcept = default;
  ~Box() = default;

  [[nodiscard]] bool has_value() const { return p_ != nullptr; }
  explicit operator bool() const { return has_value(); }
  T& operator*() { return *p_; }
  const T& operator*() const { return *p_; }
  T* operator->() { return p_.get(); }
  const T* operator->() const { return p_.get(); }
  [[nodiscard]] T* get() { return p_.get(); }
  [[nodiscard]] const T* get() const { return p_.get(); }
  T& emplace() {
    p_ = std::make_unique<T>();
    return *p_;
  }
  void reset() { p_.reset(); }

  friend bool operator==(const Box& a, const Box& b) {
    if (!a.p_ || !b.p_) {
      return !a.p_ && !b.p_;
    }
    return *a.p_ == *b.p_;
  }

 private:
  std::unique_ptr<T> p_;
};

}  // namespace sf::opcua
