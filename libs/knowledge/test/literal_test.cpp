#include "sf/knowledge/literal.hpp"

#include <gtest/gtest.h>

#include "sf/knowledge/term.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

std::string xsd(std::string_view local) {
  return std::string(vocab::kXsd) + std::string(local);
}

TEST(Literal, NumbersOfTheDecimalFamilyAreEqualByValue) {
  Dictionary d;
  const TermId int1 = d.literal("1", xsd("int"));
  const TermId integer01 = d.literal("01", xsd("integer"));
  const TermId dec10 = d.literal("1.0", xsd("decimal"));
  const TermId dec15 = d.literal("1.5", xsd("decimal"));
  EXPECT_NE(int1, dec10);                          // distinct terms ...
  EXPECT_EQ(d.value_id(int1), d.value_id(dec10));  // ... one value
  EXPECT_EQ(d.value_id(int1), d.value_id(integer01));
  EXPECT_NE(d.value_id(int1), d.value_id(dec15));
}

TEST(Literal, DoubleFloatAndDecimalAreSeparateValueSpaces) {
  Dictionary d;
  const TermId dbl = d.literal("1.0", xsd("double"));
  EXPECT_EQ(d.value_id(dbl), d.value_id(d.literal("1E0", xsd("double"))));
  EXPECT_NE(d.value_id(dbl), d.value_id(d.literal("1", xsd("int"))));
  EXPECT_NE(d.value_id(dbl), d.value_id(d.literal("1.0", xsd("float"))));
  // Java's Double.equals: NaN is one value, 0.0 and -0.0 are two.
  EXPECT_EQ(d.value_id(d.literal("NaN", xsd("double"))), d.value_id(d.literal("NaN", xsd("double"))));
  EXPECT_NE(d.value_id(d.literal("0.0", xsd("double"))), d.value_id(d.literal("-0.0", xsd("double"))));
}

TEST(Literal, IllFormedAndOutOfRangeLiteralsEqualOnlyThemselves) {
  Dictionary d;
  const TermId big = d.literal("3000000000", xsd("int"));
  EXPECT_EQ(d.value(big)->cls, ValueClass::other);
  EXPECT_NE(d.value_id(big), d.value_id(d.literal("3000000000", xsd("long"))));
  EXPECT_EQ(d.value(d.literal("300", xsd("byte")))->cls, ValueClass::other);
  EXPECT_EQ(d.value(d.literal("abc", xsd("integer")))->cls, ValueClass::other);
  EXPECT_EQ(d.value(d.literal(" 7 ", xsd("int")))->decimal.mantissa, 7);  // whitespace collapse
}

TEST(Literal, StringsBooleansAndLanguageTags) {
  Dictionary d;
  EXPECT_EQ(d.literal("x"), d.literal("x", vocab::kXsdString));  // RDF 1.1: one term
  EXPECT_EQ(d.value_id(d.literal("true", vocab::kXsdBoolean)),
            d.value_id(d.literal("1", vocab::kXsdBoolean)));
  EXPECT_EQ(d.value_id(d.literal("a", {}, "en")), d.value_id(d.literal("a", {}, "EN")));
  EXPECT_NE(d.value_id(d.literal("a", {}, "en")), d.value_id(d.literal("a")));
}

TEST(Literal, DateTimesCompareAsInstants) {
  Dictionary d;
  const TermId utc = d.literal("2024-01-01T00:00:00Z", vocab::kXsdDateTime);
  const TermId plus1 = d.literal("2024-01-01T01:00:00+01:00", vocab::kXsdDateTime);
  const TermId local = d.literal("2024-01-01T00:00:00", vocab::kXsdDateTime);
  EXPECT_EQ(d.value_id(utc), d.value_id(plus1));
  EXPECT_NE(d.value_id(utc), d.value_id(local));
  const TermId later = d.literal("2024-01-01T00:00:00.5Z", vocab::kXsdDateTime);
  EXPECT_EQ(compare_values(*d.value(utc), *d.value(later)), -1);
  EXPECT_FALSE(compare_values(*d.value(utc), *d.value(local)).has_value());  // indeterminate
  EXPECT_EQ(d.value(d.literal("2024-02-30T00:00:00Z", vocab::kXsdDateTime))->cls, ValueClass::other);
}

TEST(Literal, CompareMixesTypesLikeJena) {
  Dictionary d;
  const auto cmp = [&](TermId a, TermId b) { return compare_values(*d.value(a), *d.value(b)); };
  EXPECT_EQ(cmp(d.literal("20", xsd("int")), d.literal("20.5", xsd("decimal"))), -1);    // exact decimals
  EXPECT_EQ(cmp(d.literal("80.1", xsd("double")), d.literal("80.1", xsd("float"))), 1);  // float widened
  EXPECT_EQ(cmp(d.literal("2", xsd("integer")), d.literal("2.0", xsd("double"))), 0);
  EXPECT_FALSE(cmp(d.literal("2"), d.literal("2", xsd("int"))).has_value());
}

TEST(Literal, ArithmeticResultTypesFollowJena) {
  Dictionary d;
  const auto op = [&](ArithmeticOp o, TermId a, TermId b) { return arithmetic(o, *d.value(a), *d.value(b)); };
  const TermId i7 = d.literal("7", xsd("integer"));
  const TermId i2 = d.literal("2", xsd("int"));
  auto q = op(ArithmeticOp::quotient, i7, i2);
  ASSERT_TRUE(q);
  EXPECT_EQ(q->lexical, "3");  // Java long division
  EXPECT_EQ(q->datatype, vocab::kXsdInt);
  auto big = op(ArithmeticOp::sum, d.literal("2147483647", xsd("int")), i2);
  ASSERT_TRUE(big);
  EXPECT_EQ(big->datatype, vocab::kXsdLong);
  auto dbl = op(ArithmeticOp::product, d.literal("20.5", xsd("double")), d.literal("1000000", xsd("int")));
  ASSERT_TRUE(dbl);
  EXPECT_EQ(dbl->lexical, "2.05E7");
  EXPECT_EQ(dbl->datatype, vocab::kXsdDouble);
  auto flt = op(ArithmeticOp::sum, d.literal("20.5", xsd("double")), d.literal("0.1", xsd("float")));
  EXPECT_EQ(flt->lexical, "20.600000001490116");  // the float's exact value, as Java widens it
  auto dec = op(ArithmeticOp::sum, d.literal("2.5", xsd("decimal")), d.literal("1", xsd("int")));
  EXPECT_EQ(dec->lexical, "3.5");
  EXPECT_EQ(dec->datatype, vocab::kXsdDecimal);
  EXPECT_FALSE(op(ArithmeticOp::quotient, i7, d.literal("0", xsd("int"))));
  EXPECT_FALSE(op(ArithmeticOp::sum, i7, d.literal("x")));
}

TEST(Literal, JavaDoubleFormatting) {
  EXPECT_EQ(java_double_string(21.5), "21.5");
  EXPECT_EQ(java_double_string(100.0), "100.0");
  EXPECT_EQ(java_double_string(0.001), "0.001");
  EXPECT_EQ(java_double_string(0.0001), "1.0E-4");
  EXPECT_EQ(java_double_string(1e7), "1.0E7");
  EXPECT_EQ(java_double_string(-1234567.25), "-1234567.25");
  EXPECT_EQ(java_double_string(6.833333333333333), "6.833333333333333");
  EXPECT_EQ(java_double_string(0.0), "0.0");
}

}  // namespace
}  // namespace sf::knowledge
