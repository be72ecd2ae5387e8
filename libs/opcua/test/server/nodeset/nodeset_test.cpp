// NodeSet2 import and export (OPC 10000-6 Annex F): a model survives export → import into a
// fresh address space node by node; hand-written files with aliases, foreign namespace indexes
// and the XML value encoding of OPC 10000-6 §5.3 import as the spec reads; bad files are
// refused with file:line:column and change nothing.
#include "sf/opcua/server/nodeset.hpp"

#include <gtest/gtest.h>

#include <string>

#include "sf/examples/opcua_demo.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server {
namespace {

AddressSpace fresh_space() {
  AddressSpace space;
  EXPECT_TRUE(build_namespace0(space));
  return space;
}

// A model with every node class and values of many built-in types, in namespace urn:test.
void build_model(AddressSpace& space) {
  const std::uint16_t ns = space.add_namespace("urn:test");
  ObjectTypeSpec machine_type;
  machine_type.node_id = NodeId(ns, 1000);
  machine_type.browse_name = QualifiedName(ns, "MachineType");
  machine_type.parent = NodeId(0, id::BaseObjectType);
  machine_type.is_abstract = true;
  ASSERT_TRUE(space.add_object_type(machine_type));

  ReferenceTypeSpec feeds;
  feeds.node_id = NodeId(ns, 1001);
  feeds.browse_name = QualifiedName(ns, "Feeds");
  feeds.parent = NodeId(0, id::NonHierarchicalReferences);
  feeds.inverse_name = LocalizedText("en", "FedBy");
  ASSERT_TRUE(space.add_reference_type(feeds));

  ObjectSpec machine;
  machine.node_id = NodeId(ns, String("Robot 1"));
  machine.browse_name = QualifiedName(ns, "Robot1");
  machine.display_name = LocalizedText("en", "Robot 1");
  machine.description = LocalizedText("de", "Ein Roboter <mit> & Sonderzeichen");
  machine.parent = NodeId(0, id::ObjectsFolder);
  machine.reference_type = NodeId(0, id::Organizes);
  machine.type_definition = NodeId(ns, 1000);
  machine.event_notifier = event_notifier::SubscribeToEvents;
  ASSERT_TRUE(space.add_object(machine));

  const auto add = [&](std::string_view name, std::uint32_t data_type, Variant value, std::int32_t rank) {
    VariableSpec v;
    v.node_id = NodeId(ns, String(std::string("Robot 1.") + std::string(name)));
    v.browse_name = QualifiedName(ns, String(name));
    v.parent = NodeId(ns, String("Robot 1"));
    v.data_type = NodeId(0, data_type);
    v.value_rank = rank;
    v.value = DataValue(std::move(value));
    v.access_level = access_level::ReadWrite;
    v.user_access_level = access_level::CurrentRead;
    v.minimum_sampling_interval = 250.0;
    ASSERT_TRUE(space.add_variable(v)) << name;
  };
  add("Speed", id::Double, Variant(1.25), value_rank::Scalar);
  add("Tiny", id::Float, Variant(0.1F), value_rank::Scalar);
  add("Count", id::UInt64, Variant(std::uint64_t{18'446'744'073'709'551'615ULL}), value_rank::Scalar);
  add("Offset", id::SByte, Variant(std::int8_t{-128}), value_rank::Scalar);
  add("On", id::Boolean, Variant(true), value_rank::Scalar);
  add("Name", id::String, Variant("candy <&> box"), value_rank::Scalar);
  add("Since", id::DateTime, Variant(DateTime(133'000'000'000'000'123)), value_rank::Scalar);
  add("Id", id::Guid, Variant(*Guid::parse("72962B91-FA75-4AE6-8D28-B404DC7DAF63")), value_rank::Scalar);
  add("Blob", id::ByteString, Variant(ByteString{0, 1, 2, 250, 255}), value_rank::Scalar);
  add("Where", id::NodeId, Variant(NodeId(ns, String("Robot 1"))), value_rank::Scalar);
  add("Label", id::LocalizedText, Variant(LocalizedText("en", "hello")), value_rank::Scalar);
  add("Qname", id::QualifiedName, Variant(QualifiedName(ns, "Q")), value_rank::Scalar);
  add("Status", id::StatusCode, Variant(StatusCode(status::BadTimeout)), value_rank::Scalar);
  add("Names", id::String, Variant(std::vector<String>{"a", "b", ""}), value_rank::OneDimension);
  add("Matrix", id::Int32, *Variant::matrix(Array<std::int32_t>{1, 2, 3, 4, 5, 6}, {2, 3}), 2);
  add("Mixed", id::BaseDataType, Variant(std::vector<Variant>{Variant(1.5), Variant("x")}),
      value_rank::OneDimension);
  Range range;
  range.low = -10.0;
  range.high = 90.0;
  add("Range", id::Range, Variant(ExtensionObject::make(range)), value_rank::Scalar);

  MethodSpec start;
  start.node_id = NodeId(ns, String("Robot 1.Start"));
  start.browse_name = QualifiedName(ns, "Start");
  start.parent = NodeId(ns, String("Robot 1"));
  Argument speed;
  speed.name = "speed";
  speed.data_type = NodeId(0, id::Double);
  speed.value_rank = value_rank::Scalar;
  speed.description = LocalizedText("en", "mm/s");
  start.input_arguments = {speed};
  ASSERT_TRUE(space.add_method(start));

  ASSERT_TRUE(space.add_reference(NodeId(ns, String("Robot 1")), NodeId(ns, 1001), NodeId(0, id::Server)));
}

// A NodeId or QualifiedName value of namespace `from` moved to namespace `to`.
Variant translated(const Variant& value, std::uint16_t from, std::uint16_t to) {
  if (const auto* id = value.get_if<NodeId>(); id != nullptr && id->namespace_index == from) {
    NodeId copy = *id;
    copy.namespace_index = to;
    return Variant(copy);
  }
  if (const auto* name = value.get_if<QualifiedName>(); name != nullptr && name->namespace_index == from) {
    return Variant(QualifiedName(to, name->name));
  }
  return value;
}

// Every node of namespace `uri` in `a` (at least min_nodes) has an equal node in `b`:
// attributes, value and the set of references.
void expect_same_namespace(const AddressSpace& a, const AddressSpace& b, std::string_view uri,
                           std::size_t min_nodes) {
  const std::uint16_t ns_a = *a.namespace_index(uri);
  const auto ns_b_found = b.namespace_index(uri);
  ASSERT_TRUE(ns_b_found.has_value());
  const std::uint16_t ns_b = *ns_b_found;
  const auto translate = [&](NodeId id) {
    if (id.namespace_index == ns_a) {
      id.namespace_index = ns_b;
    }
    return id;
  };
  std::size_t compared = 0;
  a.for_each_node([&](const Node& node) {
    if (node.node_id.namespace_index != ns_a) {
      return;
    }
    ++compared;
    const Node* other = b.find(translate(node.node_id));
    ASSERT_NE(other, nullptr) << to_string(node.node_id);
    EXPECT_EQ(other->node_class(), node.node_class());
    EXPECT_EQ(other->browse_name.name, node.browse_name.name);
    EXPECT_EQ(other->display_name, node.display_name) << to_string(node.node_id);
    EXPECT_EQ(other->description, node.description) << to_string(node.node_id);
    EXPECT_EQ(other->references.size(), node.references.size()) << to_string(node.node_id);
    for (const Reference& r : node.references) {
      const Reference mapped{translate(r.reference_type_id), translate(r.target_id), r.is_forward};
      EXPECT_NE(std::find(other->references.begin(), other->references.end(), mapped),
                other->references.end())
          << to_string(node.node_id) << " lacks " << to_string(r.target_id);
    }
    if (const auto* v = node.as<VariableNode>()) {
      const auto* w = other->as<VariableNode>();
      ASSERT_NE(w, nullptr);
      EXPECT_EQ(w->value.value, translated(v->value.value, ns_a, ns_b)) << to_string(node.node_id);
      EXPECT_EQ(w->data_type, v->data_type);
      EXPECT_EQ(w->value_rank, v->value_rank);
      EXPECT_EQ(w->access_level, v->access_level);
      EXPECT_EQ(w->user_access_level, v->user_access_level);
      EXPECT_EQ(w->minimum_sampling_interval, v->minimum_sampling_interval);
    }
  });
  EXPECT_GE(compared, min_nodes);
}

TEST(NodeSet, ExportThenImportReproducesEveryNode) {
  AddressSpace source = fresh_space();
  build_model(source);
  auto xml = export_nodeset(source, {.namespace_uris = {"urn:test"}});
  ASSERT_TRUE(xml.ok()) << xml.error().message;

  AddressSpace target = fresh_space();
  target.add_namespace("urn:other");  // shifts urn:test to another index in the target
  auto report = import_nodeset(target, *xml);
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_TRUE(report->warnings.empty()) << report->warnings.front();
  EXPECT_EQ(report->namespace_uris, std::vector<std::string>{"urn:test"});
  expect_same_namespace(source, target, "urn:test", 22);
  const std::uint16_t ns = *target.namespace_index("urn:test");
  EXPECT_EQ(ns, 2);
  // Type and instance relations survive: the robot's type is the imported abstract type.
  EXPECT_EQ(*target.type_definition(NodeId(ns, String("Robot 1"))), NodeId(ns, 1000));
  EXPECT_TRUE(target.find_as<ObjectTypeNode>(NodeId(ns, 1000))->is_abstract);
  EXPECT_EQ(target.find_as<ReferenceTypeNode>(NodeId(ns, 1001))->inverse_name, LocalizedText("en", "FedBy"));
}

TEST(NodeSet, DemoModelRoundTripsAndExportIsStable) {
  AddressSpace source = fresh_space();
  ASSERT_TRUE(examples::add_demo_nodes(source));
  auto first = export_nodeset(source, {.namespace_uris = {std::string(examples::kDemoNamespaceUri)}});
  ASSERT_TRUE(first.ok());
  AddressSpace target = fresh_space();
  ASSERT_TRUE(import_nodeset(target, *first).ok());
  expect_same_namespace(source, target, examples::kDemoNamespaceUri, 6);
  auto second = export_nodeset(target, {.namespace_uris = {std::string(examples::kDemoNamespaceUri)}});
  ASSERT_TRUE(second.ok());
  // Apart from the time stamps, exporting the import gives the same document.
  const auto strip = [](std::string text) {
    for (const char* attribute : {"LastModified=\"", "PublicationDate=\""}) {
      for (auto at = text.find(attribute); at != std::string::npos; at = text.find(attribute, at + 1)) {
        const auto start = at + std::string_view(attribute).size();
        text.erase(start, text.find('"', start) - start);
      }
    }
    return text;
  };
  EXPECT_EQ(strip(*first), strip(*second));
}

// A file as modelling tools write it: aliases, its own namespace numbering, references listed on
// both ends, values in the XML encoding.
constexpr std::string_view kHandWritten = R"(<?xml version="1.0" encoding="utf-8"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd"
           xmlns:uax="http://opcfoundation.org/UA/2008/02/Types.xsd">
  <NamespaceUris>
    <Uri>urn:a</Uri>
    <Uri>urn:b</Uri>
  </NamespaceUris>
  <Aliases>
    <Alias Alias="Double">i=11</Alias>
    <Alias Alias="HasComponent">i=47</Alias>
    <Alias Alias="HasProperty">i=46</Alias>
    <Alias Alias="HasTypeDefinition">i=40</Alias>
    <Alias Alias="Organizes">i=35</Alias>
  </Aliases>
  <UAObject NodeId="ns=2;i=1" BrowseName="2:Line">
    <DisplayName>Line</DisplayName>
    <References>
      <Reference ReferenceType="Organizes" IsForward="false">i=85</Reference>
      <Reference ReferenceType="HasTypeDefinition">i=58</Reference>
      <Reference ReferenceType="HasComponent">ns=2;i=2</Reference>
      <Reference ReferenceType="HasProperty">ns=2;i=3</Reference>
    </References>
  </UAObject>
  <UAVariable NodeId="ns=2;i=2" BrowseName="2:Temperature" DataType="Double" AccessLevel="3">
    <DisplayName>Temperature</DisplayName>
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=2;i=1</Reference>
      <Reference ReferenceType="HasTypeDefinition">i=63</Reference>
    </References>
    <Value><uax:Double>21.5</uax:Double></Value>
  </UAVariable>
  <UAVariable NodeId="ns=2;i=3" BrowseName="1:Limits" DataType="i=12" ValueRank="1" ArrayDimensions="2">
    <DisplayName>Limits</DisplayName>
    <References>
      <Reference ReferenceType="HasTypeDefinition">i=68</Reference>
    </References>
    <Value>
      <uax:ListOfString><uax:String>low</uax:String><uax:String>high</uax:String></uax:ListOfString>
    </Value>
  </UAVariable>
  <UAMethod NodeId="ns=2;i=4" BrowseName="2:Stop" ParentNodeId="ns=2;i=1">
    <References>
      <Reference ReferenceType="HasComponent" IsForward="false">ns=2;i=1</Reference>
      <Reference ReferenceType="HasProperty">ns=2;i=5</Reference>
    </References>
  </UAMethod>
  <UAVariable NodeId="ns=2;i=5" BrowseName="InputArguments" DataType="i=296" ValueRank="1">
    <References>
      <Reference ReferenceType="HasTypeDefinition">i=68</Reference>
    </References>
    <Value>
      <uax:ListOfExtensionObject>
        <uax:ExtensionObject>
          <uax:TypeId><uax:Identifier>i=297</uax:Identifier></uax:TypeId>
          <uax:Body>
            <uax:Argument>
              <uax:Name>reason</uax:Name>
              <uax:DataType><uax:Identifier>ns=1;i=77</uax:Identifier></uax:DataType>
              <uax:ValueRank>-1</uax:ValueRank>
              <uax:ArrayDimensions />
              <uax:Description><uax:Locale>en</uax:Locale><uax:Text>why</uax:Text></uax:Description>
            </uax:Argument>
          </uax:Body>
        </uax:ExtensionObject>
      </uax:ListOfExtensionObject>
    </Value>
  </UAVariable>
</UANodeSet>
)";

TEST(NodeSet, ImportsAHandWrittenFileWithItsOwnNamespaceNumbering) {
  AddressSpace space = fresh_space();
  space.add_namespace("urn:b");  // urn:b exists (index 1); urn:a is new (index 2)
  auto report = import_nodeset(space, kHandWritten, {.source_name = "line.xml"});
  ASSERT_TRUE(report.ok()) << report.error().message;
  const std::uint16_t a = *space.namespace_index("urn:a");
  const std::uint16_t b = *space.namespace_index("urn:b");
  EXPECT_EQ(a, 2);
  EXPECT_EQ(b, 1);
  EXPECT_EQ(report->nodes_added, 5U);
  // File index 2 (urn:b) is the server's 1, file index 1 (urn:a) is the server's 2.
  const Node* line = space.find(NodeId(b, 1));
  ASSERT_NE(line, nullptr);
  EXPECT_EQ(line->browse_name, QualifiedName(b, "Line"));
  const auto* limits = space.find_as<VariableNode>(NodeId(b, 3));
  ASSERT_NE(limits, nullptr);
  EXPECT_EQ(limits->browse_name, QualifiedName(a, "Limits"));
  EXPECT_EQ(limits->value.value, Variant(std::vector<String>{"low", "high"}));
  EXPECT_EQ(limits->array_dimensions, std::vector<std::uint32_t>{2});
  const auto* temperature = space.find_as<VariableNode>(NodeId(b, 2));
  ASSERT_NE(temperature, nullptr);
  EXPECT_EQ(temperature->value.value, Variant(21.5));
  EXPECT_EQ(temperature->data_type, NodeId(0, id::Double));
  EXPECT_EQ(temperature->access_level, 3);
  // The Argument's DataType NodeId is translated like every other NodeId.
  const auto* arguments = space.find_as<VariableNode>(NodeId(b, 5))->value.value.array_if<ExtensionObject>();
  ASSERT_NE(arguments, nullptr);
  ASSERT_EQ(arguments->size(), 1U);
  const Argument* reason = (*arguments)[0].get_if<Argument>();
  ASSERT_NE(reason, nullptr);
  EXPECT_EQ(reason->name, "reason");
  EXPECT_EQ(reason->data_type, NodeId(a, 77));
  EXPECT_EQ(reason->description, LocalizedText("en", "why"));
  // The Objects folder organizes Line; the reference listed on both ends exists once.
  EXPECT_NE(space.child(NodeId(0, id::ObjectsFolder), QualifiedName(b, "Line")), nullptr);
  EXPECT_EQ(std::count(line->references.begin(), line->references.end(),
                       Reference{NodeId(0, id::HasComponent), NodeId(b, 2), true}),
            1);
  EXPECT_TRUE(report->warnings.empty());
}

// Replaces the first occurrence of `from` in the hand-written file.
std::string variant_of(std::string_view from, std::string_view to) {
  std::string text(kHandWritten);
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  return text;
}

struct BadFile {
  std::string name;
  std::string xml;
  std::string expected;  // part of the error message, with its location
};

TEST(NodeSet, BadFilesAreRefusedWithTheirLocationAndChangeNothing) {
  const std::vector<BadFile> cases = {
      {"truncated", std::string(kHandWritten.substr(0, 400)), "bad.xml:"},
      {"root", "<Foo/>", "bad.xml:1:1: the root element is <Foo>"},
      {"alias", variant_of("DataType=\"Double\"", "DataType=\"Dubble\""),
       "bad.xml:24:3: 'Dubble' is neither an alias"},
      {"node id", variant_of("NodeId=\"ns=2;i=2\"", "NodeId=\"ns=2;x=2\""),
       "bad.xml:24:3: invalid NodeId 'ns=2;x=2'"},
      {"namespace", variant_of("NodeId=\"ns=2;i=2\"", "NodeId=\"ns=7;i=2\""),
       "namespace index 7 of ns=7;i=2 is not in the NamespaceUris table"},
      {"value", variant_of("<uax:Double>21.5</uax:Double>", "<uax:Double>warm</uax:Double>"),
       "bad.xml:30:12: 'warm' is not a Double"},
      {"value type", variant_of("<uax:Double>21.5</uax:Double>", "<uax:Real>1</uax:Real>"),
       "<Real> is not a value type"},
      {"duplicate", variant_of("NodeId=\"ns=2;i=3\"", "NodeId=\"ns=2;i=2\""),
       "NodeId ns=1;i=2 appears twice"},
      {"existing", variant_of("NodeId=\"ns=2;i=1\"", "NodeId=\"i=85\" x=\"\""), ""},
      {"number", variant_of("AccessLevel=\"3\"", "AccessLevel=\"300\""),
       "AccessLevel=\"300\" is not a valid"},
  };
  for (const BadFile& bad : cases) {
    AddressSpace space = fresh_space();
    space.add_namespace("urn:b");
    const std::size_t before = space.size();
    const auto version = space.model_version();
    auto report = import_nodeset(
        space, bad.xml, {.source_name = "bad.xml", .skip_existing_namespace0 = bad.name != "existing"});
    ASSERT_FALSE(report.ok()) << bad.name;
    EXPECT_NE(report.error().message.find(bad.expected), std::string::npos)
        << bad.name << ": " << report.error().message;
    EXPECT_EQ(space.size(), before) << bad.name;
    if (bad.name != "existing") {
      EXPECT_EQ(space.model_version(), version) << bad.name;
    }
  }
}

TEST(NodeSet, ExistingNodesOfNamespace0AreSkippedAndOthersRefused) {
  AddressSpace space = fresh_space();
  const std::string with_ns0 = variant_of("<UAObject NodeId=\"ns=2;i=1\"",
                                          "<UAObject NodeId=\"i=85\" BrowseName=\"Objects\"/>\n"
                                          "  <UAObject NodeId=\"ns=2;i=1\"");
  auto report = import_nodeset(space, with_ns0);
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_EQ(report->nodes_skipped, 1U);
  EXPECT_EQ(report->nodes_added, 5U);
  // A second import of the same file collides with its own nodes.
  auto again = import_nodeset(space, kHandWritten, {.source_name = "again.xml"});
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.error().message.find("again.xml:15:3: BadNodeIdExists"), std::string::npos)
      << again.error().message;
}

TEST(NodeSet, ReferencesToUnknownNodesAreWarnings) {
  AddressSpace space = fresh_space();
  auto report = import_nodeset(
      space, variant_of("<Reference ReferenceType=\"HasTypeDefinition\">i=63</Reference>",
                        "<Reference ReferenceType=\"HasTypeDefinition\">ns=1;i=999</Reference>"));
  ASSERT_TRUE(report.ok()) << report.error().message;
  ASSERT_EQ(report->warnings.size(), 1U);
  EXPECT_NE(report->warnings[0].find("<nodeset>:28:7: reference"), std::string::npos) << report->warnings[0];
}

TEST(NodeSet, ExportOfAnUnknownNamespaceFails) {
  AddressSpace space = fresh_space();
  auto xml = export_nodeset(space, {.namespace_uris = {"urn:nowhere"}});
  ASSERT_FALSE(xml.ok());
  EXPECT_NE(xml.error().message.find("urn:nowhere"), std::string::npos);
}

TEST(NodeSet, MissingFileIsAClearError) {
  AddressSpace space = fresh_space();
  auto report = import_nodeset_file(space, "/nonexistent/model.xml");
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.error().message.find("/nonexistent/model.xml"), std::string::npos);
}

}  // namespace
}  // namespace sf::opcua::server
