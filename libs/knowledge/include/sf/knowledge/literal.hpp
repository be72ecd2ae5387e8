// Typed literal values (RDF 1.1 Concepts §3.3, XML Schema 1.1 Part 2 §3): the value a literal
// denotes, so that literals compare by value as Jena's Node.sameValueAs does — xsd:int "1",
// xsd:integer "01" and xsd:decimal "1.0" are the same value; xsd:double and xsd:float form
// their own value spaces; ill-formed literals and unknown datatypes equal only themselves.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace sf::knowledge {

enum class ValueClass : std::uint8_t {
  other,        // unknown datatype or ill-formed lexical form: the term is its own value
  string,       // xsd:string (simple literals are xsd:string in RDF 1.1)
  lang_string,  // rdf:langString; the language tag compares case-insensitively (BCP 47)
  decimal,      // xsd:decimal and every integer type derived from it (XSD Part 2 §3.3.3, §3.4)
  float_,       // xsd:float: IEEE single precision, kept widened to double
  double_,      // xsd:double
  boolean,      // xsd:boolean: "true"/"1", "false"/"0"
  date_time,    // xsd:dateTime and xsd:date (a date is its midnight), normalised to UTC when zoned
};

// A decimal value mantissa * 10^-scale, normalised (no trailing zero digits when scale > 0).
struct Decimal {
  std::int64_t mantissa = 0;
  std::int32_t scale = 0;

  [[nodiscard]] bool integral() const { return scale == 0; }
  [[nodiscard]] double to_double() const;
};

struct LiteralValue {
  ValueClass cls = ValueClass::other;
  Decimal decimal;            // decimal
  double number = 0;          // float_, double_ (and the double value of a decimal)
  bool boolean = false;       // boolean
  std::int64_t seconds = 0;   // date_time: seconds since 1970-01-01T00:00:00 (UTC when zoned)
  std::int32_t nanos = 0;     // date_time: fraction of the second
  bool zoned = false;         // date_time: had a time zone
  std::string_view lexical;   // string, lang_string: the text; other: the lexical form
  std::string_view lang;      // lang_string: the tag as written
  std::string_view datatype;  // other: the datatype IRI

  [[nodiscard]] bool numeric() const {
    return cls == ValueClass::decimal || cls == ValueClass::float_ || cls == ValueClass::double_;
  }
};

// Parses a literal's lexical form for its datatype (XSD whitespace "collapse" applies to the
// non-string types). The views in the result point into the arguments.
LiteralValue parse_literal(std::string_view lexical, std::string_view datatype, std::string_view lang);

// Value equality (Jena's sameValueAs) and a hash consistent with it. Only meaningful for
// values whose class is not `other` (those compare as terms).
bool same_value(const LiteralValue& a, const LiteralValue& b);
std::size_t value_hash(const LiteralValue& v);

// Order of two numbers or two instants (Jena's Util.compareTypedLiterals): -1, 0, +1, or nothing
// when they are not comparable (different kinds, or a zoned and an unzoned dateTime, which XSD
// calls indeterminate). A float or double on either side compares as double; two decimals
// compare exactly (Jena compares their truncated long values: see docs/knowledge.md).
std::optional<int> compare_values(const LiteralValue& a, const LiteralValue& b);

// A literal made by a builtin: its lexical form and datatype IRI.
struct MadeLiteral {
  std::string lexical;
  std::string_view datatype;
};

enum class ArithmeticOp : std::uint8_t { sum, difference, product, quotient };

// Jena's arithmetic builtins: with a float or double operand the result is an xsd:double;
// two integral values give an integer (xsd:int when it fits 32 bits, else xsd:long; quotient
// truncates as Java's long division). Two decimals of which one has a fraction give the exact
// xsd:decimal (Jena truncates them to longs). Nothing on overflow or division by zero of integers.
std::optional<MadeLiteral> arithmetic(ArithmeticOp op, const LiteralValue& a, const LiteralValue& b);

// Java's Double.toString (Jena writes computed doubles with it): "21.5", "1.0E7", "1.0E-4", "NaN".
std::string java_double_string(double d);
// XSD canonical decimal: "3.5", "-0.25", "4.0" for an integral value.
std::string decimal_string(const Decimal& d);

}  // namespace sf::knowledge
