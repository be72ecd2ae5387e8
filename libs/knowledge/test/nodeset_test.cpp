// The ontology → NodeSet2 mapping, read back with pugixml: the structure OPC 10000-6 Annex F
// asks for, independent of a server (kb_nodeset_test loads it into node-opcua).
#include <pugixml.hpp>

#include <sstream>

#include "sf/knowledge/nodeset.hpp"
#include "test_util.hpp"

namespace sf::knowledge {
namespace {

constexpr std::string_view kOntology = R"(
@prefix sf: <http://smartfactory.example/ontology/candy#> .
<http://ex/onto> a owl:Ontology ; rdfs:label "Demo" .
sf:Machine a owl:Class ; rdfs:comment "A machine." .
sf:Robot a owl:Class ; rdfs:subClassOf sf:Machine .
sf:Capability a owl:Class .
sf:liveValue a owl:DatatypeProperty .
sf:temperature a owl:DatatypeProperty ; rdfs:subPropertyOf sf:liveValue ; rdfs:domain sf:Machine ; rdfs:range xsd:double .
sf:serial a owl:DatatypeProperty ; rdfs:domain sf:Machine ; rdfs:range xsd:unsignedInt .
sf:hasComponent a owl:ObjectProperty .
sf:canPerform a owl:ObjectProperty .
sf:processes a owl:ObjectProperty .
sf:processedBy a owl:ObjectProperty ; owl:inverseOf sf:processes .
sf:connectedTo a owl:ObjectProperty , owl:SymmetricProperty .
sf:r1 a sf:Robot , sf:Machine ; sf:temperature "41.5"^^xsd:double ; sf:serial 7 ; sf:hasComponent sf:arm ;
  sf:canPerform sf:Pick ; sf:connectedTo sf:r2 .
sf:r2 a sf:Robot ; sf:processedBy sf:r1 .
sf:arm a sf:Machine .
sf:Pick a sf:Capability .
)";

struct Nodeset : ::testing::Test {
  Dictionary d;
  pugi::xml_document doc;
  pugi::xml_node root;
  OntologyModel model;

  void SetUp() override {
    auto m = extract_ontology(d, testing::turtle(d, kOntology));
    ASSERT_TRUE(m.ok()) << m.error().message;
    model = std::move(*m);
    std::ostringstream out;
    ASSERT_TRUE(write_nodeset(out, d, model).ok());
    ASSERT_TRUE(doc.load_string(out.str().c_str()));
    root = doc.child("UANodeSet");
  }

