// The rule grammar of Jena's Rule.Parser (Rule.java): rules, clauses and nodes, with
// positions for every error. Stricter than Jena where Jena silently makes a relative IRI of a
// bare word or defers an unknown builtin to run time.
#include <algorithm>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "builtin_info.hpp"
#include "lexer.hpp"
#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/rules.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace rules {
namespace {

using Kind = Token::Kind;

// Jena's PrintUtil prefixes, known in every rule file.
std::string_view builtin_prefix(std::string_view name) {
  if (name == "rdf") {
    return vocab::kRdf;
  }
  if (name == "rdfs") {
    return vocab::kRdfs;
  }
  if (name == "owl") {
    return vocab::kOwl;
  }
  if (name == "xsd") {
    return vocab::kXsd;
  }
  if (name == "rb") {
    return vocab::kRb;
  }
  return {};
}

bool is_word(const Token* t, std::string_view text) {
  return t != nullptr && t->kind == Kind::word && t->text == text;
}

bool starts_number(std::string_view w) {
  const auto digit = [](char c) { return c >= '0' && c <= '9'; };
  return !w.empty() && (digit(w[0]) || (w[0] == '-' && w.size() > 1 && digit(w[1])));
}

class Parser {
 public:
  Parser(Lexed lexed, std::string_view file, Dictionary& dict)
      : toks_(std::move(lexed.tokens)), prefixes_(std::move(lexed.prefixes)), file_(file), dict_(dict) {}

  Result<RuleSet> run() {
    RuleSet set;
    while (peek() != nullptr) {
      auto r = rule();
      if (!r) {
        return r.error();
      }
      set.rules.push_back(std::move(*r));
    }
    return set;
  }

 private:
  const Token* peek(std::size_t ahead = 0) const {
    return pos_ + ahead < toks_.size() ? &toks_[pos_ + ahead] : nullptr;
  }
  const Token& next() { return toks_[pos_++]; }

  Error error_at(const Token* t, std::string_view message) const {
    const int line = t != nullptr ? t->line : (toks_.empty() ? 1 : toks_.back().line);
    const int col = t != nullptr ? t->column : (toks_.empty() ? 1 : toks_.back().column);
    return make_error(Errc::malformed, fmt::format("{}:{}:{}: {}", file_, line, col, message));
  }

  Result<Rule> rule() {
    Rule r;
    const Token* start = peek();
    r.pos = SourcePos{std::string(file_), start->line, start->column};
    const bool bracketed = start->kind == Kind::open_bracket;
    if (bracketed) {
      next();
    }
    if (const Token* t = peek();
        t != nullptr && t->kind == Kind::word && t->text.size() > 1 && t->text.back() == ':') {
      r.name = t->text.substr(0, t->text.size() - 1);
      next();
    }
    while (!is_word(peek(), "->")) {
      if (peek() == nullptr) {
        return error_at(start, "rule without '->'");
      }
      if (is_word(peek(), "<-")) {
        return error_at(peek(), "backward rules ('<-') are not supported: the engine runs forward rules");
      }
      SF_TRY(clause(r, false));
    }
    next();  // ->
    while (true) {
      const Token* t = peek();
      if (t == nullptr) {
        return error_at(start, bracketed ? "rule not closed with ']'" : "rule not ended with '.'");
      }
      if (t->kind == Kind::close_bracket || is_word(t, ".")) {
        next();
        break;
      }
      if (is_word(t, "->")) {
        return error_at(t, "a second '->' in one rule");
      }
      SF_TRY(clause(r, true));
    }
    SF_TRY(check(r));
    return r;
  }

  Status clause(Rule& r, bool head) {
    const Token* t = peek();
    if (t->kind == Kind::open_paren) {
      return triple(r, head);
    }
    if (t->kind == Kind::open_bracket) {
      return error_at(t, "nested rules are not supported");
    }
    if (t->kind == Kind::word && peek(1) != nullptr && peek(1)->kind == Kind::open_paren) {
      return builtin(r, head);
    }
    return error_at(
        t, fmt::format("expected a triple pattern '(s p o)' or a builtin call, found '{}'", t->text));
  }

  Status triple(Rule& r, bool head) {
    const Token& open = next();
    std::vector<RuleNode> nodes;
    while (peek() != nullptr && peek()->kind != Kind::close_paren) {
      const Token& t = next();
      if (t.kind == Kind::word && peek() != nullptr && peek()->kind == Kind::open_paren) {
        return error_at(&t, fmt::format("functor terms such as '{}(...)' are not supported", t.text));
      }
      auto n = node(r, t);
      if (!n) {
        return n.error();
      }
      nodes.push_back(*n);
    }
    if (peek() == nullptr) {
      return error_at(&open, "triple pattern not closed with ')'");
    }
    next();
    if (nodes.size() != 3) {
      return error_at(&open, fmt::format("a triple pattern has 3 terms, this one has {}", nodes.size()));
    }
    (head ? r.head : r.body).emplace_back(TriplePattern{nodes[0], nodes[1], nodes[2]});
    return {};
  }

