// The parts of an OWL ontology (OWL 2 Structural Specification §5, in its RDF mapping) that an
// OPC UA information model is built from (paper §VI): named classes with their superclasses,
// object and datatype properties with domain, range and characteristics, and individuals with
// their types, data values and links.
#pragma once

#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/knowledge/store.hpp"

namespace sf::knowledge {

struct OntologyClass {
  TermId iri = kNoTerm;
  std::string name;  // local name
  std::string label;
  std::string comment;
  std::vector<TermId> parents;  // named superclasses (rdfs:subClassOf)
};

struct OntologyProperty {
  TermId iri = kNoTerm;
  std::string name;
  std::string label;
  std::string comment;
  bool object = false;  // owl:ObjectProperty (else owl:DatatypeProperty)
  std::vector<TermId> domains;
  TermId range = kNoTerm;
  TermId inverse = kNoTerm;     // owl:inverseOf, either direction
  bool names_inverse = false;   // this property is the subject of the owl:inverseOf statement
  std::vector<TermId> parents;  // rdfs:subPropertyOf
  bool symmetric = false;
  bool transitive = false;
  bool part_of = false;  // sf:hasComponent or a sub-property of it: OPC UA HasComponent
  bool live = false;     // a sub-property of sf:liveValue: a data variable, not a property
};

struct OntologyIndividual {
  TermId iri = kNoTerm;
  std::string name;
  std::string label;
  std::vector<TermId> types;                      // asserted named classes
  std::vector<std::pair<TermId, TermId>> values;  // datatype property, literal
  std::vector<std::pair<TermId, TermId>> links;   // object property, individual
};

struct OntologyModel {
  std::string namespace_uri;  // the owl:Ontology IRI
  std::string label;          // its rdfs:label
  std::vector<OntologyClass> classes;
  std::vector<OntologyProperty> properties;
  std::vector<OntologyIndividual> individuals;

  [[nodiscard]] const OntologyClass* find_class(TermId iri) const;
  [[nodiscard]] const OntologyProperty* find_property(TermId iri) const;
  [[nodiscard]] const OntologyIndividual* find_individual(TermId iri) const;

  std::unordered_map<TermId, std::size_t> class_index;
  std::unordered_map<TermId, std::size_t> property_index;
  std::unordered_map<TermId, std::size_t> individual_index;
};

// Reads the model from triples (an ontology file, optionally with data). Classes, properties
// and individuals come out sorted by IRI, so the same input gives the same model.
Result<OntologyModel> extract_ontology(const Dictionary& dict, const std::vector<Triple>& triples);

// The local name of an IRI: after the last '#', else after the last '/'.
std::string local_name(std::string_view iri);

}  // namespace sf::knowledge
