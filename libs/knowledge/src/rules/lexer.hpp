// Tokens of a Jena rule file. Like Jena's Rule.rulesParserFromReader, whole lines starting with
// '#' or '//' are comments and `@prefix` lines declare prefixes; the rest is split at the
// delimiters ( ) [ ] , and white space, with '...' and "..." literals (a backslash takes the
// next character literally, as org.apache.jena.util.Tokenizer does).
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"

namespace sf::knowledge::rules {

struct Token {
  enum class Kind { word, open_paren, close_paren, open_bracket, close_bracket, literal };
  Kind kind = Kind::word;
  std::string text;      // a word, or a literal's content
  std::string datatype;  // literal: the "^^..." suffix without "^^" (may be empty)
  int line = 0;
  int column = 0;
};

struct Lexed {
  std::vector<Token> tokens;
  std::map<std::string, std::string> prefixes;
};

// Errors are "file:line:column: message".
Result<Lexed> lex(std::string_view text, std::string_view file);

}  // namespace sf::knowledge::rules
