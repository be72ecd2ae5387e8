// Small pieces the Contract Net roles share: the visitor of message variants and the
// incarnation a role starts with when its configuration names none.
#pragma once

#include <cstdint>
#include <random>

namespace sf::negotiation::detail {

// std::visit over a message variant with one lambda per alternative.
template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

// A non-zero random incarnation: a restarted role is told apart from its earlier life, so
// messages addressed to that life are not taken for its own.
inline std::uint32_t random_incarnation() {
  std::random_device rd;
  std::uint32_t v = 0;
  while (v == 0) {
    v = rd();
  }
  return v;
}

}  // namespace sf::negotiation::detail
