// Dictionary-encoded RDF terms (RDF 1.1 Concepts §3.2–3.4): every IRI, blank node and literal
// is interned once and named by a 32-bit TermId. Each term also has a value id: terms that
// denote the same value (literals such as "1"^^xsd:int and "1.0"^^xsd:decimal) share it, so
// the store and the reasoner match by value with one integer comparison.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "sf/knowledge/literal.hpp"

namespace sf::knowledge {

using TermId = std::uint32_t;
inline constexpr TermId kNoTerm = 0;

enum class TermKind : std::uint8_t { iri = 1, blank = 2, literal = 3 };

struct Term {
  TermKind kind = TermKind::iri;
  std::string_view text;      // the IRI, the blank node label, or the literal's lexical form
  std::string_view datatype;  // literals: xsd:string for simple literals, rdf:langString with a tag
  std::string_view lang;      // literals with a language tag
};

class Dictionary {
 public:
  Dictionary();
  ~Dictionary();
  Dictionary(const Dictionary&) = delete;
  Dictionary& operator=(const Dictionary&) = delete;

  TermId iri(std::string_view iri);
  TermId blank(std::string_view label);
  // A literal; an empty datatype means xsd:string (or rdf:langString when lang is given).
  TermId literal(std::string_view lexical, std::string_view datatype = {}, std::string_view lang = {});
  // A blank node distinct from every other term.
  TermId fresh_blank();
  // The term's id if it was interned, else kNoTerm.
  [[nodiscard]] TermId find(TermKind kind, std::string_view text, std::string_view datatype = {},
                            std::string_view lang = {}) const;

  [[nodiscard]] Term term(TermId id) const;
  [[nodiscard]] TermKind kind(TermId id) const { return recs_[id].kind; }
  [[nodiscard]] bool is_literal(TermId id) const { return recs_[id].kind == TermKind::literal; }
  // Equal for terms that denote the same value (Jena's sameValueAs); the term's own id otherwise.
  [[nodiscard]] TermId value_id(TermId id) const { return recs_[id].vid; }
  // The parsed value of a literal, nullptr for IRIs and blank nodes.
  [[nodiscard]] const LiteralValue* value(TermId id) const;

  [[nodiscard]] std::size_t size() const { return recs_.size() - 1; }
  [[nodiscard]] std::size_t memory_bytes() const;

 private:
  struct Rec {
    const char* text = nullptr;
    std::uint32_t text_len = 0;
    std::uint16_t lang_len = 0;
    TermKind kind = TermKind::iri;
    TermId datatype = kNoTerm;
    TermId vid = kNoTerm;
    std::uint32_t value = 0;  // index into values_ + 1, 0 for none
  };
  class Table;

  TermId intern(TermKind kind, std::string_view text, TermId datatype, std::string_view lang);
  const char* store_text(std::string_view text, std::string_view lang);
  void assign_value(TermId id);
  [[nodiscard]] std::size_t term_hash(TermKind kind, std::string_view text, TermId datatype,
                                      std::string_view lang) const;

  std::vector<Rec> recs_;
  std::vector<LiteralValue> values_;
  std::vector<std::unique_ptr<char[]>> chunks_;
  std::size_t chunk_used_ = 0;
  std::size_t text_bytes_ = 0;
  std::unique_ptr<Table> terms_;
  std::unique_ptr<Table> values_by_value_;
  TermId xsd_string_ = kNoTerm;
  TermId rdf_lang_string_ = kNoTerm;
  std::uint64_t fresh_counter_ = 0;
};

}  // namespace sf::knowledge