  pugi::xml_node by_name(const char* element, const char* name) const {
    return root.find_child_by_attribute(element, "BrowseName", (std::string("1:") + name).c_str());
  }
  std::string id_of(const char* element, const char* name) const {
    return by_name(element, name).attribute("NodeId").value();
  }
  // The targets of the node's references of one type and direction.
  static std::vector<std::string> refs(pugi::xml_node n, const char* type, bool forward = true) {
    std::vector<std::string> out;
    for (auto r : n.child("References").children("Reference")) {
      if (std::string(r.attribute("ReferenceType").value()) == type &&
          r.attribute("IsForward").as_bool(true) == forward) {
        out.emplace_back(r.text().get());
      }
    }
    return out;
  }
};

TEST_F(Nodeset, ModelComesFromTheOntology) {
  EXPECT_EQ(model.namespace_uri, "http://ex/onto");
  EXPECT_EQ(model.label, "Demo");
  EXPECT_EQ(model.classes.size(), 3U);
  const OntologyProperty* t =
      model.find_property(d.iri("http://smartfactory.example/ontology/candy#temperature"));
  ASSERT_NE(t, nullptr);
  EXPECT_TRUE(t->live);
  EXPECT_FALSE(t->object);
  const OntologyProperty* by =
      model.find_property(d.iri("http://smartfactory.example/ontology/candy#processedBy"));
  EXPECT_TRUE(by->names_inverse);
  EXPECT_EQ(local_name("http://a/b#c"), "c");
  EXPECT_EQ(local_name("http://a/b/c"), "c");
}

TEST_F(Nodeset, ClassesBecomeObjectTypesWithHasSubtype) {
  EXPECT_EQ(root.child("NamespaceUris").child("Uri").text().get(), std::string("http://ex/onto"));
  const auto robot = by_name("UAObjectType", "Robot");
  ASSERT_TRUE(robot);
  EXPECT_EQ(refs(robot, "HasSubtype", false), std::vector<std::string>{id_of("UAObjectType", "Machine")});
  EXPECT_EQ(refs(by_name("UAObjectType", "Machine"), "HasSubtype", false), std::vector<std::string>{"i=58"});
  EXPECT_STREQ(by_name("UAObjectType", "Machine").child("Description").text().get(), "A machine.");
}

TEST_F(Nodeset, DatatypePropertiesBecomeTypedVariables) {
  const std::string machine = id_of("UAObjectType", "Machine");
  std::map<std::string, pugi::xml_node> declared;
  for (auto v : root.children("UAVariable")) {
    if (machine == v.attribute("ParentNodeId").value()) {
      declared[v.attribute("BrowseName").value()] = v;
    }
  }
  ASSERT_EQ(declared.size(), 2U);
  EXPECT_STREQ(declared["1:temperature"].attribute("DataType").value(), "Double");
  EXPECT_EQ(refs(declared["1:temperature"], "HasTypeDefinition"),
            std::vector<std::string>{"i=63"});  // data variable
  EXPECT_EQ(refs(declared["1:temperature"], "HasModellingRule"), std::vector<std::string>{"i=80"});
  EXPECT_STREQ(declared["1:serial"].attribute("DataType").value(), "UInt32");
  EXPECT_EQ(refs(declared["1:serial"], "HasTypeDefinition"), std::vector<std::string>{"i=68"});  // property
  EXPECT_EQ(ua_data_type(std::string(vocab::kXsd) + "dateTime").id, 13U);
  EXPECT_EQ(ua_data_type(std::string(vocab::kXsd) + "boolean").id, 1U);
  EXPECT_EQ(ua_data_type("http://ex/custom").id, 24U);
}

TEST_F(Nodeset, ObjectPropertiesBecomeReferenceTypes) {
  EXPECT_FALSE(by_name("UAReferenceType", "hasComponent"));  // OPC UA's own HasComponent
  const auto processes = by_name("UAReferenceType", "processes");
  ASSERT_TRUE(processes);
  EXPECT_STREQ(processes.child("InverseName").text().get(), "processedBy");
  EXPECT_FALSE(by_name("UAReferenceType", "processedBy"));
  EXPECT_TRUE(by_name("UAReferenceType", "connectedTo").attribute("Symmetric").as_bool());
  EXPECT_EQ(refs(by_name("UAReferenceType", "canPerform"), "HasSubtype", false),
            std::vector<std::string>{"i=32"});
}

TEST_F(Nodeset, IndividualsBecomeObjects) {
  const auto r1 = by_name("UAObject", "r1");
  ASSERT_TRUE(r1);
  EXPECT_EQ(refs(r1, "HasTypeDefinition"),
            std::vector<std::string>{id_of("UAObjectType", "Robot")});  // most specific
  EXPECT_EQ(refs(r1, "HasComponent").size(), 2U);  // the arm and the temperature variable
  EXPECT_EQ(refs(r1, id_of("UAReferenceType", "canPerform").c_str()),
            std::vector<std::string>{id_of("UAObject", "Pick")});
  const auto arm = by_name("UAObject", "arm");
  EXPECT_STREQ(arm.attribute("ParentNodeId").value(), id_of("UAObject", "r1").c_str());
  // r2 processedBy r1 is written as the inverse of processes.
  EXPECT_EQ(refs(by_name("UAObject", "r2"), id_of("UAReferenceType", "processes").c_str(), false),
            std::vector<std::string>{id_of("UAObject", "r1")});
  const std::string r1_id = id_of("UAObject", "r1");
  for (auto v : root.children("UAVariable")) {
    if (r1_id == v.attribute("ParentNodeId").value() &&
        std::string(v.attribute("BrowseName").value()) == "1:temperature") {
      EXPECT_STREQ(v.child("Value").child("Double").text().get(), "41.5");
    }
  }
  // Top-level objects sit in a folder under Objects (i=85).
  const auto folder = by_name("UAObject", "Demo");
  EXPECT_EQ(refs(folder, "Organizes", false), std::vector<std::string>{"i=85"});
  EXPECT_EQ(refs(r1, "Organizes", false), std::vector<std::string>{folder.attribute("NodeId").value()});
}

TEST(NodesetErrors, NoClassesIsAnError) {
  Dictionary d;
  auto m = extract_ontology(d, testing::turtle(d, "ex:a ex:p ex:b ."));
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, Errc::not_found);
}

}  // namespace
}  // namespace sf::knowledge
