// The Like operator's pattern matching (OPC 10000-4 §7.4.3 Table 118): '%' matches any run of
// characters, '_' any single one, '[abc]' / '[a-z]' one of a set, '[^...]' one not in it, and
// '\' makes the next character literal. Matching is on bytes (UTF-8 is not decoded), by dynamic
// programming so hostile patterns stay O(text × pattern).
#include <string>
#include <vector>

#include "server/subscriptions/event_filter.hpp"

namespace sf::opcua::subs {
namespace {

struct Token {
  enum class Kind { Literal, AnyOne, AnyRun, Set } kind = Kind::Literal;
  char literal = 0;
  bool negated = false;
  std::string set;  // pairs of (low, high) characters
};

// Parses one "[...]" starting after '['; returns the index after ']' (or the end).
std::size_t parse_set(std::string_view p, std::size_t i, Token& t) {
  t.kind = Token::Kind::Set;
  if (i < p.size() && p[i] == '^') {
    t.negated = true;
    ++i;
  }
  while (i < p.size() && p[i] != ']') {
    char low = p[i];
    if (low == '\\' && i + 1 < p.size()) {
      low = p[++i];
    }
    char high = low;
    if (i + 2 < p.size() && p[i + 1] == '-' && p[i + 2] != ']') {
      high = p[i + 2];
      i += 2;
    }
    t.set += low;
    t.set += high;
    ++i;
  }
  return i < p.size() ? i + 1 : i;
}

std::vector<Token> tokenize(std::string_view p) {
  std::vector<Token> tokens;
  for (std::size_t i = 0; i < p.size();) {
    Token t;
    const char c = p[i];
    if (c == '%') {
      t.kind = Token::Kind::AnyRun;
      ++i;
    } else if (c == '_') {
      t.kind = Token::Kind::AnyOne;
      ++i;
    } else if (c == '[') {
      i = parse_set(p, i + 1, t);
    } else if (c == '\\' && i + 1 < p.size()) {
      t.literal = p[i + 1];
      i += 2;
    } else {
      t.literal = c;
      ++i;
    }
    tokens.push_back(std::move(t));
  }
  return tokens;
}

bool matches_one(const Token& t, char c) {
  switch (t.kind) {
    case Token::Kind::AnyOne:
      return true;
    case Token::Kind::Set: {
      bool in = false;
      for (std::size_t k = 0; k + 1 < t.set.size(); k += 2) {
        in = in || (c >= t.set[k] && c <= t.set[k + 1]);
      }
      return in != t.negated;
    }
    default:
      return c == t.literal;
  }
}

}  // namespace

bool like_matches(std::string_view text, std::string_view pattern) {
  const std::vector<Token> tokens = tokenize(pattern);
  // reach[j]: the first j characters of the text are matched by the tokens seen so far.
  std::vector<char> reach(text.size() + 1, 0);
  reach[0] = 1;
  for (const Token& t : tokens) {
    std::vector<char> next(text.size() + 1, 0);
    if (t.kind == Token::Kind::AnyRun) {
      char any = 0;
      for (std::size_t j = 0; j <= text.size(); ++j) {
        any = static_cast<char>(any | reach[j]);
        next[j] = any;
      }
    } else {
      for (std::size_t j = 0; j < text.size(); ++j) {
        next[j + 1] = static_cast<char>(reach[j] != 0 && matches_one(t, text[j]));
      }
    }
    reach.swap(next);
  }
  return reach[text.size()] != 0;
}

}  // namespace sf::opcua::subs
