// ExtensionObject bodies (OPC 10000-6 §5.2.2.15): the typed wrapper of a generated structure and
// the registry that maps DataTypeEncoding NodeIds to body decoders.
#pragma once

#include <concepts>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/codec.hpp"
#include "sf/opcua/variant.hpp"

namespace sf::opcua {

// A generated structure: it knows its name and the namespace-0 NodeIds of its DataType and of
// its binary DataTypeEncoding.
template <typename T>
concept EncodableStructure = requires {
  { T::kTypeName } -> std::convertible_to<std::string_view>;
  { T::kTypeId } -> std::convertible_to<std::uint32_t>;
  { T::kBinaryEncodingId } -> std::convertible_to<std::uint32_t>;
};

template <typename T>
class TypedBody final : public ExtensionBody {
 public:
  explicit TypedBody(T v) : value(std::move(v)) {}
  [[nodiscard]] std::unique_ptr<ExtensionBody> clone() const override {
    return std::make_unique<TypedBody>(value);
  }
  [[nodiscard]] bool equals(const ExtensionBody& other) const override {
    const auto* o = dynamic_cast<const TypedBody*>(&other);
    return o != nullptr && o->value == value;
  }
  void encode(Encoder& encoder) const override { encode_binary(encoder, value); }
  [[nodiscard]] std::string to_string() const override {
    using sf::opcua::to_string;
    return to_string(value);
  }
  [[nodiscard]] std::string_view type_name() const override { return T::kTypeName; }

  T value;
};

// Maps DataTypeEncoding NodeIds to body decoders. ExtensionRegistry::standard() knows every
// structure generated from libs/opcua/schema/types.txt; applications add their own types.
class ExtensionRegistry {
 public:
  // Decodes one body; the Decoder reads exactly the body's bytes.
  using DecodeFn = std::unique_ptr<ExtensionBody> (*)(Decoder&);
  struct Entry {
    DecodeFn decode = nullptr;
    std::string_view type_name;
  };

  // type_name must outlive the registry (the generated types use their kTypeName).
  void add(const NodeId& encoding_id, DecodeFn decode, std::string_view type_name);
  template <EncodableStructure T>
  void add() {
    add(NodeId(0, T::kBinaryEncodingId), &decode_body<T>, T::kTypeName);
  }
  [[nodiscard]] const Entry* find(const NodeId& encoding_id) const;
  [[nodiscard]] std::size_t size() const { return entries_.size(); }

  static const ExtensionRegistry& standard();

  template <typename T>
  static std::unique_ptr<ExtensionBody> decode_body(Decoder& d) {
    auto body = std::make_unique<TypedBody<T>>(T{});
    decode_binary(d, body->value);
    return body;
  }

 private:
  std::unordered_map<NodeId, Entry> entries_;
};

template <typename T>
ExtensionObject ExtensionObject::make(T value) {
  static_assert(EncodableStructure<T>, "ExtensionObject::make needs a generated structure");
  return ExtensionObject(NodeId(0, T::kBinaryEncodingId), std::make_unique<TypedBody<T>>(std::move(value)));
}

template <typename T>
const T* ExtensionObject::get_if() const {
  const auto* typed = dynamic_cast<const TypedBody<T>*>(body());
  return typed != nullptr ? &typed->value : nullptr;
}

template <typename T>
T* ExtensionObject::get_if() {
  auto* holder = std::get_if<std::unique_ptr<ExtensionBody>>(&body_);
  auto* typed = holder != nullptr ? dynamic_cast<TypedBody<T>*>(holder->get()) : nullptr;
  return typed != nullptr ? &typed->value : nullptr;
}

}  // namespace sf::opcua
