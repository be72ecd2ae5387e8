// Ontology → OPC UA information model as a NodeSet2 XML document (OPC 10000-6 Annex F,
// UANodeSet.xsd): classes become ObjectTypes (rdfs:subClassOf → HasSubtype), datatype
// properties variables of those types with the XSD range mapped to a namespace-0 DataType,
// object properties ReferenceTypes (part-of → HasComponent, owl:inverseOf → InverseName,
// owl:SymmetricProperty → Symmetric), individuals Objects with HasTypeDefinition, their data
// values variables and their links references. Written with pugixml, without the OPC UA module.
#pragma once

#include <ostream>
#include <string>

#include "sf/core/result.hpp"
#include "sf/knowledge/ontology.hpp"

namespace sf::knowledge {

struct NodesetOptions {
  std::string namespace_uri;      // empty: the ontology's IRI
  std::uint32_t first_id = 1000;  // numeric NodeIds are assigned from here, in model order
};

// The namespace-0 DataType of an XSD datatype (OPC 10000-6 §5.1.2 built-in types: Boolean i=1
// ... DateTime i=13), BaseDataType (i=24) when there is none.
struct UaDataType {
  std::uint32_t id;
  std::string_view name;
};
UaDataType ua_data_type(std::string_view xsd_datatype);

Status write_nodeset(std::ostream& out, const Dictionary& dict, const OntologyModel& model,
                     const NodesetOptions& options = {});

}  // namespace sf::knowledge
