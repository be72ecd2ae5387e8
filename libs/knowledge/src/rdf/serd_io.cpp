// Reading and writing RDF through serd 0.30 (Debian libserd-dev): serd tokenises and expands
// the syntax, we intern the terms.
#include <serd/serd.h>

#include <atomic>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "sf/knowledge/rdf_io.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

const uint8_t* u8(const char* s) {
  return reinterpret_cast<const uint8_t*>(s);
}
std::string_view view(const SerdNode* n) {
  return n == nullptr || n->buf == nullptr
             ? std::string_view{}
             : std::string_view(reinterpret_cast<const char*>(n->buf), n->n_bytes);
}

// RFC 3986 §3.1: scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ), then ':'.
bool has_iri_scheme(std::string_view iri) {
  const auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  if (iri.empty() || !alpha(iri[0])) {
    return false;
  }
  for (std::size_t i = 1; i < iri.size(); ++i) {
    const char c = iri[i];
    if (c == ':') {
      return true;
    }
    if (!alpha(c) && !(c >= '0' && c <= '9') && c != '+' && c != '-' && c != '.') {
      return false;
    }
  }
  return false;
}

// Well-formed UTF-8 (RFC 3629 §4): no stray continuation bytes, overlong forms, surrogates or
// code points above U+10FFFF.
bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (b < 0x80) {
      ++i;
      continue;
    }
    if (b >= 0xC2 && b <= 0xDF) {
      n = 1;
      cp = b & 0x1FU;
    } else if (b >= 0xE0 && b <= 0xEF) {
      n = 2;
      cp = b & 0x0FU;
    } else if (b >= 0xF0 && b <= 0xF4) {
      n = 3;
      cp = b & 0x07U;
    } else {
      return false;
    }
    if (i + n >= s.size()) {  // the sequence runs past the end
      return false;
    }
    for (std::size_t k = 1; k <= n; ++k) {
      const auto c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xC0U) != 0x80U) {
        return false;
      }
      cp = (cp << 6U) | (c & 0x3FU);
    }
    const std::uint32_t min = n == 1 ? 0x80U : n == 2 ? 0x800U : 0x10000U;
    if (cp < min || cp > 0x10FFFFU || (cp >= 0xD800U && cp <= 0xDFFFU)) {
      return false;
    }
    i += n + 1;
  }
  return true;
}

// For error messages: bytes outside printable ASCII as \xNN.
std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b >= 0x7F) {
      out += fmt::format("\\x{:02X}", b);
    } else {
      out += c;
    }
  }
  return out;
}

// A serd node we own (serd_env_expand_node allocates).
struct OwnedNode {
  SerdNode node = SERD_NODE_NULL;
  ~OwnedNode() { serd_node_free(&node); }
};

struct ReadState {
  Dictionary& dict;
  SerdEnv* env;
  std::string name;
  std::string_view text;  // the input, or empty when reading a file (then read on demand)
  std::string path;
  Document doc;
  std::string error;  // the first error, "name:line:col: message"

  void fail_at(std::string message) {
    if (error.empty()) {
      error = fmt::format("{}:{}", name, message);
    }
  }

  // serd reports no position to the statement sink: locate the prefixed name in the text.
  void fail_curie(const SerdNode* n) {
    fail_near(view(n), fmt::format("undeclared prefix in '{}'", view(n)));
  }

