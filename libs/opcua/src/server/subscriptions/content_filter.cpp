// ContentFilter where clauses (OPC 10000-4 §7.4): validation and evaluation against one event.
// Supported operators: Equals, IsNull, GreaterThan, LessThan, GreaterThanOrEqual,
// LessThanOrEqual, Like, Not, Between, InList, And, Or, OfType. Cast, InView, RelatedTo,
// BitwiseAnd and BitwiseOr are BadFilterOperatorUnsupported. Operands: Element, Literal and
// SimpleAttribute (AttributeOperand is not for event filters, §7.17.3).
#include <algorithm>
#include <compare>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "server/subscriptions/event_filter.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::subs {
namespace {

using Op = FilterOperator;

// Operand count per operator (§7.4.3 Table 119/120); -2 = "two or more" (InList).
int operand_count(Op op) {
  switch (op) {
    case Op::IsNull:
    case Op::Not:
    case Op::InView:
    case Op::OfType:
      return 1;
    case Op::Between:
      return 3;
    case Op::InList:
      return -2;
    case Op::RelatedTo:
      return 6;
    default:
      return 2;
  }
}

bool supported(Op op) {
  return op != Op::Cast && op != Op::InView && op != Op::RelatedTo && op != Op::BitwiseAnd &&
         op != Op::BitwiseOr;
}

StatusCode check_operand(const ExtensionObject& operand, std::size_t self, std::size_t count, Op op,
                         const TypeTree& types) {
  if (const auto* e = operand.get_if<ElementOperand>()) {
    // Elements form a tree whose operands point forward (§7.4.1): no cycles.
    return e->index > self && e->index < count ? status::Good : status::BadFilterElementInvalid;
  }
  if (const auto* l = operand.get_if<LiteralOperand>()) {
    if (op == Op::OfType && l->value.get_if<NodeId>() == nullptr) {
      return status::BadFilterOperandInvalid;
    }
    return status::Good;
  }
  if (const auto* s = operand.get_if<SimpleAttributeOperand>()) {
    return op == Op::OfType ? status::BadFilterOperandInvalid : check_simple_operand(*s, types);
  }
  return status::BadFilterOperandInvalid;
}

ContentFilterElementResult check_element(const ContentFilterElement& element, std::size_t self,
                                         std::size_t count, const TypeTree& types) {
  ContentFilterElementResult r;
  const auto raw = static_cast<std::int32_t>(element.filter_operator);
  if (raw < 0 || raw > static_cast<std::int32_t>(Op::BitwiseOr)) {
    r.status_code = status::BadFilterOperatorInvalid;
    return r;
  }
  const Op op = element.filter_operator;
  if (!supported(op)) {
    r.status_code = status::BadFilterOperatorUnsupported;
    return r;
  }
  const int want = operand_count(op);
  const auto have = static_cast<int>(std::min<std::size_t>(element.filter_operands.size(), 1000));
  if (want >= 0 ? have != want : have < -want) {
    r.status_code = status::BadFilterOperandCountMismatch;
    return r;
  }
  bool bad = false;
  for (const auto& operand : element.filter_operands) {
    const StatusCode st = check_operand(operand, self, count, op, types);
    r.operand_status_codes.push_back(st);
    bad = bad || !st.is_good();
  }
  if (bad) {
    r.status_code = status::BadFilterOperandInvalid;
  } else {
    r.operand_status_codes.clear();
  }
  return r;
}

// ---- Values and comparisons (§7.4.3 implicit conversions, simplified) ------------------------

std::optional<std::string> as_text(const Variant& v) {
  if (const auto* s = v.get_if<String>()) {
    return s->str();
  }
  if (const auto* t = v.get_if<LocalizedText>()) {
    return t->text.str();
  }
  if (const auto* q = v.get_if<QualifiedName>()) {
    return q->name.str();
  }
  return std::nullopt;
}

struct Number {
  bool integral = false;
  bool negative = false;
  std::uint64_t magnitude = 0;  // for integral values
  double real = 0;
};

std::optional<Number> as_number(const Variant& v) {
  return std::visit(
      [](const auto& x) -> std::optional<Number> {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>) {
          return Number{true, false, x ? 1U : 0U, x ? 1.0 : 0.0};
        } else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) {
          const bool neg = x < 0;
          const auto mag = neg ? static_cast<std::uint64_t>(-(static_cast<std::int64_t>(x) + 1)) + 1U
                               : static_cast<std::uint64_t>(x);
          return Number{true, neg, mag, static_cast<double>(x)};
        } else if constexpr (std::is_integral_v<T>) {
          return Number{true, false, static_cast<std::uint64_t>(x), static_cast<double>(x)};
        } else if constexpr (std::is_floating_point_v<T>) {
          return Number{false, false, 0, static_cast<double>(x)};
        } else if constexpr (std::is_same_v<T, StatusCode>) {
          return Number{true, false, x.value(), static_cast<double>(x.value())};
        } else if constexpr (std::is_same_v<T, String>) {
          // §7.4.3: a String converts to a number when it holds one.
          const std::string& s = x.str();
          char* end = nullptr;
          const double d = std::strtod(s.c_str(), &end);
          if (s.empty() || end != s.c_str() + s.size()) {
            return std::nullopt;
          }
          return Number{false, false, 0, d};
        } else {
          return std::nullopt;
        }
      },
      v.storage());
}

