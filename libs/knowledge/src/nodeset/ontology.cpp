#include "sf/knowledge/ontology.hpp"

#include <algorithm>
#include <functional>
#include <set>

#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

std::string iri(std::string_view ns, std::string_view local) {
  return std::string(ns) + std::string(local);
}

struct Vocab {
  TermId type, owl_class, rdfs_class, sub_class, object_prop, datatype_prop, domain, range, inverse,
      symmetric, transitive, sub_prop, label, comment, ontology, thing, live_value, has_component;

  explicit Vocab(const Dictionary& d)
      : type(d.find(TermKind::iri, vocab::kRdfType)),
        owl_class(d.find(TermKind::iri, vocab::kOwlClass)),
        rdfs_class(d.find(TermKind::iri, iri(vocab::kRdfs, "Class"))),
        sub_class(d.find(TermKind::iri, vocab::kRdfsSubClassOf)),
        object_prop(d.find(TermKind::iri, vocab::kOwlObjectProperty)),
        datatype_prop(d.find(TermKind::iri, vocab::kOwlDatatypeProperty)),
        domain(d.find(TermKind::iri, vocab::kRdfsDomain)),
        range(d.find(TermKind::iri, vocab::kRdfsRange)),
        inverse(d.find(TermKind::iri, vocab::kOwlInverseOf)),
        symmetric(d.find(TermKind::iri, vocab::kOwlSymmetricProperty)),
        transitive(d.find(TermKind::iri, vocab::kOwlTransitiveProperty)),
        sub_prop(d.find(TermKind::iri, vocab::kRdfsSubPropertyOf)),
        label(d.find(TermKind::iri, vocab::kRdfsLabel)),
        comment(d.find(TermKind::iri, vocab::kRdfsComment)),
        ontology(d.find(TermKind::iri, vocab::kOwlOntology)),
        thing(d.find(TermKind::iri, iri(vocab::kOwl, "Thing"))),
        live_value(d.find(TermKind::iri, iri(vocab::kSf, "liveValue"))),
        has_component(d.find(TermKind::iri, iri(vocab::kSf, "hasComponent"))) {}
};

using Facts = std::unordered_map<TermId, std::vector<std::pair<TermId, TermId>>>;

class Extractor {
 public:
  Extractor(const Dictionary& d, const std::vector<Triple>& triples) : d_(d), v_(d) {
    for (const Triple& t : triples) {
      facts_[t.s].emplace_back(t.p, t.o);
    }
  }

  Result<OntologyModel> run() {
    collect_kinds();
    if (classes_.empty()) {
      return make_error(Errc::not_found, "no classes (owl:Class or rdfs:subClassOf) in the input");
    }
    OntologyModel m;
    m.namespace_uri = namespace_uri();
    m.label = ontology_label();
    for (TermId c : sorted(classes_)) {
      m.classes.push_back(make_class(c));
    }
    for (TermId p : sorted(properties_)) {
      m.properties.push_back(make_property(p));
    }
    for (TermId i : sorted(individuals_)) {
      m.individuals.push_back(make_individual(i));
    }
    for (std::size_t i = 0; i < m.classes.size(); ++i) {
      m.class_index[m.classes[i].iri] = i;
    }
    for (std::size_t i = 0; i < m.properties.size(); ++i) {
      m.property_index[m.properties[i].iri] = i;
    }
    for (std::size_t i = 0; i < m.individuals.size(); ++i) {
      m.individual_index[m.individuals[i].iri] = i;
    }
    return m;
  }

 private:
  bool is_iri(TermId t) const { return t != kNoTerm && d_.kind(t) == TermKind::iri; }

  std::vector<TermId> objects(TermId s, TermId p) const {
    std::vector<TermId> out;
    if (auto it = facts_.find(s); it != facts_.end()) {
      for (const auto& [pp, o] : it->second) {
        if (pp == p && p != kNoTerm) {
          out.push_back(o);
        }
      }
    }
    return out;
  }

  bool has_type(TermId s, TermId c) const {
    const auto types = objects(s, v_.type);
    return c != kNoTerm && std::find(types.begin(), types.end(), c) != types.end();
  }

  void collect_kinds() {
    for (const auto& [s, pos] : facts_) {
      for (const auto& [p, o] : pos) {
        if (p == v_.type && (o == v_.owl_class || o == v_.rdfs_class) && is_iri(s)) {
          classes_.insert(s);
        } else if (p == v_.sub_class && is_iri(s)) {
          classes_.insert(s);
          if (is_iri(o) && o != v_.thing) {
            classes_.insert(o);
          }
        } else if (p == v_.type && (o == v_.object_prop || o == v_.datatype_prop) && is_iri(s)) {
          properties_.insert(s);
        } else if (p == v_.inverse && is_iri(s) && is_iri(o)) {
          inverses_.emplace(s, o);  // p owl:inverseOf q names the inverse of both
          inverses_.emplace(o, s);
        }
      }
    }
    for (const auto& [s, pos] : facts_) {
      if (!is_iri(s) || classes_.count(s) || properties_.count(s)) {
        continue;
      }
      for (const auto& [p, o] : pos) {
        if (p == v_.type && classes_.count(o)) {
          individuals_.insert(s);
        }
      }
    }
  }

