// Helpers shared by the opcua sources; not part of the module's API.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace sf::opcua {

// True when the matrix dimensions describe exactly `length` elements: their product, or 0 when
// a dimension is <= 0 (OPC 10000-6 §5.2.2.16).
bool dimensions_match(const std::vector<std::int32_t>& dimensions, std::size_t length);

}  // namespace sf::opcua
