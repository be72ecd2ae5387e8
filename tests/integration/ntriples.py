"""N-Triples reading and graph comparison with blank nodes compared up to renaming.

Terms are tuples: ("iri", text), ("blank", label), ("literal", lexical, datatype, lang) with
the implicit xsd:string made explicit (RDF 1.1 N-Triples §2.5).
"""
import hashlib
import re

XSD_STRING = "http://www.w3.org/2001/XMLSchema#string"
_TERM = re.compile(r'\s*(<[^>]*>|_:[^\s]+|"(?:[^"\\]|\\.)*"(?:@[A-Za-z0-9-]+|\^\^<[^>]*>)?)')
_ESC = re.compile(r'\\(u[0-9A-Fa-f]{4}|U[0-9A-Fa-f]{8}|.)')
_SIMPLE = {"t": "\t", "n": "\n", "r": "\r", "b": "\b", "f": "\f", '"': '"', "'": "'", "\\": "\\"}


def _unescape(s):
    def one(m):
        e = m.group(1)
        return chr(int(e[1:], 16)) if e[0] in "uU" else _SIMPLE.get(e, e)
    return _ESC.sub(one, s)


def _term(tok):
    if tok.startswith("<"):
        return ("iri", _unescape(tok[1:-1]))
    if tok.startswith("_:"):
        return ("blank", tok[2:])
    end = tok.rindex('"')
    lex = _unescape(tok[1:end])
    rest = tok[end + 1:]
    if rest.startswith("@"):
        return ("literal", lex, "http://www.w3.org/1999/02/22-rdf-syntax-ns#langString", rest[1:].lower())
    return ("literal", lex, rest[3:-1] if rest.startswith("^^") else XSD_STRING, "")


def parse(text):
    """The triples of an N-Triples document (comment lines are skipped)."""
    triples = []
    for n, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        terms, pos = [], 0
        for _ in range(3):
            m = _TERM.match(line, pos)
            if not m:
                raise ValueError(f"line {n}: cannot read a term at {line[pos:pos + 40]!r}")
            terms.append(_term(m.group(1)))
            pos = m.end()
        if line[pos:].strip() != ".":
            raise ValueError(f"line {n}: expected '.' at {line[pos:]!r}")
        triples.append(tuple(terms))
    return triples


def _h(*parts):
    return hashlib.sha1(repr(parts).encode()).hexdigest()


def canonical(triples, rounds=6):
    """Replaces blank nodes by a hash of their neighbourhood (colour refinement, `rounds` deep)."""
    blanks = {t[1] for tr in triples for t in tr if t[0] == "blank"}
    colour = {b: "b" for b in blanks}

    def name(t):
        return ("blank", colour[t[1]]) if t[0] == "blank" else t

    for _ in range(rounds):
        sig = {b: [] for b in blanks}
        for s, p, o in triples:
            if s[0] == "blank":
                sig[s[1]].append(("out", name(p), name(o)))
            if o[0] == "blank":
                sig[o[1]].append(("in", name(s), name(p)))
        colour = {b: _h(colour[b], sorted(sig[b])) for b in blanks}
    return sorted((name(s), name(p), name(o)) for s, p, o in triples)


def show(t):
    def one(x):
        if x[0] == "iri":
            return f"<{x[1]}>"
        if x[0] == "blank":
            return f"_:{x[1][:8]}"
        suffix = f"@{x[3]}" if x[3] else ("" if x[2] == XSD_STRING else f"^^<{x[2]}>")
        return f'"{x[1]}"{suffix}'
    return " ".join(one(x) for x in t) + " ."


def difference(a, b, limit=20):
    """Lines describing what only a or only b has (blank nodes up to renaming); empty if equal."""
    ca, cb = canonical(a), canonical(b)
    from collections import Counter
    left, right = Counter(ca), Counter(cb)
    only_a = list((left - right).elements())
    only_b = list((right - left).elements())
    out = [f"only ours: {show(t)}" for t in only_a[:limit]] + [f"only Jena: {show(t)}" for t in only_b[:limit]]
    if len(only_a) > limit or len(only_b) > limit:
        out.append(f"... {len(only_a)} only ours, {len(only_b)} only Jena in all")
    return out
