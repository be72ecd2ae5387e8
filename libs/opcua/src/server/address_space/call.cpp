// The Call service (OPC 10000-4 §5.11.2): the method must belong to the object (or its type),
// be executable, and get the input arguments its InputArguments property declares.
#include <algorithm>

#include "server/address_space/service_util.hpp"
#include "sf/opcua/binary.hpp"

namespace sf::opcua::server {

namespace {

using detail::logger;

using detail::ns0;

// A HasComponent (or subtype) reference from holder to method.
bool has_component(const AddressSpace& space, const NodeId& holder, const NodeId& method) {
  const Node* node = space.find(holder);
  if (node == nullptr) {
    return false;
  }
  return std::any_of(node->references.begin(), node->references.end(), [&](const Reference& r) {
    return r.is_forward && r.target_id == method &&
           space.is_subtype(r.reference_type_id, ns0(id::HasComponent));
  });
}

// OPC 10000-4 §5.11.2.1: the Method is a component of the Object, or of its ObjectType (or a
// supertype), whose Methods all instances share.
bool method_of(const AddressSpace& space, const Node& object, const NodeId& method) {
  if (has_component(space, object.node_id, method)) {
    return true;
  }
  const NodeId* type =
      object.node_class() == NodeClass::ObjectType ? &object.node_id : space.type_definition(object.node_id);
  for (int depth = 0; type != nullptr && depth < 64; ++depth) {
    if (has_component(space, *type, method)) {
      return true;
    }
    type = space.supertype(*type);
  }
  return false;
}

// The Argument[] value of the method's InputArguments/OutputArguments property (empty if none).
std::vector<Argument> arguments(const AddressSpace& space, const NodeId& method, std::string_view name) {
  std::vector<Argument> out;
  const Node* property = space.child(method, QualifiedName(0, String(name)));
  if (property == nullptr) {
    return out;
  }
  auto value = space.value(property->node_id);
  const auto* list = value ? value->value.array_if<ExtensionObject>() : nullptr;
  if (list == nullptr) {
    return out;
  }
  for (const auto& object : *list) {
    if (const auto* argument = object.get_if<Argument>()) {
      out.push_back(*argument);
    } else if (const auto* body = object.opaque_body();
               body != nullptr && object.type_id() == ns0(id::Argument_Encoding_DefaultBinary)) {
      // A body kept undecoded (e.g. imported from elsewhere).
      ByteReader reader(body->span());
      Decoder decoder(reader);
      Argument decoded;
      decode_binary(decoder, decoded);
      if (decoder.ok()) {
        out.push_back(std::move(decoded));
      }
    }
  }
  return out;
}

CallMethodResult call_one(AddressSpace& space, const CallMethodRequest& request, const ServiceContext& ctx) {
  CallMethodResult result;
  const Node* object = space.find(request.object_id);
  const auto* method = space.find_as<MethodNode>(request.method_id);
  if (object == nullptr) {
    result.status_code = status::BadNodeIdUnknown;
  } else if (object->node_class() != NodeClass::Object && object->node_class() != NodeClass::ObjectType) {
    result.status_code = status::BadNodeIdInvalid;
  } else if (method == nullptr || !method_of(space, *object, request.method_id)) {
    result.status_code = status::BadMethodInvalid;
  } else if (!method->executable) {
    result.status_code = status::BadNotExecutable;
  } else if (!method->user_executable || (ctx.user != nullptr && !ctx.user->can_call(*method))) {
    result.status_code = status::BadUserAccessDenied;
  }
  if (result.status_code.is_bad()) {
    return result;
  }
  const auto declared = arguments(space, request.method_id, "InputArguments");
  const auto& given = request.input_arguments;
  if (given.size() < declared.size()) {
    result.status_code = status::BadArgumentsMissing;
    return result;
  }
  if (given.size() > declared.size()) {
    result.status_code = status::BadTooManyArguments;
    return result;
  }
  bool all_good = true;
  result.input_argument_results.resize(given.size());
  for (std::size_t i = 0; i < given.size(); ++i) {
    const auto& a = declared[i];
    const std::vector<std::uint32_t> dims(a.array_dimensions.begin(), a.array_dimensions.end());
    result.input_argument_results[i] = detail::check_value(space, given[i], a.data_type, a.value_rank, dims);
    all_good = all_good && result.input_argument_results[i].is_good();
  }
  if (!all_good) {
    result.status_code = status::BadInvalidArgument;
    return result;
  }
  result.input_argument_results.clear();
  if (!method->callback) {
    result.status_code = status::BadNotImplemented;
    return result;
  }
  // The callback may change the address space: copy it before the call.
  const MethodCallback callback = method->callback;
  std::vector<Variant> in(given.begin(), given.end());
  std::vector<Variant> out;
  result.status_code = callback(request.object_id, in, out);
  if (!result.status_code.is_bad()) {
    result.output_arguments = Array<Variant>(std::move(out));
  }
  return result;
}

}  // namespace

CallResponse call(AddressSpace& space, const CallRequest& request, ServiceContext& ctx) {
  CallResponse response;
  response.response_header = detail::response_header(request.request_header, ctx);
  if (!detail::check_operation_count("Call", request.methods_to_call.size(),
                                     ctx.limits.max_nodes_per_method_call, response.response_header)) {
    return response;
  }
  for (const auto& item : request.methods_to_call) {
    response.results.push_back(call_one(space, item, ctx));
    if (response.results.back().status_code.is_bad()) {
      logger()->debug("Call {} on {}: {}", to_string(item.method_id), to_string(item.object_id),
                      to_string(response.results.back().status_code));
    }
  }
  return response;
}

}  // namespace sf::opcua::server
