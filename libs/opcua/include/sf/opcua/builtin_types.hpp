// The scalar built-in types of OPC UA (OPC 10000-3 §8, OPC 10000-6 §5.1/§5.2.2) as C++ value
// types with equality, hashing where a type can key a map, and a readable to_string.
// Variant, DataValue, ExtensionObject and DiagnosticInfo are in variant.hpp.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <iosfwd>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::opcua {

// Built-in type ids (OPC 10000-6 §5.1.2, Table 1): the low six bits of a Variant's encoding mask.
enum class BuiltinType : std::uint8_t {
  Null = 0,
  Boolean = 1,
  SByte = 2,
  Byte = 3,
  Int16 = 4,
  UInt16 = 5,
  Int32 = 6,
  UInt32 = 7,
  Int64 = 8,
  UInt64 = 9,
  Float = 10,
  Double = 11,
  String = 12,
  DateTime = 13,
  Guid = 14,
  ByteString = 15,
  XmlElement = 16,
  NodeId = 17,
  ExpandedNodeId = 18,
  StatusCode = 19,
  QualifiedName = 20,
  LocalizedText = 21,
  ExtensionObject = 22,
  DataValue = 23,
  Variant = 24,
  DiagnosticInfo = 25,
};
std::string_view to_string(BuiltinType type);

// String (OPC 10000-6 §5.2.2.4): UTF-8 text that may be null (length -1), which differs from
// the empty string (length 0). A default-constructed String is null.
class String {
 public:
  String() = default;
  String(std::string text) : text_(std::move(text)), null_(false) {}  // NOLINT(google-explicit-constructor)
  String(std::string_view text) : text_(text), null_(false) {}        // NOLINT(google-explicit-constructor)
  String(const char* text) : text_(text), null_(false) {}             // NOLINT(google-explicit-constructor)

  [[nodiscard]] bool is_null() const { return null_; }
  // True for null and for empty strings.
  [[nodiscard]] bool empty() const { return text_.empty(); }
  [[nodiscard]] std::size_t size() const { return text_.size(); }
  // The text; "" when null.
  [[nodiscard]] const std::string& str() const { return text_; }
  [[nodiscard]] std::string_view view() const { return text_; }
  void assign(std::string_view text) {
    text_.assign(text);
    null_ = false;
  }
  void set_null() {
    text_.clear();
    null_ = true;
  }

  friend bool operator==(const String&, const String&) = default;
  friend bool operator==(const String& a, std::string_view b) { return !a.null_ && a.text_ == b; }
  friend bool operator==(const String& a, const std::string& b) { return !a.null_ && a.text_ == b; }
  friend bool operator==(const String& a, const char* b) { return !a.null_ && a.text_ == b; }

 private:
  std::string text_;
  bool null_ = true;
};

// ByteString (OPC 10000-6 §5.2.2.7): opaque bytes, null (length -1) or not. Default: null.
class ByteString {
 public:
  ByteString() = default;
  ByteString(Bytes bytes) : bytes_(std::move(bytes)), null_(false) {}  // NOLINT(google-explicit-constructor)
  ByteString(std::initializer_list<std::uint8_t> bytes) : bytes_(bytes), null_(false) {}
  explicit ByteString(ByteSpan bytes) : bytes_(bytes.begin(), bytes.end()), null_(false) {}
  // The UTF-8 bytes of text (certificates, nonces and passwords are often built from text).
  static ByteString from_text(std::string_view text);

  [[nodiscard]] bool is_null() const { return null_; }
  [[nodiscard]] bool empty() const { return bytes_.empty(); }
  [[nodiscard]] std::size_t size() const { return bytes_.size(); }
  [[nodiscard]] const Bytes& bytes() const { return bytes_; }
  [[nodiscard]] ByteSpan span() const { return bytes_; }
  void assign(ByteSpan bytes) {
    bytes_.assign(bytes.begin(), bytes.end());
    null_ = false;
  }
  void set_null() {
    bytes_.clear();
    null_ = true;
  }