  std::vector<TermId> sorted(const std::set<TermId>& ids) const {
    std::vector<TermId> out(ids.begin(), ids.end());
    std::sort(out.begin(), out.end(), [&](TermId a, TermId b) { return d_.term(a).text < d_.term(b).text; });
    return out;
  }

  std::string text_of(TermId s, TermId p) const {
    const auto vals = objects(s, p);
    for (TermId v : vals) {
      if (d_.is_literal(v)) {
        return std::string(d_.term(v).text);
      }
    }
    return {};
  }

  std::string namespace_uri() const {
    for (const auto& [s, pos] : facts_) {
      if (is_iri(s) && has_type(s, v_.ontology)) {
        return std::string(d_.term(s).text);
      }
    }
    const std::string first(d_.term(*classes_.begin()).text);
    return first.substr(0, first.size() - local_name(first).size());
  }

  std::string ontology_label() const {
    for (const auto& [s, pos] : facts_) {
      if (is_iri(s) && has_type(s, v_.ontology)) {
        return text_of(s, v_.label);
      }
    }
    return {};
  }

  OntologyClass make_class(TermId c) const {
    OntologyClass k;
    k.iri = c;
    k.name = local_name(d_.term(c).text);
    k.label = text_of(c, v_.label);
    k.comment = text_of(c, v_.comment);
    for (TermId parent : objects(c, v_.sub_class)) {
      if (classes_.count(parent) && parent != c) {
        k.parents.push_back(parent);
      }
    }
    std::sort(k.parents.begin(), k.parents.end(),
              [&](TermId a, TermId b) { return d_.term(a).text < d_.term(b).text; });
    return k;
  }

  // Follows rdfs:subPropertyOf upwards from p looking for target.
  bool reaches(TermId p, TermId target) const {
    std::set<TermId> seen;
    std::function<bool(TermId)> up = [&](TermId x) {
      if (x == target) {
        return true;
      }
      if (!seen.insert(x).second) {
        return false;
      }
      for (TermId parent : objects(x, v_.sub_prop)) {
        if (up(parent)) {
          return true;
        }
      }
      return false;
    };
    return target != kNoTerm && up(p);
  }

  OntologyProperty make_property(TermId p) const {
    OntologyProperty k;
    k.iri = p;
    k.name = local_name(d_.term(p).text);
    k.label = text_of(p, v_.label);
    k.comment = text_of(p, v_.comment);
    k.object = has_type(p, v_.object_prop);
    k.domains = objects(p, v_.domain);
    const auto ranges = objects(p, v_.range);
    k.range = ranges.empty() ? kNoTerm : ranges.front();
    if (auto it = inverses_.find(p); it != inverses_.end()) {
      k.inverse = it->second;
      k.names_inverse = !objects(p, v_.inverse).empty();
    }
    for (TermId parent : objects(p, v_.sub_prop)) {
      if (properties_.count(parent)) {
        k.parents.push_back(parent);
      }
    }
    k.symmetric = has_type(p, v_.symmetric);
    k.transitive = has_type(p, v_.transitive);
    k.part_of = k.object && reaches(p, v_.has_component);
    k.live = !k.object && p != v_.live_value && reaches(p, v_.live_value);
    return k;
  }

  OntologyIndividual make_individual(TermId i) const {
    OntologyIndividual k;
    k.iri = i;
    k.name = local_name(d_.term(i).text);
    k.label = text_of(i, v_.label);
    for (const auto& [p, o] : facts_.at(i)) {
      if (p == v_.type && classes_.count(o)) {
        k.types.push_back(o);
      } else if (properties_.count(p) && d_.is_literal(o) && !has_type(p, v_.object_prop)) {
        k.values.emplace_back(p, o);
      } else if (properties_.count(p) && individuals_.count(o) && has_type(p, v_.object_prop)) {
        k.links.emplace_back(p, o);
      }
    }
    return k;
  }

  const Dictionary& d_;
  Vocab v_;
  Facts facts_;
  std::set<TermId> classes_;
  std::set<TermId> properties_;
  std::set<TermId> individuals_;
  std::unordered_map<TermId, TermId> inverses_;
};

template <typename T>
const T* lookup(const std::unordered_map<TermId, std::size_t>& index, const std::vector<T>& items,
                TermId iri) {
  auto it = index.find(iri);
  return it == index.end() ? nullptr : &items[it->second];
}

}  // namespace

std::string local_name(std::string_view iri) {
  std::size_t cut = iri.rfind('#');
  if (cut == std::string_view::npos) {
    cut = iri.rfind('/');
  }
  return std::string(cut == std::string_view::npos ? iri : iri.substr(cut + 1));
}

const OntologyClass* OntologyModel::find_class(TermId iri) const {
  return lookup(class_index, classes, iri);
}
const OntologyProperty* OntologyModel::find_property(TermId iri) const {
  return lookup(property_index, properties, iri);
}
const OntologyIndividual* OntologyModel::find_individual(TermId iri) const {
  return lookup(individual_index, individuals, iri);
}

Result<OntologyModel> extract_ontology(const Dictionary& dict, const std::vector<Triple>& triples) {
  return Extractor(dict, triples).run();
}

}  // namespace sf::knowledge
