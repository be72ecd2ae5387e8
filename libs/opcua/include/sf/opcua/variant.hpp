// The composite built-in types: DiagnosticInfo (OPC 10000-6 §5.2.2.12), ExtensionObject
// (§5.2.2.15), Variant (§5.2.2.16) and DataValue (§5.2.2.17). They nest into each other, so they
// live together; Box breaks the cycles.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/containers.hpp"
#include "sf/opcua/status_code.hpp"

namespace sf::opcua {

class Encoder;
class Decoder;
struct DataValue;

// DiagnosticInfo (OPC 10000-4 §7.12): the four Int32 fields index the ResponseHeader's string
// table; -1 means "no value" and such fields are not encoded. additional_info is encoded when
// not null, inner_status_code when not Good, inner_diagnostic_info when present.
struct DiagnosticInfo {
  std::int32_t symbolic_id = -1;
  std::int32_t namespace_uri = -1;
  std::int32_t locale = -1;
  std::int32_t localized_text = -1;
  String additional_info;
  StatusCode inner_status_code;
  Box<DiagnosticInfo> inner_diagnostic_info;

  friend bool operator==(const DiagnosticInfo&, const DiagnosticInfo&) = default;
};

// A structure decoded from (or to be encoded into) an ExtensionObject body. The generated types
// are wrapped in TypedBody<T> (binary.hpp); ExtensionObject::get_if<T>() unwraps them.
class ExtensionBody {
 public:
  ExtensionBody() = default;
  ExtensionBody(const ExtensionBody&) = delete;
  ExtensionBody& operator=(const ExtensionBody&) = delete;
  virtual ~ExtensionBody() = default;

  [[nodiscard]] virtual std::unique_ptr<ExtensionBody> clone() const = 0;
  [[nodiscard]] virtual bool equals(const ExtensionBody& other) const = 0;
  virtual void encode(Encoder& encoder) const = 0;
  [[nodiscard]] virtual std::string to_string() const = 0;
  [[nodiscard]] virtual std::string_view type_name() const = 0;
};

template <typename T>
class TypedBody;

// ExtensionObject (OPC 10000-6 §5.2.2.15): a structure identified by the NodeId of its
// DataTypeEncoding. The body is absent, a decoded structure (when the decoder's registry knows
// the encoding id), opaque binary bytes (when it does not) or an XML element.
class ExtensionObject {
 public:
  enum class Encoding : std::uint8_t { None = 0, Binary = 1, Xml = 2 };

  ExtensionObject() = default;
  ExtensionObject(NodeId type_id, std::unique_ptr<ExtensionBody> body);
  ExtensionObject(const ExtensionObject& other);
  ExtensionObject(ExtensionObject&&) noexcept = default;
  ExtensionObject& operator=(const ExtensionObject& other);
  ExtensionObject& operator=(ExtensionObject&&) noexcept = default;
  ~ExtensionObject();

  // A generated structure T, tagged with T's binary encoding id (defined in binary.hpp).
  template <typename T>
  static ExtensionObject make(T value);
  static ExtensionObject opaque(NodeId type_id, ByteString body);
  static ExtensionObject xml(NodeId type_id, XmlElement body);

  [[nodiscard]] const NodeId& type_id() const { return type_id_; }
  [[nodiscard]] Encoding encoding() const;
  [[nodiscard]] bool empty() const { return body_.index() == 0; }
  [[nodiscard]] bool is_decoded() const { return body_.index() == 3; }
  // The undecoded binary body, or nullptr.
  [[nodiscard]] const ByteString* opaque_body() const { return std::get_if<ByteString>(&body_); }
  [[nodiscard]] const XmlElement* xml_body() const { return std::get_if<XmlElement>(&body_); }
  [[nodiscard]] const ExtensionBody* body() const;
  // The decoded structure if it is a T, else nullptr (defined in binary.hpp).
  template <typename T>
  [[nodiscard]] const T* get_if() const;
  template <typename T>
  [[nodiscard]] T* get_if();

  friend bool operator==(const ExtensionObject& a, const ExtensionObject& b);