  friend bool operator==(const ByteString&, const ByteString&) = default;

 private:
  Bytes bytes_;
  bool null_ = true;
};

// XmlElement (OPC 10000-6 §5.2.2.8): an XML fragment, encoded like a String.
struct XmlElement {
  String xml;
  friend bool operator==(const XmlElement&, const XmlElement&) = default;
};

// Guid (OPC 10000-6 §5.2.2.6): Data1..Data3 little-endian, Data4 as 8 raw bytes.
struct Guid {
  std::uint32_t data1 = 0;
  std::uint16_t data2 = 0;
  std::uint16_t data3 = 0;
  std::array<std::uint8_t, 8> data4{};

  // "72962B91-FA75-4AE6-8D28-B404DC7DAF63" (case-insensitive, braces allowed).
  static Result<Guid> parse(std::string_view text);
  [[nodiscard]] bool is_null() const { return *this == Guid{}; }
  friend auto operator<=>(const Guid&, const Guid&) = default;
};

// DateTime (OPC 10000-6 §5.2.2.5): 100-ns intervals since 1601-01-01 00:00 UTC as Int64. The
// raw tick count is kept as received; conversions clamp as the spec says: 0 is the earliest
// representable time and INT64_MAX the latest.
class DateTime {
 public:
  static constexpr std::int64_t kTicksPerSecond = 10'000'000;
  // Ticks from 1601-01-01 to the Unix epoch 1970-01-01.
  static constexpr std::int64_t kUnixEpochTicks = 116'444'736'000'000'000;

  constexpr DateTime() = default;
  constexpr explicit DateTime(std::int64_t ticks) : ticks_(ticks) {}

  static constexpr DateTime min() { return DateTime{0}; }
  static constexpr DateTime max() { return DateTime{INT64_MAX}; }
  // Times at or before 1601 become 0, times at or after 9999-12-31 23:59:59 become max().
  static DateTime from_system_clock(std::chrono::system_clock::time_point t);
  static DateTime from_unix_seconds(std::int64_t seconds);
  // The xs:dateTime form of the XML encoding (OPC 10000-6 §5.3.1.6): "2024-05-01T12:00:00Z",
  // with up to 7 fraction digits and "Z" or a "+hh:mm"/"-hh:mm" offset (none = UTC).
  static Result<DateTime> parse(std::string_view text);
  // Saturates at the limits of system_clock (which cannot represent 1601 or 9999).
  [[nodiscard]] std::chrono::system_clock::time_point to_system_clock() const;

  [[nodiscard]] constexpr std::int64_t ticks() const { return ticks_; }
  [[nodiscard]] constexpr bool is_min() const { return ticks_ <= 0; }
  friend constexpr auto operator<=>(const DateTime&, const DateTime&) = default;

 private:
  std::int64_t ticks_ = 0;
};

enum class NodeIdType : std::uint8_t { Numeric = 0, String = 1, Guid = 2, Opaque = 3 };

// NodeId (OPC 10000-3 §8.2, OPC 10000-6 §5.2.2.9): a namespace index and a numeric, string,
// Guid or opaque identifier. Default: the null NodeId i=0.
struct NodeId {
  using Identifier = std::variant<std::uint32_t, String, Guid, ByteString>;

  std::uint16_t namespace_index = 0;
  Identifier identifier = std::uint32_t{0};

  NodeId() = default;
  NodeId(std::uint16_t ns, std::uint32_t id) : namespace_index(ns), identifier(id) {}
  NodeId(std::uint16_t ns, String id) : namespace_index(ns), identifier(std::move(id)) {}
  NodeId(std::uint16_t ns, Guid id) : namespace_index(ns), identifier(id) {}
  NodeId(std::uint16_t ns, ByteString id) : namespace_index(ns), identifier(std::move(id)) {}

  // Parses the text form of OPC 10000-6 §5.3.1.10: "i=85", "ns=2;s=Demo",
  // "ns=1;g=72962B91-FA75-4AE6-8D28-B404DC7DAF63", "ns=1;b=<base64>".
  static Result<NodeId> parse(std::string_view text);

