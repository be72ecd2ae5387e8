// Browse, BrowseNext with continuation points, TranslateBrowsePathsToNodeIds, RegisterNodes.
#include <set>

#include "space_fixture.hpp"

namespace sf::opcua::server::test {
namespace {

class BrowseServiceTest : public SpaceFixture {
 protected:
  BrowseResult browse1(const NodeId& node, BrowseDirection direction = BrowseDirection::Forward,
                       const NodeId& type = NodeId(), bool subtypes = true, std::uint32_t class_mask = 0,
                       std::uint32_t result_mask = static_cast<std::uint32_t>(BrowseResultMask::All),
                       std::uint32_t max_refs = 0) {
    BrowseRequest request;
    request.requested_max_references_per_node = max_refs;
    BrowseDescription d;
    d.node_id = node;
    d.browse_direction = direction;
    d.reference_type_id = type;
    d.include_subtypes = subtypes;
    d.node_class_mask = class_mask;
    d.result_mask = result_mask;
    request.nodes_to_browse.push_back(d);
    auto response = browse(space, request, ctx);
    EXPECT_EQ(response.results.size(), 1U);
    return response.results.empty() ? BrowseResult{} : response.results[0];
  }

  static std::set<std::string> names(const std::vector<ReferenceDescription>& refs) {
    std::set<std::string> out;
    for (const auto& r : refs) {
      out.insert(r.browse_name.name.str());
    }
    return out;
  }

  BrowsePathResult translate(const NodeId& start, const std::vector<RelativePathElement>& elements) {
    TranslateBrowsePathsToNodeIdsRequest request;
    BrowsePath path;
    path.starting_node = start;
    path.relative_path.elements = elements;
    request.browse_paths.push_back(path);
    auto response = translate_browse_paths(space, request, ctx);
    EXPECT_EQ(response.results.size(), 1U);
    return response.results.empty() ? BrowsePathResult{} : response.results[0];
  }

