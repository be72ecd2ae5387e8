// XSD datatypes → namespace-0 DataTypes (OPC 10000-6 §5.1.2, Table 1 built-in types; NodeIds
// from OPC 10000-6 Annex A / NodeIds.csv).
#include <array>

#include "sf/knowledge/nodeset.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

struct Mapping {
  std::string_view xsd;
  UaDataType ua;
};

constexpr std::array<Mapping, 24> kMap{{
    {"boolean", {1, "Boolean"}},
    {"byte", {2, "SByte"}},
    {"unsignedByte", {3, "Byte"}},
    {"short", {4, "Int16"}},
    {"unsignedShort", {5, "UInt16"}},
    {"int", {6, "Int32"}},
    {"unsignedInt", {7, "UInt32"}},
    {"long", {8, "Int64"}},
    {"integer", {8, "Int64"}},
    {"negativeInteger", {8, "Int64"}},
    {"nonPositiveInteger", {8, "Int64"}},
    {"unsignedLong", {9, "UInt64"}},
    {"nonNegativeInteger", {9, "UInt64"}},
    {"positiveInteger", {9, "UInt64"}},
    {"float", {10, "Float"}},
    {"double", {11, "Double"}},
    {"decimal", {11, "Double"}},  // Part 3's Decimal (i=50) is a structure; a double carries the value
    {"string", {12, "String"}},
    {"normalizedString", {12, "String"}},
    {"token", {12, "String"}},
    {"anyURI", {12, "String"}},
    {"dateTime", {13, "DateTime"}},
    {"date", {13, "DateTime"}},
    {"base64Binary", {15, "ByteString"}},
}};

}  // namespace

UaDataType ua_data_type(std::string_view xsd_datatype) {
  if (xsd_datatype == vocab::kRdfLangString) {
    return {12, "String"};
  }
  if (xsd_datatype.starts_with(vocab::kXsd)) {
    const std::string_view local = xsd_datatype.substr(vocab::kXsd.size());
    for (const Mapping& m : kMap) {
      if (m.xsd == local) {
        return m.ua;
      }
    }
  }
  return {24, "BaseDataType"};
}

}  // namespace sf::knowledge