std::partial_ordering compare_numbers(const Number& a, const Number& b) {
  if (a.integral && b.integral) {
    if (a.negative != b.negative) {
      return a.negative ? std::partial_ordering::less : std::partial_ordering::greater;
    }
    return a.negative ? b.magnitude <=> a.magnitude : a.magnitude <=> b.magnitude;
  }
  return a.real <=> b.real;
}

bool is_numeric_type(const Variant& v) {
  const auto t = v.type();
  return v.is_scalar() &&
         ((t >= BuiltinType::Boolean && t <= BuiltinType::Double) || t == BuiltinType::StatusCode);
}

std::optional<NodeId> as_node_id(const Variant& v) {
  if (const auto* n = v.get_if<NodeId>()) {
    return *n;
  }
  if (const auto* e = v.get_if<ExpandedNodeId>()) {
    return e->is_local() ? std::optional<NodeId>(e->node_id) : std::nullopt;
  }
  if (const auto* s = v.get_if<String>()) {
    auto parsed = NodeId::parse(s->view());
    return parsed ? std::optional<NodeId>(*parsed) : std::nullopt;
  }
  return std::nullopt;
}

// nullopt: the operands cannot be compared (no implicit conversion); unordered: comparable
// for equality only and not equal.
std::optional<std::partial_ordering> compare(const Variant& a, const Variant& b) {
  if (a.is_array() || b.is_array()) {
    return a == b ? std::partial_ordering::equivalent : std::partial_ordering::unordered;
  }
  if (is_numeric_type(a) || is_numeric_type(b)) {
    const auto x = as_number(a);
    const auto y = as_number(b);
    if (!x || !y) {
      return std::nullopt;
    }
    return compare_numbers(*x, *y);
  }
  if (const auto* x = a.get_if<DateTime>()) {
    const auto* y = b.get_if<DateTime>();
    return y != nullptr ? std::optional(*x <=> *y) : std::nullopt;
  }
  if (a.type() == BuiltinType::NodeId || b.type() == BuiltinType::NodeId ||
      a.type() == BuiltinType::ExpandedNodeId || b.type() == BuiltinType::ExpandedNodeId) {
    const auto x = as_node_id(a);
    const auto y = as_node_id(b);
    if (!x || !y) {
      return std::nullopt;
    }
    return *x == *y ? std::partial_ordering::equivalent : std::partial_ordering::unordered;
  }
  if (a.type() == b.type() && a.type() != BuiltinType::String && a.type() != BuiltinType::LocalizedText) {
    return a == b ? std::partial_ordering::equivalent : std::partial_ordering::unordered;
  }
  const auto x = as_text(a);
  const auto y = as_text(b);
  if (!x || !y) {
    return std::nullopt;
  }
  return *x <=> *y;
}

std::optional<bool> as_bool(const Variant& v) {
  if (const auto* b = v.get_if<bool>()) {
    return *b;
  }
  if (is_numeric_type(v)) {
    return as_number(v)->real != 0;
  }
  return std::nullopt;
}

Variant tri(std::optional<bool> b) {
  return b ? Variant(*b) : Variant{};
}

// ---- Evaluation -----------------------------------------------------------------------------

class Evaluator {
 public:
  Evaluator(const ContentFilter& filter, const Event& event, const TypeTree& types)
      : filter_(filter), event_(event), types_(types), results_(filter.elements.size()) {}

  // Operands point forward only, so evaluating from the last element to the first sees every
  // operand's result already computed.
  Variant run() {
    for (std::size_t i = filter_.elements.size(); i-- > 0;) {
      results_[i] = evaluate(filter_.elements[i]);
    }
    return results_.empty() ? Variant(true) : results_[0];
  }