  static RelativePathElement element(std::uint16_t ns_index, const std::string& name,
                                     const NodeId& type = ns0(id::HierarchicalReferences),
                                     bool inverse = false) {
    RelativePathElement e;
    e.reference_type_id = type;
    e.include_subtypes = true;
    e.is_inverse = inverse;
    e.target_name = QualifiedName(ns_index, String(name));
    return e;
  }
};

TEST_F(BrowseServiceTest, DirectionsAndReferenceTypes) {
  const auto all = browse1(demo, BrowseDirection::Both);
  ASSERT_TRUE(all.status_code.is_good());
  // 5 variables + 1 method + HasTypeDefinition forward, Organizes inverse.
  EXPECT_EQ(all.references.size(), 8U);
  const auto forward = browse1(demo, BrowseDirection::Forward, ns0(id::HasComponent), false);
  EXPECT_EQ(names(forward.references),
            (std::set<std::string>{"Temperature", "Counter", "Doubles", "Text", "Matrix", "Multiply"}));
  const auto inverse = browse1(demo, BrowseDirection::Inverse);
  ASSERT_EQ(inverse.references.size(), 1U);
  EXPECT_EQ(inverse.references[0].node_id.node_id, ns0(id::ObjectsFolder));
  EXPECT_FALSE(inverse.references[0].is_forward);
  EXPECT_EQ(inverse.references[0].reference_type_id, ns0(id::Organizes));
  // HasComponent without subtypes misses nothing here; Aggregates needs includeSubtypes.
  EXPECT_TRUE(browse1(demo, BrowseDirection::Forward, ns0(id::Aggregates), false).references.empty());
  EXPECT_EQ(browse1(demo, BrowseDirection::Forward, ns0(id::Aggregates), true).references.size(), 6U);
}

TEST_F(BrowseServiceTest, NodeClassAndResultMasks) {
  const auto methods =
      browse1(demo, BrowseDirection::Forward, NodeId(), true, static_cast<std::uint32_t>(NodeClass::Method));
  ASSERT_EQ(methods.references.size(), 1U);
  EXPECT_EQ(methods.references[0].node_class, NodeClass::Method);
  EXPECT_TRUE(methods.references[0].type_definition.node_id.is_null());  // only for Objects/Variables

  const auto vars = browse1(demo, BrowseDirection::Forward, ns0(id::HasComponent), true,
                            static_cast<std::uint32_t>(NodeClass::Variable));
  ASSERT_EQ(vars.references.size(), 5U);
  EXPECT_EQ(vars.references[0].type_definition.node_id, ns0(id::BaseDataVariableType));

  const auto bare = browse1(demo, BrowseDirection::Forward, ns0(id::HasComponent), true, 0,
                            static_cast<std::uint32_t>(BrowseResultMask::BrowseName));
  ASSERT_FALSE(bare.references.empty());
  for (const auto& r : bare.references) {
    EXPECT_FALSE(r.browse_name.name.empty());
    EXPECT_TRUE(r.reference_type_id.is_null());
    EXPECT_TRUE(r.display_name.text.is_null());
    EXPECT_EQ(r.node_class, NodeClass::Unspecified);
    EXPECT_TRUE(r.type_definition.node_id.is_null());
    EXPECT_FALSE(r.node_id.node_id.is_null());  // always returned
  }
}

TEST_F(BrowseServiceTest, Errors) {
  EXPECT_EQ(browse1(NodeId(ns, "nope")).status_code, status::BadNodeIdUnknown);
  EXPECT_EQ(browse1(demo, BrowseDirection::Invalid).status_code, status::BadBrowseDirectionInvalid);
  EXPECT_EQ(browse1(demo, BrowseDirection::Forward, ns0(id::FolderType)).status_code,
            status::BadReferenceTypeIdInvalid);
  BrowseRequest request;
  EXPECT_EQ(browse(space, request, ctx).response_header.service_result, status::BadNothingToDo);
  request.nodes_to_browse.resize(3);
  ctx.limits.max_nodes_per_browse = 2;
  EXPECT_EQ(browse(space, request, ctx).response_header.service_result, status::BadTooManyOperations);
  ctx.limits.max_nodes_per_browse = 0;
  request.view.view_id = demo;
  EXPECT_EQ(browse(space, request, ctx).response_header.service_result, status::BadViewIdUnknown);
}

TEST_F(BrowseServiceTest, ContinuationPointsPageExhaustAndRelease) {
  const auto first = browse1(demo, BrowseDirection::Forward, ns0(id::HasComponent), true, 0,
                             static_cast<std::uint32_t>(BrowseResultMask::All), 4);
  ASSERT_TRUE(first.status_code.is_good());
  EXPECT_EQ(first.references.size(), 4U);
  ASSERT_FALSE(first.continuation_point.is_null());
  EXPECT_EQ(continuations.size(), 1U);

  BrowseNextRequest next;
  next.continuation_points = {first.continuation_point};
  auto rest = browse_next(space, next, ctx);
  ASSERT_EQ(rest.results.size(), 1U);
  EXPECT_TRUE(rest.results[0].status_code.is_good());
  EXPECT_EQ(rest.results[0].references.size(), 2U);
  EXPECT_TRUE(rest.results[0].continuation_point.is_null());
  auto seen = names(first.references);
  auto more = names(rest.results[0].references);
  seen.insert(more.begin(), more.end());
  EXPECT_EQ(seen.size(), 6U);
  EXPECT_EQ(continuations.size(), 0U);
  // A used point is gone.
  EXPECT_EQ(browse_next(space, next, ctx).results[0].status_code, status::BadContinuationPointInvalid);

  // The session has two points: a third browse finds none left.
  auto a = browse1(demo, BrowseDirection::Forward, NodeId(), true, 0, 63, 1);
  auto b = browse1(demo, BrowseDirection::Forward, NodeId(), true, 0, 63, 1);
  auto c = browse1(demo, BrowseDirection::Forward, NodeId(), true, 0, 63, 1);
  EXPECT_FALSE(a.continuation_point.is_null());
  EXPECT_FALSE(b.continuation_point.is_null());
  EXPECT_EQ(c.status_code, status::BadNoContinuationPoints);
  EXPECT_EQ(continuations.size(), 2U);

  // Releasing frees them.
  next.release_continuation_points = true;
  next.continuation_points = {a.continuation_point, b.continuation_point};
  auto released = browse_next(space, next, ctx);
  ASSERT_EQ(released.results.size(), 2U);
  EXPECT_TRUE(released.results[0].status_code.is_good());
  EXPECT_TRUE(released.results[0].references.empty());
  EXPECT_EQ(continuations.size(), 0U);
  EXPECT_FALSE(
      browse1(demo, BrowseDirection::Forward, NodeId(), true, 0, 63, 1).continuation_point.is_null());

  next.continuation_points.clear();
  EXPECT_EQ(browse_next(space, next, ctx).response_header.service_result, status::BadNothingToDo);
  next.continuation_points = {ByteString{1, 2, 3}};
  EXPECT_EQ(browse_next(space, next, ctx).results[0].status_code, status::BadContinuationPointInvalid);
}

TEST_F(BrowseServiceTest, TranslateBrowsePaths) {
  auto r =
      translate(ns0(id::RootFolder), {element(0, "Objects"), element(ns, "Demo"), element(ns, "Counter")});
  ASSERT_TRUE(r.status_code.is_good()) << to_string(r.status_code);
  ASSERT_EQ(r.targets.size(), 1U);
  EXPECT_EQ(r.targets[0].target_id.node_id, counter);
  EXPECT_EQ(r.targets[0].remaining_path_index, 0xFFFFFFFFU);

  auto status_time = translate(ns0(id::ObjectsFolder),
                               {element(0, "Server"), element(0, "ServerStatus"), element(0, "CurrentTime")});
  ASSERT_EQ(status_time.targets.size(), 1U);
  EXPECT_EQ(status_time.targets[0].target_id.node_id, ns0(id::Server_ServerStatus_CurrentTime));

  auto up = translate(counter, {element(ns, "Demo", ns0(id::HasComponent), true)});
  ASSERT_EQ(up.targets.size(), 1U);
  EXPECT_EQ(up.targets[0].target_id.node_id, demo);

  // Without subtypes HierarchicalReferences itself matches nothing.
  auto strict = element(0, "Objects");
  strict.include_subtypes = false;
  EXPECT_EQ(translate(ns0(id::RootFolder), {strict}).status_code, status::BadNoMatch);
  EXPECT_EQ(translate(ns0(id::RootFolder), {element(0, "Nothing")}).status_code, status::BadNoMatch);
  EXPECT_EQ(translate(ns0(id::RootFolder), {element(0, "Objects"), element(0, "")}).status_code,
            status::BadBrowseNameInvalid);
  EXPECT_EQ(translate(NodeId(ns, "nope"), {element(0, "Objects")}).status_code, status::BadNodeIdUnknown);
  EXPECT_EQ(translate(ns0(id::RootFolder), {}).status_code, status::BadNothingToDo);

  TranslateBrowsePathsToNodeIdsRequest empty;
  EXPECT_EQ(translate_browse_paths(space, empty, ctx).response_header.service_result, status::BadNothingToDo);
}

TEST_F(BrowseServiceTest, RegisterNodesEchoes) {
  RegisterNodesRequest request;
  EXPECT_EQ(register_nodes(space, request, ctx).response_header.service_result, status::BadNothingToDo);
  request.nodes_to_register = {counter, temperature};
  auto response = register_nodes(space, request, ctx);
  EXPECT_EQ(response.registered_node_ids, request.nodes_to_register);
  ctx.limits.max_nodes_per_register_nodes = 1;
  EXPECT_EQ(register_nodes(space, request, ctx).response_header.service_result, status::BadTooManyOperations);
  UnregisterNodesRequest un;
  un.nodes_to_unregister = {counter};
  EXPECT_TRUE(unregister_nodes(space, un, ctx).response_header.service_result.is_good());
}

}  // namespace
}  // namespace sf::opcua::server::test