 private:
  NodeId type_id_;
  std::variant<std::monostate, ByteString, XmlElement, std::unique_ptr<ExtensionBody>> body_;
};

class Variant;

namespace detail {

// The C++ type of each built-in type id as stored in a Variant; the large and the recursive
// ones are boxed so that a Variant stays small.
template <typename T>
struct VariantBoxed : std::false_type {};
template <>
struct VariantBoxed<ExpandedNodeId> : std::true_type {};
template <>
struct VariantBoxed<ExtensionObject> : std::true_type {};
template <>
struct VariantBoxed<DataValue> : std::true_type {};
template <>
struct VariantBoxed<DiagnosticInfo> : std::true_type {};

template <typename T>
using VariantScalarSlot = std::conditional_t<VariantBoxed<T>::value, Box<T>, T>;

template <typename T, typename... Ts>
inline constexpr bool kOneOf = (std::is_same_v<T, Ts> || ...);

template <typename T, typename... Ts>
constexpr BuiltinType builtin_type_index() {
  static_assert(kOneOf<T, Ts...>, "not an OPC UA built-in type");
  std::uint8_t id = 0;
  std::uint8_t at = 0;
  ((++at, id = std::is_same_v<T, Ts> ? at : id), ...);
  return static_cast<BuiltinType>(id);
}

// The C++ types a Variant holds as scalars (every built-in type except Variant itself).
template <typename T>
inline constexpr bool kVariantScalar =
    kOneOf<T, bool, std::int8_t, std::uint8_t, std::int16_t, std::uint16_t, std::int32_t, std::uint32_t,
           std::int64_t, std::uint64_t, float, double, String, DateTime, Guid, ByteString, XmlElement, NodeId,
           ExpandedNodeId, StatusCode, QualifiedName, LocalizedText, ExtensionObject, DataValue,
           DiagnosticInfo>;

}  // namespace detail

// Variant (OPC 10000-6 §5.2.2.16): empty (Null), a scalar of one built-in type, or a
// one-dimensional array of one built-in type, optionally reshaped into a matrix by
// array_dimensions (higher rank first; their product equals the number of elements). A Variant
// never holds a scalar Variant, but it may hold an array of Variants.
class Variant {
 public:
  using Storage =
      std::variant<std::monostate, bool, std::int8_t, std::uint8_t, std::int16_t, std::uint16_t, std::int32_t,
                   std::uint32_t, std::int64_t, std::uint64_t, float, double, String, DateTime, Guid,
                   ByteString, XmlElement, NodeId, Box<ExpandedNodeId>, StatusCode, QualifiedName,
                   LocalizedText, Box<ExtensionObject>, Box<DataValue>, Box<DiagnosticInfo>, Array<bool>,
                   Array<std::int8_t>, Array<std::uint8_t>, Array<std::int16_t>, Array<std::uint16_t>,
                   Array<std::int32_t>, Array<std::uint32_t>, Array<std::int64_t>, Array<std::uint64_t>,
                   Array<float>, Array<double>, Array<String>, Array<DateTime>, Array<Guid>,
                   Array<ByteString>, Array<XmlElement>, Array<NodeId>, Array<ExpandedNodeId>,
                   Array<StatusCode>, Array<QualifiedName>, Array<LocalizedText>, Array<ExtensionObject>,
                   Array<DataValue>, Array<Variant>, Array<DiagnosticInfo>>;

  // Storage index of the first array alternative.
  static constexpr std::size_t kFirstArrayIndex = 25;

  Variant() = default;
  // A scalar of a built-in type: Variant(3.5), Variant(std::int32_t{7}), Variant(NodeId(0, 85)).
  template <typename T>
  requires detail::kVariantScalar<std::decay_t<T>> Variant(T&& value)  // NOLINT(google-explicit-constructor)
      : storage_(detail::VariantScalarSlot<std::decay_t<T>>(std::forward<T>(value))) {}
  Variant(const char* text);       // NOLINT(google-explicit-constructor)
  Variant(std::string text);       // NOLINT(google-explicit-constructor)
  Variant(std::string_view text);  // NOLINT(google-explicit-constructor)
  // A one-dimensional array.
  template <typename T>
  requires detail::kVariantScalar<T> || std::is_same_v<T, Variant> Variant(Array<T> values)
      : storage_(std::move(values)) {}  // NOLINT(google-explicit-constructor)
  template <typename T>
  requires detail::kVariantScalar<T> || std::is_same_v<T, Variant> Variant(std::vector<T> values)
      : storage_(Array<T>(std::move(values))) {}  // NOLINT(google-explicit-constructor)
  // A matrix: values in row-major order (higher rank first) and one length per dimension.
  template <typename T>
  static Result<Variant> matrix(Array<T> values, std::vector<std::int32_t> dimensions);

