// Helpers for the knowledge tests: Turtle and rules from strings, triples as N-Triples text.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/reasoner.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge::testing {

inline constexpr std::string_view kPrefixes =
    "@prefix ex: <http://ex/> .\n"
    "@prefix rdf: <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .\n"
    "@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .\n"
    "@prefix owl: <http://www.w3.org/2002/07/owl#> .\n"
    "@prefix xsd: <http://www.w3.org/2001/XMLSchema#> .\n";

inline std::vector<Triple> turtle(Dictionary& d, std::string_view body) {
  auto doc = read_rdf_string(d, std::string(kPrefixes) + std::string(body), Syntax::turtle, "test.ttl");
  EXPECT_TRUE(doc.ok()) << (doc.ok() ? "" : doc.error().message);
  return doc.ok() ? doc->triples : std::vector<Triple>{};
}

inline RuleSet rules(Dictionary& d, std::string_view text) {
  auto r = parse_rules(std::string("@prefix ex: <http://ex/>.\n") + std::string(text), "test.rules", d);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? std::move(*r) : RuleSet{};
}

// The triples as sorted N-Triples lines, with the http://ex/ namespace shortened to ex:.
inline std::set<std::string> lines(const Dictionary& d, const std::vector<Triple>& ts) {
  std::set<std::string> out;
  for (const Triple& t : ts) {
    std::string line = format_triple(d, t);
    for (std::size_t pos; (pos = line.find("<http://ex/")) != std::string::npos;) {
      const std::size_t end = line.find('>', pos);
      line.replace(pos, end - pos + 1, "ex:" + line.substr(pos + 11, end - pos - 11));
    }
    out.insert(line);
  }
  return out;
}

inline std::vector<Triple> triples_of(const Reasoner& r, const std::vector<TripleId>& ids) {
  std::vector<Triple> out;
  for (TripleId id : ids) {
    out.push_back(r.store().at(id));
  }
  return out;
}

inline std::set<std::string> inferred(const Reasoner& r) {
  return lines(r.dictionary(), triples_of(r, r.inferred()));
}

// Every alive triple (data and derived).
inline std::set<std::string> closure(const Reasoner& r) {
  std::vector<TripleId> ids;
  for (TripleId id = 0; id < r.store().next_id(); ++id) {
    if (r.store().alive(id)) {
      ids.push_back(id);
    }
  }
  return lines(r.dictionary(), triples_of(r, ids));
}

}  // namespace sf::knowledge::testing
