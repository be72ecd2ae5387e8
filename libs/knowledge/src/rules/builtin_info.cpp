#include "builtin_info.hpp"

#include <array>

namespace sf::knowledge::rules {
namespace {

// Jena 4.5 org.apache.jena.reasoner.rulesys.builtins.*
constexpr std::array<BuiltinInfo, 22> kBuiltins{{
    {Builtin::equal, "equal", 2, 2, true, false, true},
    {Builtin::not_equal, "notEqual", 2, 2, true, false, true},
    {Builtin::less_than, "lessThan", 2, 2, true, false, true},
    {Builtin::greater_than, "greaterThan", 2, 2, true, false, true},
    {Builtin::le, "le", 2, 2, true, false, true},
    {Builtin::ge, "ge", 2, 2, true, false, true},
    {Builtin::sum, "sum", 3, 3, true, false, true},
    {Builtin::difference, "difference", 3, 3, true, false, true},
    {Builtin::product, "product", 3, 3, true, false, true},
    {Builtin::quotient, "quotient", 3, 3, true, false, true},
    {Builtin::min, "min", 3, 3, true, false, true},
    {Builtin::max, "max", 3, 3, true, false, true},
    {Builtin::no_value, "noValue", 2, 3, true, false, false},
    {Builtin::regex, "regex", 2, -1, true, false, true},
    {Builtin::str_concat, "strConcat", 1, -1, true, false, true},
    {Builtin::make_skolem, "makeSkolem", 1, -1, true, false, true},
    {Builtin::is_literal, "isLiteral", 1, 1, true, false, true},
    {Builtin::not_literal, "notLiteral", 1, 1, true, false, true},
    {Builtin::bound, "bound", 1, -1, true, false, true},
    {Builtin::unbound, "unbound", 1, -1, true, false, true},
    {Builtin::print, "print", 0, -1, true, true, true},
    {Builtin::remove, "remove", 1, -1, false, true, false},
}};

}  // namespace

const BuiltinInfo* find_builtin(std::string_view name) {
  for (const auto& b : kBuiltins) {
    if (b.name == name) {
      return &b;
    }
  }
  return nullptr;
}

const BuiltinInfo& builtin_info(Builtin op) {
  for (const auto& b : kBuiltins) {
    if (b.op == op) {
      return b;
    }
  }
  return kBuiltins[0];
}

}  // namespace sf::knowledge::rules

namespace sf::knowledge {
std::string_view builtin_name(Builtin b) {
  return rules::builtin_info(b).name;
}
}  // namespace sf::knowledge