  [[nodiscard]] NodeIdType type() const { return static_cast<NodeIdType>(identifier.index()); }
  [[nodiscard]] bool is_numeric() const { return identifier.index() == 0; }
  // The numeric identifier, or 0 for other identifier types.
  [[nodiscard]] std::uint32_t numeric() const;
  // OPC 10000-3 §8.2.4: namespace 0 and the identifier type's null value.
  [[nodiscard]] bool is_null() const;
  [[nodiscard]] std::size_t hash() const;

  friend bool operator==(const NodeId&, const NodeId&) = default;
};

// ExpandedNodeId (OPC 10000-6 §5.2.2.10): a NodeId that may name its namespace by URI and
// live in another server. The URI is encoded when not null, the server index when not 0.
struct ExpandedNodeId {
  NodeId node_id;
  String namespace_uri;
  std::uint32_t server_index = 0;

  ExpandedNodeId() = default;
  ExpandedNodeId(NodeId id) : node_id(std::move(id)) {}  // NOLINT(google-explicit-constructor)
  ExpandedNodeId(NodeId id, String uri, std::uint32_t server = 0)
      : node_id(std::move(id)), namespace_uri(std::move(uri)), server_index(server) {}

  [[nodiscard]] bool is_local() const { return namespace_uri.is_null() && server_index == 0; }
  friend bool operator==(const ExpandedNodeId&, const ExpandedNodeId&) = default;
};

// QualifiedName (OPC 10000-6 §5.2.2.13): a name qualified by a namespace index.
struct QualifiedName {
  std::uint16_t namespace_index = 0;
  String name;

  QualifiedName() = default;
  QualifiedName(std::uint16_t ns, String n) : namespace_index(ns), name(std::move(n)) {}
  friend bool operator==(const QualifiedName&, const QualifiedName&) = default;
};

// LocalizedText (OPC 10000-6 §5.2.2.14): text with an optional locale; a field is encoded when
// it is not null.
struct LocalizedText {
  String locale;
  String text;

  LocalizedText() = default;
  LocalizedText(String locale_id, String t) : locale(std::move(locale_id)), text(std::move(t)) {}
  friend bool operator==(const LocalizedText&, const LocalizedText&) = default;
};

// Readable forms for logs and test output.
std::string to_string(const String& value);      // "\"text\"" or "null"
std::string to_string(const ByteString& value);  // "0x01a4ff" (first 32 bytes) or "null"
std::string to_string(const XmlElement& value);
std::string to_string(const Guid& value);            // "72962B91-FA75-4AE6-8D28-B404DC7DAF63"
std::string to_string(DateTime value);               // "2024-05-01T12:00:00.1234567Z"
std::string to_string(const NodeId& value);          // "i=85", "ns=2;s=Demo"
std::string to_string(const ExpandedNodeId& value);  // "svr=1;nsu=http://x/;s=Demo"
std::string to_string(const QualifiedName& value);   // "2:Demo" ("Demo" in namespace 0)
std::string to_string(const LocalizedText& value);   // "\"Hello\"@en"

std::ostream& operator<<(std::ostream& os, const String& value);
std::ostream& operator<<(std::ostream& os, const ByteString& value);
std::ostream& operator<<(std::ostream& os, const Guid& value);
std::ostream& operator<<(std::ostream& os, DateTime value);
std::ostream& operator<<(std::ostream& os, const NodeId& value);
std::ostream& operator<<(std::ostream& os, const ExpandedNodeId& value);
std::ostream& operator<<(std::ostream& os, const QualifiedName& value);
std::ostream& operator<<(std::ostream& os, const LocalizedText& value);

// Base64 (RFC 4648) for opaque NodeIds in text form.
std::string base64_encode(ByteSpan bytes);
Result<Bytes> base64_decode(std::string_view text);

}  // namespace sf::opcua

template <>
struct std::hash<sf::opcua::NodeId> {
  std::size_t operator()(const sf::opcua::NodeId& id) const noexcept { return id.hash(); }
};