  // `message` at the first place `needle` occurs in the text (line 0 when it does not).
  void fail_near(std::string_view needle, const std::string& message) {
    std::string file_text;
    if (text.empty() && !path.empty()) {
      std::ifstream in(path, std::ios::binary);
      std::ostringstream all;
      all << in.rdbuf();
      file_text = all.str();
      text = file_text;
    }
    const std::size_t at = text.find(needle);
    int line = 1;
    int col = 1;
    for (std::size_t i = 0; at != std::string_view::npos && i < at; ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    if (at == std::string_view::npos) {
      line = 0;
      col = 0;
    }
    fail_at(fmt::format("{}:{}: {}", line, col, message));
  }

  // Expands a URI or CURIE node to an absolute IRI; empty on failure.
  std::string expand(const SerdNode* n) const {
    OwnedNode full;
    full.node = serd_env_expand_node(env, n);
    return std::string(view(&full.node));
  }

  // RDF 1.1 §3.2: IRIs in a graph are absolute (RFC 3987 §2.2: scheme ":" ...) and, as
  // Turtle text is, UTF-8. serd takes anything before the first ':' for a scheme and passes
  // bytes on unchecked, so an IRI it accepted may be neither; what a writer refuses later.
  bool absolute_iri(const SerdNode* n, const std::string& iri) {
    if (!has_iri_scheme(iri) || !valid_utf8(iri)) {
      fail_near(view(n), fmt::format("not an absolute IRI in UTF-8: <{}>", printable(iri)));
      return false;
    }
    return true;
  }

  TermId term(const SerdNode* n, const SerdNode* datatype, const SerdNode* lang) {
    switch (n->type) {
      case SERD_URI:
      case SERD_CURIE: {
        const std::string iri = expand(n);
        if (iri.empty()) {
          return kNoTerm;
        }
        return absolute_iri(n, iri) ? dict.iri(iri) : kNoTerm;
      }
      case SERD_BLANK:
        return dict.blank(view(n));
      case SERD_LITERAL: {
        std::string dt;
        if (datatype != nullptr && datatype->type != SERD_NOTHING) {
          dt = expand(datatype);
          if (dt.empty() || !absolute_iri(datatype, dt)) {
            return kNoTerm;
          }
        }
        return dict.literal(view(n), dt, lang == nullptr ? std::string_view{} : view(lang));
      }
      case SERD_NOTHING:
        break;
    }
    return kNoTerm;
  }
};

SerdStatus on_base(void* handle, const SerdNode* uri) {
  auto* st = static_cast<ReadState*>(handle);
  return serd_env_set_base_uri(st->env, uri);
}

SerdStatus on_prefix(void* handle, const SerdNode* name, const SerdNode* uri) {
  auto* st = static_cast<ReadState*>(handle);
  const SerdStatus s = serd_env_set_prefix(st->env, name, uri);
  if (s == SERD_SUCCESS) {
    OwnedNode full;
    full.node = serd_env_expand_node(st->env, uri);
    st->doc.prefixes[std::string(view(name))] = std::string(view(&full.node));
  }
  return s;
}

SerdStatus on_statement(void* handle, SerdStatementFlags /*flags*/, const SerdNode* /*graph*/,
                        const SerdNode* subject, const SerdNode* predicate, const SerdNode* object,
                        const SerdNode* datatype, const SerdNode* lang) {
  auto* st = static_cast<ReadState*>(handle);
  const TermId s = st->term(subject, nullptr, nullptr);
  const TermId p = st->term(predicate, nullptr, nullptr);
  const TermId o = st->term(object, datatype, lang);
  if (s == kNoTerm || p == kNoTerm || o == kNoTerm) {
    for (const SerdNode* n : {subject, predicate, object, datatype}) {
      if (n != nullptr && n->type == SERD_CURIE && st->expand(n).empty()) {
        st->fail_curie(n);
      }
    }
    st->fail_at("0:0: a term could not be expanded");
    return SERD_ERR_BAD_CURIE;
  }
  st->doc.triples.push_back(Triple{s, p, o});
  return SERD_SUCCESS;
}

SerdStatus on_error(void* handle, const SerdError* e) {
  auto* st = static_cast<ReadState*>(handle);
  char text[512];
  va_list args;
  va_copy(args, *e->args);
  // serd hands over a printf format and its arguments (SerdError::fmt, ::args).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  std::vsnprintf(text, sizeof text, e->fmt, args);
#pragma GCC diagnostic pop
  va_end(args);
  std::string message(text);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) {
    message.pop_back();
  }
  st->fail_at(fmt::format("{}:{}: {}", e->line, e->col + 1, message));
  return SERD_SUCCESS;
}

std::atomic<std::uint64_t> g_documents{0};

}  // namespace

Syntax syntax_for_path(std::string_view path) {
  return path.ends_with(".nt") ? Syntax::ntriples : Syntax::turtle;
}

namespace {

// Sets up a strict reader with our sinks, lets `read` feed it, and returns the document or the
// first error.
template <typename Read>
Result<Document> read_document(Dictionary& dict, Syntax syntax, std::string_view name,
                               std::string_view base_iri, std::string_view text, const std::string& path,
                               Read&& read) {
  const std::string base(base_iri);
  SerdNode base_node = serd_node_from_string(SERD_URI, u8(base.c_str()));
  std::unique_ptr<SerdEnv, void (*)(SerdEnv*)> env(serd_env_new(base.empty() ? nullptr : &base_node),
                                                   serd_env_free);
  ReadState st{dict, env.get(), std::string(name), text, path, {}, {}};
  std::unique_ptr<SerdReader, void (*)(SerdReader*)> reader(
      serd_reader_new(syntax == Syntax::ntriples ? SERD_NTRIPLES : SERD_TURTLE, &st, nullptr, on_base,
                      on_prefix, on_statement, nullptr),
      serd_reader_free);
  serd_reader_set_strict(reader.get(), true);
  serd_reader_set_error_sink(reader.get(), on_error, &st);
  // Blank node labels are per document (RDF 1.1 Concepts §3.4).
  const std::string prefix = fmt::format("d{}_", ++g_documents);
  serd_reader_add_blank_prefix(reader.get(), u8(prefix.c_str()));
  const SerdStatus status = read(reader.get());
  if (!st.error.empty()) {
    return make_error(Errc::malformed, st.error);
  }
  if (status != SERD_SUCCESS && status != SERD_FAILURE) {
    return make_error(Errc::malformed,
                      fmt::format("{}: {}", name, reinterpret_cast<const char*>(serd_strerror(status))));
  }
  return std::move(st.doc);
}

}  // namespace

Result<Document> read_rdf_string(Dictionary& dict, std::string_view text, Syntax syntax,
                                 std::string_view name, std::string_view base_iri) {
  if (text.find('\0') != std::string_view::npos) {
    return make_error(Errc::malformed, fmt::format("{}: contains a NUL byte", name));
  }
  // serd reads a NUL-terminated string, and its byte-order-mark check looks up to three bytes
  // ahead even in shorter input: pad with zeros so that it never reads past our buffer.
  std::string input(text);
  input.append(8, '\0');
  return read_document(dict, syntax, name, base_iri, text, {}, [&](SerdReader* reader) {
    return serd_reader_read_string(reader, u8(input.c_str()));
  });
}

// Files are streamed through serd page by page: a large data file is never held in memory whole.
Result<Document> read_rdf_file(Dictionary& dict, const std::string& path) {
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file) {
    return make_error(Errc::io, fmt::format("{}: cannot open", path));
  }
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(path, ec);
  return read_document(
      dict, syntax_for_path(path), path, "file://" + absolute.string(), {}, path,
      [&](SerdReader* reader) { return serd_reader_read_file_handle(reader, file.get(), u8(path.c_str())); });
}

}  // namespace sf::knowledge
