// The checks of a parsed layout that need all of it: unique names, belts
// that meet, stations and dispensers every assigned robot reaches, values in
// range. The first failure is returned, naming the entry's file:line:column.
#pragma once

#include "sf/line/layout.hpp"

namespace sf::line {

Status check_layout(const Layout& layout);

}  // namespace sf::line
