// What the rule parser and the engine know about each builtin: Jena's name, argument count
// (Builtin.getArgLength, or the checks in bodyCall), where it may appear, and whether it is
// monotonic (Builtin.isMonotonic).
#pragma once

#include <string_view>

#include "sf/knowledge/rules.hpp"

namespace sf::knowledge::rules {

struct BuiltinInfo {
  Builtin op;
  std::string_view name;
  int min_args;
  int max_args;  // -1: no limit
  bool in_body;
  bool in_head;
  bool monotonic;
};

const BuiltinInfo* find_builtin(std::string_view name);
const BuiltinInfo& builtin_info(Builtin op);

}  // namespace sf::knowledge::rules
