#include <cstring>
#include <functional>
#include <string>

#include "id_table.hpp"
#include "sf/knowledge/term.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {

class Dictionary::Table : public detail::IdTable {};

namespace {
constexpr std::size_t kChunkBytes = 1 << 20;

// memcpy must not see the null data() of an empty view.
void copy(char* to, std::string_view text, std::string_view lang) {
  if (!text.empty()) {
    std::memcpy(to, text.data(), text.size());
  }
  if (!lang.empty()) {
    std::memcpy(to + text.size(), lang.data(), lang.size());
  }
}
}  // namespace

Dictionary::Dictionary()
    : recs_(1), terms_(std::make_unique<Table>()), values_by_value_(std::make_unique<Table>()) {
  xsd_string_ = iri(vocab::kXsdString);
  rdf_lang_string_ = iri(vocab::kRdfLangString);
}

Dictionary::~Dictionary() = default;

TermId Dictionary::iri(std::string_view iri) {
  return intern(TermKind::iri, iri, kNoTerm, {});
}

TermId Dictionary::blank(std::string_view label) {
  return intern(TermKind::blank, label, kNoTerm, {});
}

TermId Dictionary::literal(std::string_view lexical, std::string_view datatype, std::string_view lang) {
  // RDF 1.1 Concepts §3.3: a simple literal is an xsd:string; a tagged one an rdf:langString.
  TermId dt = xsd_string_;
  if (!lang.empty()) {
    dt = rdf_lang_string_;
  } else if (!datatype.empty()) {
    dt = iri(datatype);
  }
  return intern(TermKind::literal, lexical, dt, lang);
}

TermId Dictionary::fresh_blank() {
  // Parsed labels are prefixed by their document ("d<n>_"), Skolem labels by "s": "g<n>" is free.
  return blank("g" + std::to_string(++fresh_counter_));
}

TermId Dictionary::find(TermKind kind, std::string_view text, std::string_view datatype,
                        std::string_view lang) const {
  TermId dt = kNoTerm;
  if (kind == TermKind::literal) {
    dt = !lang.empty() ? rdf_lang_string_ : xsd_string_;
    if (lang.empty() && !datatype.empty()) {
      dt = find(TermKind::iri, datatype);
      if (dt == kNoTerm) {
        return kNoTerm;
      }
    }
  }
  const std::size_t h = term_hash(kind, text, dt, lang);
  return terms_->find(h, [&](std::uint32_t id) {
    const Rec& r = recs_[id];
    return r.kind == kind && r.datatype == dt && std::string_view(r.text, r.text_len) == text &&
           std::string_view(r.text + r.text_len, r.lang_len) == lang;
  });
}

Term Dictionary::term(TermId id) const {
  const Rec& r = recs_[id];
  Term t;
  t.kind = r.kind;
  t.text = std::string_view(r.text, r.text_len);
  t.lang = std::string_view(r.text + r.text_len, r.lang_len);
  if (r.datatype != kNoTerm) {
    const Rec& d = recs_[r.datatype];
    t.datatype = std::string_view(d.text, d.text_len);
  }
  return t;
}

const LiteralValue* Dictionary::value(TermId id) const {
  const Rec& r = recs_[id];
  return r.value == 0 ? nullptr : &values_[r.value - 1];
}

std::size_t Dictionary::memory_bytes() const {
  return recs_.capacity() * sizeof(Rec) + values_.capacity() * sizeof(LiteralValue) +
         chunks_.size() * kChunkBytes + terms_->memory_bytes() + values_by_value_->memory_bytes();
}

std::size_t Dictionary::term_hash(TermKind kind, std::string_view text, TermId datatype,
                                  std::string_view lang) const {
  std::size_t h = std::hash<std::string_view>{}(text);
  h ^= (static_cast<std::size_t>(kind) << 56) + datatype * 0x9e3779b97f4a7c15ULL;
  if (!lang.empty()) {
    h ^= std::hash<std::string_view>{}(lang)*31;
  }
  return h;
}

TermId Dictionary::intern(TermKind kind, std::string_view text, TermId datatype, std::string_view lang) {
  const std::size_t h = term_hash(kind, text, datatype, lang);
  const TermId found = terms_->find(h, [&](std::uint32_t id) {
    const Rec& r = recs_[id];
    return r.kind == kind && r.datatype == datatype && std::string_view(r.text, r.text_len) == text &&
           std::string_view(r.text + r.text_len, r.lang_len) == lang;
  });
  if (found != kNoTerm) {
    return found;
  }
  const auto id = static_cast<TermId>(recs_.size());
  Rec r;
  r.text = store_text(text, lang);
  r.text_len = static_cast<std::uint32_t>(text.size());
  r.lang_len = static_cast<std::uint16_t>(lang.size());
  r.kind = kind;
  r.datatype = datatype;
  r.vid = id;
  recs_.push_back(r);
  terms_->insert(h, id);
  if (kind == TermKind::literal) {
    assign_value(id);
  }
  return id;
}

// Text and language tag are stored back to back in chunks that never move, so the views in
// LiteralValue stay valid.
const char* Dictionary::store_text(std::string_view text, std::string_view lang) {
  const std::size_t need = text.size() + lang.size();
  text_bytes_ += need;
  if (need > kChunkBytes / 4) {
    auto big = std::make_unique<char[]>(need + 1);
    copy(big.get(), text, lang);
    const char* p = big.get();
    chunks_.insert(chunks_.begin(), std::move(big));  // keep the current chunk last
    return p;
  }
  if (chunks_.empty() || chunk_used_ + need > kChunkBytes) {
    chunks_.push_back(std::make_unique<char[]>(kChunkBytes));
    chunk_used_ = 0;
  }
  char* p = chunks_.back().get() + chunk_used_;
  copy(p, text, lang);
  chunk_used_ += need;
  return p;
}

void Dictionary::assign_value(TermId id) {
  const Term t = term(id);
  LiteralValue v = parse_literal(t.text, t.datatype, t.lang);
  values_.push_back(v);
  recs_[id].value = static_cast<std::uint32_t>(values_.size());
  if (v.cls == ValueClass::other) {
    return;  // equal only to itself
  }
  const std::size_t h = value_hash(v);
  const TermId same = values_by_value_->find(
      h, [&](std::uint32_t other) { return same_value(values_[recs_[other].value - 1], v); });
  if (same != kNoTerm) {
    recs_[id].vid = same;
  } else {
    values_by_value_->insert(h, id);
  }
}

}  // namespace sf::knowledge