 private:
  Variant operand(const ExtensionObject& o) const {
    if (const auto* e = o.get_if<ElementOperand>()) {
      return results_[e->index];
    }
    if (const auto* l = o.get_if<LiteralOperand>()) {
      return l->value;
    }
    if (const auto* s = o.get_if<SimpleAttributeOperand>()) {
      return event_field(event_, *s, types_);
    }
    return {};
  }

  Variant compare_op(Op op, const Variant& a, const Variant& b) const {
    if (a.is_empty() || b.is_empty()) {
      return {};
    }
    const auto c = compare(a, b);
    if (!c) {
      return Variant(false);
    }
    switch (op) {
      case Op::Equals:
        return Variant(*c == std::partial_ordering::equivalent);
      case Op::GreaterThan:
        return Variant(*c == std::partial_ordering::greater);
      case Op::LessThan:
        return Variant(*c == std::partial_ordering::less);
      case Op::GreaterThanOrEqual:
        return Variant(*c == std::partial_ordering::greater || *c == std::partial_ordering::equivalent);
      default:  // LessThanOrEqual
        return Variant(*c == std::partial_ordering::less || *c == std::partial_ordering::equivalent);
    }
  }

  Variant evaluate(const ContentFilterElement& element) const {
    std::vector<Variant> v;
    v.reserve(element.filter_operands.size());
    for (const auto& o : element.filter_operands) {
      v.push_back(operand(o));
    }
    switch (element.filter_operator) {
      case Op::Equals:
      case Op::GreaterThan:
      case Op::LessThan:
      case Op::GreaterThanOrEqual:
      case Op::LessThanOrEqual:
        return compare_op(element.filter_operator, v[0], v[1]);
      case Op::IsNull:
        return Variant(v[0].is_empty());
      case Op::Like: {
        const auto text = as_text(v[0]);
        const auto pattern = as_text(v[1]);
        return text && pattern ? Variant(like_matches(*text, *pattern)) : Variant(false);
      }
      case Op::Not: {
        const auto b = as_bool(v[0]);
        return b ? Variant(!*b) : Variant{};
      }
      case Op::Between:
        return logical_and(compare_op(Op::GreaterThanOrEqual, v[0], v[1]),
                           compare_op(Op::LessThanOrEqual, v[0], v[2]));
      case Op::InList:
        return in_list(v);
      case Op::And:
        return logical_and(v[0], v[1]);
      case Op::Or:
        return logical_or(v[0], v[1]);
      case Op::OfType: {
        const auto* type = v[0].get_if<NodeId>();
        return Variant(type != nullptr && types_.derives(event_.event_type, *type));
      }
      default:
        return {};
    }
  }

  Variant in_list(const std::vector<Variant>& v) const {
    if (v[0].is_empty()) {
      return {};
    }
    for (std::size_t i = 1; i < v.size(); ++i) {
      const Variant eq = compare_op(Op::Equals, v[0], v[i]);
      if (const auto* b = eq.get_if<bool>(); b != nullptr && *b) {
        return Variant(true);
      }
    }
    return Variant(false);
  }

  // Three-valued logic (§7.4.3 Tables 121, 122): FALSE dominates AND, TRUE dominates OR,
  // otherwise NULL wins over the remaining value.
  static Variant logical_and(const Variant& a, const Variant& b) {
    const auto x = as_bool(a);
    const auto y = as_bool(b);
    if ((x && !*x) || (y && !*y)) {
      return Variant(false);
    }
    return x && y ? Variant(true) : Variant{};
  }
  static Variant logical_or(const Variant& a, const Variant& b) {
    const auto x = as_bool(a);
    const auto y = as_bool(b);
    if ((x && *x) || (y && *y)) {
      return Variant(true);
    }
    return tri(x && y ? std::optional<bool>(false) : std::nullopt);
  }

  const ContentFilter& filter_;
  const Event& event_;
  const TypeTree& types_;
  std::vector<Variant> results_;
};

}  // namespace

bool check_content_filter(const ContentFilter& filter, const TypeTree& types, ContentFilterResult& result) {
  result = {};
  bool ok = true;
  std::vector<ContentFilterElementResult> results;
  for (std::size_t i = 0; i < filter.elements.size(); ++i) {
    results.push_back(check_element(filter.elements[i], i, filter.elements.size(), types));
    ok = ok && results.back().status_code.is_good();
  }
  if (!ok) {
    result.element_results = std::move(results);
  }
  return ok;
}

bool where_matches(const ContentFilter& filter, const Event& event, const TypeTree& types) {
  const auto b = as_bool(Evaluator(filter, event, types).run());
  return b.value_or(false);
}

}  // namespace sf::opcua::subs