  Status builtin(Rule& r, bool head) {
    const Token& name = next();
    next();  // (
    BuiltinCall call;
    call.pos = SourcePos{std::string(file_), name.line, name.column};
    const BuiltinInfo* info = find_builtin(name.text);
    if (info == nullptr) {
      return error_at(&name, fmt::format("unknown builtin '{}'", name.text));
    }
    call.op = info->op;
    while (peek() != nullptr && peek()->kind != Kind::close_paren) {
      auto n = node(r, next());
      if (!n) {
        return n.error();
      }
      call.args.push_back(*n);
    }
    if (peek() == nullptr) {
      return error_at(&name, fmt::format("call of '{}' not closed with ')'", name.text));
    }
    next();
    const int n = static_cast<int>(call.args.size());
    if (n < info->min_args || (info->max_args >= 0 && n > info->max_args)) {
      const std::string expected = info->max_args < 0 ? fmt::format("at least {}", info->min_args)
                                   : info->min_args == info->max_args
                                       ? fmt::format("{}", info->min_args)
                                       : fmt::format("{} to {}", info->min_args, info->max_args);
      return error_at(&name, fmt::format("'{}' takes {} arguments, not {}", name.text, expected, n));
    }
    if (head ? !info->in_head : !info->in_body) {
      return error_at(&name,
                      fmt::format("'{}' cannot be used in a rule {}", name.text, head ? "head" : "body"));
    }
    (head ? r.head : r.body).emplace_back(std::move(call));
    return {};
  }

  Result<RuleNode> node(Rule& r, const Token& t) {
    if (t.kind == Kind::literal) {
      return literal(t);
    }
    if (t.kind != Kind::word) {
      return error_at(&t, fmt::format("unexpected '{}'", t.text));
    }
    const std::string& w = t.text;
    if (w.size() > 1 && w[0] == '?') {
      for (std::uint32_t i = 0; i < r.variables.size(); ++i) {
        if (r.variables[i] == w) {
          return RuleNode::variable(i);
        }
      }
      r.variables.push_back(w);
      return RuleNode::variable(static_cast<std::uint32_t>(r.variables.size() - 1));
    }
    if (w.size() > 2 && w.front() == '<' && w.back() == '>') {
      return RuleNode::constant(dict_.iri(std::string_view(w).substr(1, w.size() - 2)));
    }
    if (w == "*" || w == "_" || w == "?") {
      return error_at(&t, "wildcard variables are not supported (Jena dropped them too)");
    }
    if (starts_number(w)) {
      return number(w);
    }
    if (w.front() == '_') {
      return error_at(&t, fmt::format("blank nodes ('{}') are not supported in rules; use makeSkolem", w));
    }
    if (w.find(':') != std::string::npos) {
      auto iri = expand(t, w);
      if (!iri) {
        return iri.error();
      }
      return RuleNode::constant(dict_.iri(*iri));
    }
    return error_at(&t,
                    fmt::format("'{}' is not a term: write <iri>, prefix:name, 'literal' or ?variable", w));
  }

  // Jena's Rule.Parser.parseNumber: xsd:float with a decimal point, xsd:int without, else a
  // plain literal of the token.
  RuleNode number(const std::string& w) {
    const bool has_point = w.find('.') != std::string::npos;
    const std::string_view dt = has_point ? vocab::kXsdFloat : vocab::kXsdInt;
    const TermId lit = dict_.literal(w, dt);
    if (dict_.value(lit)->cls != ValueClass::other) {
      return RuleNode::constant(lit);
    }
    return RuleNode::constant(dict_.literal(w));
  }

  Result<RuleNode> literal(const Token& t) {
    if (t.datatype.empty()) {
      return RuleNode::constant(dict_.literal(t.text));
    }
    std::string dt;
    if (t.datatype.size() > 2 && t.datatype.front() == '<' && t.datatype.back() == '>') {
      dt = t.datatype.substr(1, t.datatype.size() - 2);
    } else {
      auto iri = expand(t, t.datatype);
      if (!iri) {
        return iri.error();
      }
      dt = *iri;
    }
    return RuleNode::constant(dict_.literal(t.text, dt));
  }

