#include "sf/line/ontology.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace sf::line {
namespace {

TEST(OntologyTest, NamesBecomeCamelCaseLocalNames) {
  EXPECT_EQ(iri_name("scara-robot-1"), "ScaraRobot1");
  EXPECT_EQ(iri_name("conveyor2"), "Conveyor2");
  EXPECT_EQ(iri_name("small-box"), "SmallBox");
  EXPECT_EQ(iri_name("pick-and-place"), "PickAndPlace");
  EXPECT_EQ(iri_name("a b/c<d>"), "ABCd");
}

TEST(OntologyTest, TheLineDescribesWhatTheLayoutSays) {
  auto layout = default_layout();
  ASSERT_TRUE(layout);
  const std::string ttl = line_turtle(*layout, "layouts/prototype-line.yaml");
  for (const char* expected :
       {"sf:Gummy a sf:CandyType , owl:NamedIndividual ; rdfs:label \"gummy bear\" ; sf:unitWeight "
        "\"2.5\"^^xsd:double .",
        "sf:LargeBox a sf:BoxType , owl:NamedIndividual ; rdfs:label \"large box\" ; sf:capacity 30 .",
        "p:ScaraRobot1 a sf:ScaraRobot , owl:NamedIndividual ; rdfs:label \"SCARA Robot 1\" ;",
        "sf:canPerform sf:PickAndPlace , sf:BoxLoading ;", "p:Denso a sf:ArticulatedRobot",
        "p:DensoGateway a sf:Gateway ;", "sf:connectedTo p:Conveyor2 , p:Conveyor3 .",
        "p:ScaraRobot1DI3 a sf:DigitalInput ; sf:channel \"3\"^^xsd:int ; rdfs:label \"box in place at "
        "conveyor2/scara1\" .",
        "sf:length \"5.4\"^^xsd:double ;", "p:Uploader a sf:BoxUploader"}) {
    EXPECT_NE(ttl.find(expected), std::string::npos) << expected;
  }
}

// The travel is rounded outwards: θ2's ±2.5 rad (±143.239°) is written ±143.3, so the arm at its
// limit violates nothing; z's 0..0.3 m stays 0.0..300.0 mm.
TEST(OntologyTest, AnAxisTravelHoldsEveryPositionTheArmMayTake) {
  auto layout = default_layout();
  ASSERT_TRUE(layout);
  const std::string ttl = line_turtle(*layout, "layouts/prototype-line.yaml");
  EXPECT_NE(ttl.find("p:ScaraRobot1Axis2 a sf:ServoAxis ; sf:axisIndex \"2\"^^xsd:int ; sf:minPosition "
                     "\"-143.3\"^^xsd:double ; sf:maxPosition \"143.3\"^^xsd:double ."),
            std::string::npos);
  EXPECT_NE(ttl.find("sf:minPosition \"0.0\"^^xsd:double ; sf:maxPosition \"300.0\"^^xsd:double ."),
            std::string::npos);
}

// The committed ontology/prototype-line.ttl is the generator's output for the default layout.
TEST(OntologyTest, TheCommittedPrototypeLineIsGeneratedFromTheDefaultLayout) {
  const char* root = std::getenv("SF_SOURCE_DIR");
  ASSERT_NE(root, nullptr);
  std::ifstream in(std::string(root) + "/ontology/prototype-line.ttl");
  ASSERT_TRUE(in);
  std::stringstream committed;
  committed << in.rdbuf();
  auto layout = default_layout();
  ASSERT_TRUE(layout);
  EXPECT_EQ(committed.str(), line_turtle(*layout, "layouts/prototype-line.yaml"))
      << "regenerate it: smartfactory plant ontology > ontology/prototype-line.ttl";
}

}  // namespace
}  // namespace sf::line
