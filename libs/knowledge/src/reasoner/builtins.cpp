// Semantics follow Jena 4.5's org.apache.jena.reasoner.rulesys.builtins classes: comparisons
// use Util.compareTypedLiterals when both sides are numbers or both instants, otherwise value
// equality; arithmetic binds (or checks) its last argument; an unbound argument makes a test
// fail. Deliberate differences are listed in docs/knowledge.md.
#include "builtins.hpp"

#include <fmt/format.h>

#include "rules/builtin_info.hpp"
#include "sf/knowledge/rdf_io.hpp"

namespace sf::knowledge::engine {
namespace {

bool numeric_or_instant(const LiteralValue* a, const LiteralValue* b) {
  if (a == nullptr || b == nullptr) {
    return false;
  }
  return (a->numeric() && b->numeric()) ||
         (a->cls == ValueClass::date_time && b->cls == ValueClass::date_time);
}

ArithmeticOp arithmetic_op(Builtin b) {
  switch (b) {
    case Builtin::difference:
      return ArithmeticOp::difference;
    case Builtin::product:
      return ArithmeticOp::product;
    case Builtin::quotient:
      return ArithmeticOp::quotient;
    default:
      return ArithmeticOp::sum;
  }
}

}  // namespace

TermId Builtins::arg(const BuiltinCall& c, std::size_t i, const Env& env) const {
  const RuleNode& n = c.args[i];
  return n.is_var ? env[n.var] : n.term;
}

// Jena's BindingEnvironment.bind: binds an unbound variable, else checks sameValueAs.
bool Builtins::bind(const RuleNode& n, TermId value, Env& env) const {
  if (n.is_var && env[n.var] == kNoTerm) {
    env[n.var] = value;
    return true;
  }
  const TermId current = n.is_var ? env[n.var] : n.term;
  return dict_.value_id(current) == dict_.value_id(value);
}

// The first two arguments when both are bound: the operands of comparisons and arithmetic.
std::optional<Builtins::Operands> Builtins::operands(const BuiltinCall& c, const Env& env) const {
  const TermId a = arg(c, 0, env);
  const TermId b = arg(c, 1, env);
  if (a == kNoTerm || b == kNoTerm) {
    return std::nullopt;
  }
  return Operands{a, b, dict_.value(a), dict_.value(b)};
}

bool Builtins::compare(const BuiltinCall& c, const Env& env, bool (*accept)(int)) const {
  const auto o = operands(c, env);
  if (!o || !numeric_or_instant(o->va, o->vb)) {
    return false;
  }
  const auto order = compare_values(*o->va, *o->vb);
  return order.has_value() && accept(*order);
}

bool Builtins::equal(const BuiltinCall& c, const Env& env) const {
  const auto o = operands(c, env);
  if (!o) {
    return false;
  }
  if (numeric_or_instant(o->va, o->vb)) {
    const auto order = compare_values(*o->va, *o->vb);
    return order.has_value() && *order == 0;
  }
  return dict_.value_id(o->a) == dict_.value_id(o->b);
}

bool Builtins::arithmetic(const BuiltinCall& c, Env& env) {
  const auto o = operands(c, env);
  if (!o || o->va == nullptr || o->vb == nullptr) {
    return false;
  }
  const auto made = sf::knowledge::arithmetic(arithmetic_op(c.op), *o->va, *o->vb);
  if (!made) {
    return false;
  }
  return bind(c.args[2], dict_.literal(made->lexical, made->datatype), env);
}

bool Builtins::extremum(const BuiltinCall& c, Env& env, bool want_min) {
  const auto o = operands(c, env);
  if (!o || o->va == nullptr || o->vb == nullptr || !o->va->numeric() || !o->vb->numeric()) {
    return false;
  }
  const int order = compare_values(*o->va, *o->vb).value_or(0);
  // Min.java: (v1 > v2) ? n2 : n1; Max.java: (v1 < v2) ? n2 : n1.
  const TermId pick = want_min ? (order > 0 ? o->b : o->a) : (order < 0 ? o->b : o->a);
  return bind(c.args[2], pick, env);
}

// NoValue.java: succeeds when no triple matches; unbound arguments are wildcards.
bool Builtins::no_value(const BuiltinCall& c, const Env& env) const {
  const auto [sn, pn, on] = no_value_args(c);
  const auto value = [&](const RuleNode* n, bool object) -> TermId {
    if (n == nullptr) {
      return kNoTerm;
    }
    const TermId t = n->is_var ? env[n->var] : n->term;
    return (object && t != kNoTerm) ? dict_.value_id(t) : t;
  };
  return !store_.contains(ValuePattern{value(sn, false), value(pn, false), value(on, true)});
}

// Regex.java: the whole text must match (Matcher.matches); further arguments take the groups.
bool Builtins::regex(const BuiltinCall& c, Env& env) {
  const TermId text = arg(c, 0, env);
  const TermId pattern = arg(c, 1, env);
  if (text == kNoTerm || pattern == kNoTerm || !dict_.is_literal(text) || !dict_.is_literal(pattern)) {
    return false;
  }
  const std::string pat(dict_.term(pattern).text);
  auto it = regexes_.find(pat);
  if (it == regexes_.end()) {
    std::optional<std::regex> compiled;
    try {
      compiled.emplace(pat, std::regex::ECMAScript);
    } catch (const std::regex_error&) {
      compiled.reset();
    }
    it = regexes_.emplace(pat, std::move(compiled)).first;
  }
  if (!it->second) {
    return false;
  }
  const std::string subject(dict_.term(text).text);
  std::smatch m;
  if (!std::regex_match(subject, m, *it->second)) {
    return false;
  }
  for (std::size_t i = 2; i < c.args.size() && i - 1 < m.size(); ++i) {
    if (!bind(c.args[i], dict_.literal(m[i - 1].matched ? m[i - 1].str() : std::string()), env)) {
      return false;
    }
  }
  return true;
}

// StrConcat.java's lex(): a literal's lexical form, an IRI's text, a blank node's label.
std::string Builtins::lexical(TermId t) const {
  const Term term = dict_.term(t);
  return term.kind == TermKind::blank ? fmt::format("b{}", t) : std::string(term.text);
}

bool Builtins::str_concat(const BuiltinCall& c, Env& env) {
  std::string out;
  for (std::size_t i = 0; i + 1 < c.args.size(); ++i) {
    const TermId t = arg(c, i, env);
    if (t == kNoTerm) {
      return false;
    }
    out += lexical(t);
  }
  return bind(c.args.back(), dict_.literal(out), env);
}

// MakeSkolem.java: the same blank node for the same remaining arguments.
bool Builtins::make_skolem(const BuiltinCall& c, Env& env) {
  std::string key = "s";
  for (std::size_t i = 1; i < c.args.size(); ++i) {
    const TermId t = arg(c, i, env);
    if (t == kNoTerm) {
      return false;
    }
    key += fmt::format("{}.", t);
  }
  return bind(c.args[0], dict_.blank(key), env);
}

void Builtins::print(const BuiltinCall& call, const Env& env) {
  std::string line;
  for (std::size_t i = 0; i < call.args.size(); ++i) {
    const TermId t = arg(call, i, env);
    line += (i ? " " : "") + (t == kNoTerm ? std::string("?") : format_term(dict_, t));
  }
  if (print_) {
    print_(line);
  }
}

bool Builtins::eval(const BuiltinCall& c, Env& env, bool skip_side_effects) {
  switch (c.op) {
    case Builtin::equal:
      return equal(c, env);
    case Builtin::not_equal:
      return arg(c, 0, env) != kNoTerm && arg(c, 1, env) != kNoTerm && !equal(c, env);
    case Builtin::less_than:
      return compare(c, env, [](int o) { return o < 0; });
    case Builtin::greater_than:
      return compare(c, env, [](int o) { return o > 0; });
    case Builtin::le:
      return compare(c, env, [](int o) { return o <= 0; });
    case Builtin::ge:
      return compare(c, env, [](int o) { return o >= 0; });
    case Builtin::sum:
    case Builtin::difference:
    case Builtin::product:
    case Builtin::quotient:
      return arithmetic(c, env);
    case Builtin::min:
    case Builtin::max:
      return extremum(c, env, c.op == Builtin::min);
    case Builtin::no_value:
      return no_value(c, env);
    case Builtin::regex:
      return regex(c, env);
    case Builtin::str_concat:
      return str_concat(c, env);
    case Builtin::make_skolem:
      return make_skolem(c, env);
    case Builtin::is_literal:
      return arg(c, 0, env) != kNoTerm && dict_.is_literal(arg(c, 0, env));
    case Builtin::not_literal:
      return arg(c, 0, env) == kNoTerm || !dict_.is_literal(arg(c, 0, env));
    case Builtin::bound:
    case Builtin::unbound:
      for (std::size_t i = 0; i < c.args.size(); ++i) {
        if ((arg(c, i, env) == kNoTerm) == (c.op == Builtin::bound)) {
          return false;
        }
      }
      return true;
    case Builtin::print:
      if (!skip_side_effects) {
        print(c, env);
      }
      return true;
    case Builtin::remove:
      return false;  // head only (the parser rejects it in a body)
  }
  return false;
}

bool Builtins::eval_all(const CompiledRule& r, Env& env, bool monotonic_only, bool skip_side_effects) {
  for (const BuiltinCall* g : r.guards) {
    if (monotonic_only && !rules::builtin_info(g->op).monotonic) {
      continue;
    }
    if (!eval(*g, env, skip_side_effects)) {
      return false;
    }
  }
  return true;
}

bool Builtins::still_holds(const CompiledRule& r, Env& env) {
  for (const BuiltinCall* g : r.guards) {
    if (!rules::builtin_info(g->op).monotonic && !eval(*g, env, true)) {
      return false;
    }
  }
  return true;
}

}  // namespace sf::knowledge::engine