  Result<std::string> expand(const Token& t, const std::string& qname) {
    const std::size_t colon = qname.find(':');
    const std::string prefix = qname.substr(0, colon);
    if (auto it = prefixes_.find(prefix); it != prefixes_.end()) {
      return it->second + qname.substr(colon + 1);
    }
    if (auto ns = builtin_prefix(prefix); !ns.empty()) {
      return std::string(ns) + qname.substr(colon + 1);
    }
    for (std::string_view scheme : {"http", "https", "urn", "file", "ftp", "mailto"}) {
      if (prefix == scheme) {
        return qname;  // an absolute IRI written without <>
      }
    }
    return error_at(&t, fmt::format("unknown prefix '{}:' (declare it with @prefix)", prefix));
  }

  // remove(n...) names body clauses by index (Jena's Remove.headAction); they must be patterns.
  Status check(const Rule& r) const {
    const auto patterns = std::count_if(r.body.begin(), r.body.end(), [](const Clause& c) {
      return std::holds_alternative<TriplePattern>(c);
    });
    if (patterns > 63) {
      return make_error(Errc::malformed,
                        fmt::format("{}: a rule body may have at most 63 triple patterns", r.pos.describe()));
    }
    for (const Clause& c : r.head) {
      const auto* call = std::get_if<BuiltinCall>(&c);
      if (call == nullptr || call->op != Builtin::remove) {
        continue;
      }
      for (const RuleNode& a : call->args) {
        const LiteralValue* v = a.is_var ? nullptr : dict_.value(a.term);
        const bool index = v != nullptr && v->cls == ValueClass::decimal && v->decimal.integral() &&
                           v->decimal.mantissa >= 0 &&
                           static_cast<std::size_t>(v->decimal.mantissa) < r.body.size();
        if (!index ||
            !std::holds_alternative<TriplePattern>(r.body[static_cast<std::size_t>(v->decimal.mantissa)])) {
          return make_error(Errc::malformed,
                            fmt::format("{}: remove() takes indexes of triple patterns in the rule body",
                                        call->pos.describe()));
        }
      }
    }
    return {};
  }

  std::vector<Token> toks_;
  std::map<std::string, std::string> prefixes_;
  std::string_view file_;
  Dictionary& dict_;
  std::size_t pos_ = 0;
};

}  // namespace
}  // namespace rules

std::string SourcePos::describe() const {
  return fmt::format("{}:{}:{}", file, line, column);
}

bool Rule::monotonic() const {
  const auto mono = [](const Clause& c) {
    const auto* call = std::get_if<BuiltinCall>(&c);
    return call == nullptr || rules::builtin_info(call->op).monotonic;
  };
  for (const Clause& c : body) {
    if (!mono(c)) {
      return false;
    }
  }
  for (const Clause& c : head) {
    if (!mono(c)) {
      return false;
    }
  }
  return true;
}

std::string Rule::label() const {
  return name.empty() ? fmt::format("rule at {}:{}", pos.file, pos.line) : name;
}

Result<RuleSet> parse_rules(std::string_view text, std::string_view file, Dictionary& dict) {
  auto lexed = rules::lex(text, file);
  if (!lexed) {
    return lexed.error();
  }
  return rules::Parser(std::move(*lexed), file, dict).run();
}

Result<RuleSet> read_rules_file(const std::string& path, Dictionary& dict) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return make_error(Errc::io, fmt::format("{}: cannot open", path));
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_rules(text.str(), path, dict);
}

namespace {

std::string format_node(const RuleNode& n, const Rule& r, const Dictionary& dict) {
  return n.is_var ? r.variables[n.var] : format_term(dict, n.term);
}

std::string format_clause(const Clause& c, const Rule& r, const Dictionary& dict) {
  if (const auto* p = std::get_if<TriplePattern>(&c)) {
    return fmt::format("({} {} {})", format_node(p->s, r, dict), format_node(p->p, r, dict),
                       format_node(p->o, r, dict));
  }
  const auto& call = std::get<BuiltinCall>(c);
  std::string out = std::string(builtin_name(call.op)) + "(";
  for (std::size_t i = 0; i < call.args.size(); ++i) {
    out += (i ? ", " : "") + format_node(call.args[i], r, dict);
  }
  return out + ")";
}

}  // namespace

std::string format_rule(const Rule& rule, const Dictionary& dict) {
  std::string out = "[";
  if (!rule.name.empty()) {
    out += rule.name + ": ";
  }
  for (const Clause& c : rule.body) {
    out += format_clause(c, rule, dict) + " ";
  }
  out += "->";
  for (const Clause& c : rule.head) {
    out += " " + format_clause(c, rule, dict);
  }
  return out + "]";
}

}  // namespace sf::knowledge