  [[nodiscard]] BuiltinType type() const;
  [[nodiscard]] bool is_empty() const { return storage_.index() == 0; }
  [[nodiscard]] bool is_scalar() const { return !is_empty() && storage_.index() < kFirstArrayIndex; }
  [[nodiscard]] bool is_array() const { return storage_.index() >= kFirstArrayIndex; }
  [[nodiscard]] bool is_matrix() const { return !dimensions_.empty(); }
  // Number of elements of an array, 1 for a scalar, 0 when empty.
  [[nodiscard]] std::size_t array_length() const;
  [[nodiscard]] const std::vector<std::int32_t>& array_dimensions() const { return dimensions_; }
  // Reshapes an array into a matrix; BadEncodingError if the product of the dimensions is not
  // the array length (a dimension <= 0 means "no elements"). Empty dimensions: one-dimensional.
  Status set_array_dimensions(std::vector<std::int32_t> dimensions);

  // The scalar if this Variant holds a T, else nullptr.
  template <typename T>
  [[nodiscard]] const T* get_if() const {
    if constexpr (detail::VariantBoxed<T>::value) {
      const auto* box = std::get_if<Box<T>>(&storage_);
      return box != nullptr ? box->get() : nullptr;
    } else {
      return std::get_if<T>(&storage_);
    }
  }
  // The array if this Variant holds an array of T, else nullptr.
  template <typename T>
  [[nodiscard]] const Array<T>* array_if() const {
    return std::get_if<Array<T>>(&storage_);
  }

  [[nodiscard]] const Storage& storage() const { return storage_; }
  // Mutable access for decoders; keep array_dimensions consistent.
  Storage& storage() { return storage_; }
  void clear();

  friend bool operator==(const Variant&, const Variant&) = default;

 private:
  Storage storage_;
  std::vector<std::int32_t> dimensions_;
};

// DataValue (OPC 10000-4 §7.11, OPC 10000-6 §5.2.2.17). A field is encoded only when it differs
// from its "absent" value: a Null value, a Good status, a 0 timestamp, 0 picoseconds.
// Picoseconds count 10-ps intervals (< 10000) added to the 100-ns timestamp.
struct DataValue {
  Variant value;
  StatusCode status;
  DateTime source_timestamp;
  std::uint16_t source_picoseconds = 0;
  DateTime server_timestamp;
  std::uint16_t server_picoseconds = 0;

  DataValue() = default;
  DataValue(Variant v) : value(std::move(v)) {}  // NOLINT(google-explicit-constructor)
  friend bool operator==(const DataValue&, const DataValue&) = default;
};

// Members of Variant that create or destroy its storage, which needs DataValue complete.
inline Variant::Variant(const char* text) : storage_(String(text)) {}
inline Variant::Variant(std::string text) : storage_(String(std::move(text))) {}
inline Variant::Variant(std::string_view text) : storage_(String(text)) {}

template <typename T>
Result<Variant> Variant::matrix(Array<T> values, std::vector<std::int32_t> dimensions) {
  Variant v(std::move(values));
  if (auto st = v.set_array_dimensions(std::move(dimensions)); !st) {
    return st.error();
  }
  return v;
}

inline void Variant::clear() {
  storage_ = std::monostate{};
  dimensions_.clear();
}

std::string to_string(const DiagnosticInfo& value);
std::string to_string(const ExtensionObject& value);
std::string to_string(const Variant& value);
std::string to_string(const DataValue& value);
std::ostream& operator<<(std::ostream& os, const DiagnosticInfo& value);
std::ostream& operator<<(std::ostream& os, const ExtensionObject& value);
std::ostream& operator<<(std::ostream& os, const Variant& value);
std::ostream& operator<<(std::ostream& os, const DataValue& value);

// The built-in type id of a C++ type that a Variant can hold (Variant itself for arrays).
template <typename T>
constexpr BuiltinType builtin_type_of() {
  // Built-in type id i + 1 is element i of this list (OPC 10000-6 Table 1).
  return detail::builtin_type_index<T, bool, std::int8_t, std::uint8_t, std::int16_t, std::uint16_t,
                                    std::int32_t, std::uint32_t, std::int64_t, std::uint64_t, float, double,
                                    String, DateTime, Guid, ByteString, XmlElement, NodeId, ExpandedNodeId,
                                    StatusCode, QualifiedName, LocalizedText, ExtensionObject, DataValue,
                                    Variant, DiagnosticInfo>();
}

}  // namespace sf::opcua
