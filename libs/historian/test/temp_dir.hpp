// The historian tests' TempDir is the shared one.
#pragma once

#include "sf/testing/temp_dir.hpp"

namespace sf::historian::test {

using TempDir = sf::testing::TempDir;

}  // namespace sf::historian::test
