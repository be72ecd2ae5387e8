// Turtle (W3C Turtle 1.1) and N-Triples (RDF 1.1 N-Triples) input and output through serd.
// Reading is all or nothing: a document with any error yields the first error as
// "file:line:column: message" and no triples.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/knowledge/store.hpp"
#include "sf/knowledge/term.hpp"

namespace sf::knowledge {

enum class Syntax { turtle, ntriples };

// ".nt" → N-Triples, anything else Turtle (N-Triples is a subset of Turtle).
Syntax syntax_for_path(std::string_view path);

struct Document {
  std::vector<Triple> triples;
  std::map<std::string, std::string> prefixes;  // @prefix declarations, name → namespace IRI
};

// Parses a file. Blank node labels are scoped to the document.
Result<Document> read_rdf_file(Dictionary& dict, const std::string& path);
// Parses text; `name` stands for the file in error messages, base_iri resolves relative IRIs.
Result<Document> read_rdf_string(Dictionary& dict, std::string_view text, Syntax syntax,
                                 std::string_view name = "<string>", std::string_view base_iri = {});

// Writes triples; Turtle output abbreviates with the given prefixes. Blank nodes are written
// as _:b<term id>.
Status write_rdf(std::ostream& out, const Dictionary& dict, const std::vector<Triple>& triples, Syntax syntax,
                 const std::map<std::string, std::string>& prefixes = {});

// One term in N-Triples syntax (for messages, explanations and JSON).
std::string format_term(const Dictionary& dict, TermId id);
std::string format_triple(const Dictionary& dict, const Triple& t);

}  // namespace sf::knowledge
