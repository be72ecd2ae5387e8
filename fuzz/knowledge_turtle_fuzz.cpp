// Fuzzes the Turtle reader (serd 0.30 + our term interning, W3C Turtle 1.1) with arbitrary
// text: it must accept or reject without crashing; whatever it accepts must write as N-Triples
// that reads back to as many triples (RDF 1.1 N-Triples is a subset of what it reads).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string_view>

#include "sf/knowledge/rdf_io.hpp"

namespace {
void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace sf::knowledge;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Dictionary dict;
  auto doc = read_rdf_string(dict, text, Syntax::turtle, "fuzz.ttl", "http://example.org/base/");
  if (!doc) {
    check(!doc.error().message.empty());
    return 0;
  }
  std::ostringstream out;
  check(write_rdf(out, dict, doc->triples, Syntax::ntriples).ok());
  auto again = read_rdf_string(dict, out.str(), Syntax::ntriples, "fuzz.nt");
  check(again.ok() && again->triples.size() == doc->triples.size());
  return 0;
}
