// The repository's ontology and rules, built into the cloud so that `knowledge: {}` works from
// any directory (as the line's default layout is built into libs/line).
#pragma once

#include <string_view>

namespace sf::cloud::detail {

std::string_view default_ontology();  // ontology/candy-factory.ttl
std::string_view default_rules();     // rules/candy-factory.rules

}  // namespace sf::cloud::detail
