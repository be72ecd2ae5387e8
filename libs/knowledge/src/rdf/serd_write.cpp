// Writing triples through serd's writer (N-Triples, or Turtle abbreviated with prefixes), and
// N-Triples term syntax for messages (RDF 1.1 N-Triples §2.3–2.5).
#include <serd/serd.h>

#include <memory>
#include <string>

#include <fmt/format.h>

#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

const uint8_t* serd_bytes(const char* s) {
  return reinterpret_cast<const uint8_t*>(s);
}

size_t ostream_sink(const void* buf, size_t len, void* stream) {
  static_cast<std::ostream*>(stream)->write(static_cast<const char*>(buf), static_cast<std::streamsize>(len));
  return len;
}

// Owns the strings serd nodes point to while one statement is written.
struct NodeText {
  std::string text;
  SerdNode node = SERD_NODE_NULL;

  void set(SerdType type, std::string value) {
    text = std::move(value);
    node = serd_node_from_substring(type, serd_bytes(text.c_str()), text.size());
  }
};

void set_term(NodeText& out, const Dictionary& dict, TermId id) {
  const Term t = dict.term(id);
  switch (t.kind) {
    case TermKind::iri:
      out.set(SERD_URI, std::string(t.text));
      break;
    case TermKind::blank:
      out.set(SERD_BLANK, fmt::format("b{}", id));
      break;
    case TermKind::literal:
      out.set(SERD_LITERAL, std::string(t.text));
      break;
  }
}

void escape_into(std::string& out, std::string_view s) {
  for (char c : s) {
    switch (c) {
      case '\\':
        out += "\\\\";
        break;
      case '"':
        out += "\\\"";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04X}", static_cast<unsigned>(c));
        } else {
          out += c;
        }
    }
  }
}

}  // namespace

Status write_rdf(std::ostream& out, const Dictionary& dict, const std::vector<Triple>& triples, Syntax syntax,
                 const std::map<std::string, std::string>& prefixes) {
  std::unique_ptr<SerdEnv, void (*)(SerdEnv*)> env(serd_env_new(nullptr), serd_env_free);
  const bool turtle = syntax == Syntax::turtle;
  const auto style = static_cast<SerdStyle>(turtle ? (SERD_STYLE_ABBREVIATED | SERD_STYLE_CURIED) : 0);
  std::unique_ptr<SerdWriter, void (*)(SerdWriter*)> writer(
      serd_writer_new(turtle ? SERD_TURTLE : SERD_NTRIPLES, style, env.get(), nullptr, ostream_sink, &out),
      serd_writer_free);
  if (turtle) {
    for (const auto& [name, ns] : prefixes) {
      const SerdNode n = serd_node_from_string(SERD_LITERAL, serd_bytes(name.c_str()));
      const SerdNode u = serd_node_from_string(SERD_URI, serd_bytes(ns.c_str()));
      serd_writer_set_prefix(writer.get(), &n, &u);
    }
  }
  NodeText s;
  NodeText p;
  NodeText o;
  NodeText dt;
  NodeText lang;
  for (const Triple& t : triples) {
    set_term(s, dict, t.s);
    set_term(p, dict, t.p);
    set_term(o, dict, t.o);
    const SerdNode* dt_node = nullptr;
    const SerdNode* lang_node = nullptr;
    if (dict.is_literal(t.o)) {
      const Term lit = dict.term(t.o);
      if (!lit.lang.empty()) {
        lang.set(SERD_LITERAL, std::string(lit.lang));
        lang_node = &lang.node;
      } else if (lit.datatype != vocab::kXsdString) {
        dt.set(SERD_URI, std::string(lit.datatype));
        dt_node = &dt.node;
      }
    }
    const SerdStatus st =
        serd_writer_write_statement(writer.get(), 0, nullptr, &s.node, &p.node, &o.node, dt_node, lang_node);
    if (st != SERD_SUCCESS) {
      return make_error(Errc::invalid_argument,
                        fmt::format("cannot write {}: {}", format_triple(dict, t),
                                    reinterpret_cast<const char*>(serd_strerror(st))));
    }
  }
  serd_writer_finish(writer.get());
  out.flush();
  if (!out) {
    return make_error(Errc::io, "write failed");
  }
  return {};
}

std::string format_term(const Dictionary& dict, TermId id) {
  const Term t = dict.term(id);
  std::string out;
  switch (t.kind) {
    case TermKind::iri:
      out = "<";
      escape_into(out, t.text);
      return out + ">";
    case TermKind::blank:
      return fmt::format("_:b{}", id);
    case TermKind::literal:
      out = "\"";
      escape_into(out, t.text);
      out += "\"";
      if (!t.lang.empty()) {
        return out + "@" + std::string(t.lang);
      }
      if (t.datatype != vocab::kXsdString) {
        out += "^^<";
        escape_into(out, t.datatype);
        out += ">";
      }
      return out;
  }
  return out;
}

std::string format_triple(const Dictionary& dict, const Triple& t) {
  return format_term(dict, t.s) + " " + format_term(dict, t.p) + " " + format_term(dict, t.o) + " .";
}

}  // namespace sf::knowledge
