#include "lexer.hpp"

#include <fmt/format.h>

namespace sf::knowledge::rules {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}
bool is_delimiter(char c) {
  return is_space(c) || c == '(' || c == ')' || c == '[' || c == ']' || c == ',';
}

class Lexer {
 public:
  Lexer(std::string_view text, std::string_view file) : text_(text), file_(file) {}

  Result<Lexed> run() {
    while (pos_ < text_.size()) {
      if (at_line_start_) {
        SF_TRY(line_start());
        continue;
      }
      const char c = text_[pos_];
      if (c == '\n') {
        advance();
        at_line_start_ = true;
      } else if (is_space(c) || c == ',') {
        advance();
      } else if (c == '(' || c == ')' || c == '[' || c == ']') {
        push_punct(c);
      } else if (c == '\'' || c == '"') {
        SF_TRY(literal(c));
      } else {
        word();
      }
    }
    return std::move(out_);
  }

 private:
  Error error_at(int line, int column, std::string_view message) const {
    return make_error(Errc::malformed, fmt::format("{}:{}:{}: {}", file_, line, column, message));
  }

  void advance() {
    if (text_[pos_] == '\n') {
      ++line_;
      column_ = 1;
    } else if ((static_cast<unsigned char>(text_[pos_]) & 0xC0) != 0x80) {
      ++column_;  // count UTF-8 characters, not bytes
    }
    ++pos_;
  }

  std::string_view rest_of_line() const {
    const std::size_t end = text_.find('\n', pos_);
    return text_.substr(pos_, end == std::string_view::npos ? std::string_view::npos : end - pos_);
  }

  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      advance();
    }
  }

  // Comment lines and directives are recognised at the start of a line (after blanks).
  Status line_start() {
    while (pos_ < text_.size() && text_[pos_] != '\n' && is_space(text_[pos_])) {
      advance();
    }
    at_line_start_ = false;
    const std::string_view line = rest_of_line();
    if (line.starts_with("#") || line.starts_with("//")) {
      skip_line();
    } else if (line.starts_with("@prefix")) {
      SF_TRY(prefix_directive(line));
      skip_line();
    } else if (line.starts_with("@")) {
      return error_at(line_, column_,
                      fmt::format("unsupported directive '{}'", line.substr(0, line.find(' '))));
    }
    return {};
  }

  // "@prefix name: <iri> ." (the trailing dot is optional).
  Status prefix_directive(std::string_view line) {
    const int line_no = line_;
    const int col = column_;
    std::string_view rest = line.substr(7);
    const auto trim = [](std::string_view& s) {
      while (!s.empty() && is_space(s.front())) {
        s.remove_prefix(1);
      }
    };
    trim(rest);
    const std::size_t colon = rest.find(':');
    const std::size_t lt = rest.find('<');
    if (colon == std::string_view::npos || lt == std::string_view::npos || colon > lt) {
      return error_at(line_no, col, "malformed @prefix: expected '@prefix name: <iri>'");
    }
    std::string name(rest.substr(0, colon));
    if (name.find_first_of(" \t") != std::string::npos) {
      return error_at(line_no, col, "malformed @prefix: the name may not contain blanks");
    }
    const std::size_t gt = rest.find('>', lt);
    if (gt == std::string_view::npos) {
      return error_at(line_no, col, "malformed @prefix: missing '>'");
    }
    out_.prefixes[name] = std::string(rest.substr(lt + 1, gt - lt - 1));
    return {};
  }

  void push_punct(char c) {
    Token t;
    t.kind = c == '('   ? Token::Kind::open_paren
             : c == ')' ? Token::Kind::close_paren
             : c == '[' ? Token::Kind::open_bracket
                        : Token::Kind::close_bracket;
    t.text = std::string(1, c);
    t.line = line_;
    t.column = column_;
    out_.tokens.push_back(std::move(t));
    advance();
  }

  Status literal(char quote) {
    Token t;
    t.kind = Token::Kind::literal;
    t.line = line_;
    t.column = column_;
    advance();
    while (pos_ < text_.size() && text_[pos_] != quote) {
      if (text_[pos_] == '\\') {
        advance();
        if (pos_ >= text_.size()) {
          break;
        }
      }
      t.text += text_[pos_];
      advance();
    }
    if (pos_ >= text_.size()) {
      return error_at(t.line, t.column, "unterminated literal");
    }
    advance();  // closing quote
    if (text_.substr(pos_).starts_with("^^")) {
      advance();
      advance();
      while (pos_ < text_.size() && !is_delimiter(text_[pos_])) {
        t.datatype += text_[pos_];
        advance();
      }
      if (t.datatype.empty()) {
        return error_at(t.line, t.column, "literal with an empty ^^datatype");
      }
    }
    out_.tokens.push_back(std::move(t));
    return {};
  }

  void word() {
    Token t;
    t.line = line_;
    t.column = column_;
    while (pos_ < text_.size() && !is_delimiter(text_[pos_])) {
      t.text += text_[pos_];
      advance();
    }
    out_.tokens.push_back(std::move(t));
  }

  std::string_view text_;
  std::string_view file_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
  bool at_line_start_ = true;
  Lexed out_;
};

}  // namespace

Result<Lexed> lex(std::string_view text, std::string_view file) {
  return Lexer(text, file).run();
}

}  // namespace sf::knowledge::rules
