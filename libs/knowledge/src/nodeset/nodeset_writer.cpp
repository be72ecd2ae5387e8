// NodeSet2 XML (OPC 10000-6 Annex F): UAObjectType, UAVariable, UAReferenceType and UAObject
// elements with their References, NodeIds numbered from NodesetOptions::first_id in namespace 1.
#include <pugixml.hpp>

#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

#include "sf/knowledge/nodeset.hpp"
#include "sf/knowledge/vocab.hpp"

namespace sf::knowledge {
namespace {

constexpr const char* kUaTypes = "http://opcfoundation.org/UA/2008/02/Types.xsd";

// Namespace-0 nodes the model points at (OPC 10000-3 §5, 10000-5 §6).
constexpr std::uint32_t kBaseObjectType = 58;
constexpr std::uint32_t kBaseDataVariableType = 63;
constexpr std::uint32_t kPropertyType = 68;
constexpr std::uint32_t kFolderType = 61;
constexpr std::uint32_t kObjectsFolder = 85;
constexpr std::uint32_t kNonHierarchicalReferences = 32;
constexpr std::uint32_t kHasComponentId = 47;
constexpr std::uint32_t kModellingRuleOptional = 80;

struct RefType {
  std::string target;  // NodeId or alias of the ReferenceType
  bool forward = true;
};

class Writer {
 public:
  Writer(const Dictionary& d, const OntologyModel& m, const NodesetOptions& o) : d_(d), m_(m), opts_(o) {
    next_ = o.first_id;
  }

  Status write(std::ostream& out) {
    header();
    assign_ids();
    for (const OntologyProperty& p : m_.properties) {
      reference_type(p);
    }
    for (const OntologyClass& c : m_.classes) {
      object_type(c);
    }
    folder();
    for (const OntologyIndividual& i : m_.individuals) {
      object(i);
    }
    doc_.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
    return out ? Status{} : make_error(Errc::io, "writing the NodeSet2 document failed");
  }

 private:
  static std::string ns0(std::uint32_t id) { return fmt::format("i={}", id); }
  static std::string ns1(std::uint32_t id) { return fmt::format("ns=1;i={}", id); }

  void header() {
    auto decl = doc_.append_child(pugi::node_declaration);
    decl.append_attribute("version") = "1.0";
    decl.append_attribute("encoding") = "utf-8";
    root_ = doc_.append_child("UANodeSet");
    root_.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
    root_.append_attribute("xmlns:xsd") = "http://www.w3.org/2001/XMLSchema";
    root_.append_attribute("xmlns") = "http://opcfoundation.org/UA/2011/03/UANodeSet.xsd";
    const std::string uri = opts_.namespace_uri.empty() ? m_.namespace_uri : opts_.namespace_uri;
    root_.append_child("NamespaceUris").append_child("Uri").text() = uri.c_str();
    auto model = root_.append_child("Models").append_child("Model");
    model.append_attribute("ModelUri") = uri.c_str();
    model.append_attribute("Version") = "1.0.0";
    model.append_attribute("PublicationDate") = "2024-01-01T00:00:00Z";
    auto req = model.append_child("RequiredModel");
    req.append_attribute("ModelUri") = "http://opcfoundation.org/UA/";
    req.append_attribute("Version") = "1.04";
    req.append_attribute("PublicationDate") = "2019-05-01T00:00:00Z";
    auto aliases = root_.append_child("Aliases");
    const std::pair<const char*, std::uint32_t> known[] = {{"Boolean", 1},
                                                           {"SByte", 2},
                                                           {"Byte", 3},
                                                           {"Int16", 4},
                                                           {"UInt16", 5},
                                                           {"Int32", 6},
                                                           {"UInt32", 7},
                                                           {"Int64", 8},
                                                           {"UInt64", 9},
                                                           {"Float", 10},
                                                           {"Double", 11},
                                                           {"String", 12},
                                                           {"DateTime", 13},
                                                           {"ByteString", 15},
                                                           {"BaseDataType", 24},
                                                           {"Organizes", 35},
                                                           {"HasModellingRule", 37},
                                                           {"HasTypeDefinition", 40},
                                                           {"HasSubtype", 45},
                                                           {"HasProperty", 46},
                                                           {"HasComponent", 47}};
    for (const auto& [name, id] : known) {
      auto a = aliases.append_child("Alias");
      a.append_attribute("Alias") = name;
      a.text() = ns0(id).c_str();
    }
  }

  // Every class, emitted object property, individual and the folder gets a number, in model order.
  void assign_ids() {
    for (const OntologyClass& c : m_.classes) {
      ids_[c.iri] = next_++;
    }
    // Of an inverse pair one ReferenceType is made, for the property the other is declared the
    // inverse of ("processedBy owl:inverseOf processes" makes processes / InverseName processedBy).
    for (const OntologyProperty& p : m_.properties) {
      const OntologyProperty* inv = p.inverse == kNoTerm ? nullptr : m_.find_property(p.inverse);
      const bool secondary =
          inv != nullptr && (p.names_inverse ? !inv->names_inverse || inv->iri < p.iri : false);
      if (p.object && !is_has_component(p) && !secondary && !(inv != nullptr && is_has_component(*inv))) {
        ids_[p.iri] = next_++;
      }
    }
    folder_id_ = next_++;
    for (const OntologyIndividual& i : m_.individuals) {
      ids_[i.iri] = next_++;
    }
  }

  static bool is_has_component(const OntologyProperty& p) { return p.name == "hasComponent"; }

  pugi::xml_node node(const char* element, std::uint32_t id, const std::string& name,
                      const std::string& display, const std::string& description) {
    auto n = root_.append_child(element);
    n.append_attribute("NodeId") = ns1(id).c_str();
    n.append_attribute("BrowseName") = ("1:" + name).c_str();
    n.append_child("DisplayName").text() = (display.empty() ? name : display).c_str();
    if (!description.empty()) {
      n.append_child("Description").text() = description.c_str();
    }
    return n;
  }

  static void ref(pugi::xml_node refs, const std::string& type, const std::string& target,
                  bool forward = true) {
    auto r = refs.append_child("Reference");
    r.append_attribute("ReferenceType") = type.c_str();
    if (!forward) {
      r.append_attribute("IsForward") = "false";
    }
    r.text() = target.c_str();
  }

  static pugi::xml_node references(pugi::xml_node n) {
    auto r = n.child("References");
    return r ? r : n.append_child("References");
  }

  // owl:ObjectProperty → UAReferenceType under NonHierarchicalReferences (or its super-property).
  void reference_type(const OntologyProperty& p) {
    auto it = ids_.find(p.iri);
    if (it == ids_.end()) {
      return;
    }
    auto n = node("UAReferenceType", it->second, p.name, p.label, p.comment);
    if (p.symmetric) {
      n.append_attribute("Symmetric") = "true";
    }
    std::string super = ns0(p.part_of ? kHasComponentId : kNonHierarchicalReferences);
    for (TermId parent : p.parents) {
      if (auto pit = ids_.find(parent); pit != ids_.end()) {
        super = ns1(pit->second);
      }
    }
    ref(references(n), "HasSubtype", super, false);
    if (!p.symmetric) {
      const OntologyProperty* inv = p.inverse == kNoTerm ? nullptr : m_.find_property(p.inverse);
      n.append_child("InverseName").text() = (inv != nullptr ? inv->name : p.name + "Inverse").c_str();
    }
  }

  // How a link with property p is written from its subject: a reference type and direction.
  std::optional<RefType> link_type(const OntologyProperty& p) const {
    if (is_has_component(p)) {
      return RefType{"HasComponent", true};
    }
    if (auto it = ids_.find(p.iri); it != ids_.end()) {
      return RefType{ns1(it->second), true};
    }
    const OntologyProperty* inv = p.inverse == kNoTerm ? nullptr : m_.find_property(p.inverse);
    if (inv == nullptr) {
      return std::nullopt;
    }
    if (is_has_component(*inv)) {
      return RefType{"HasComponent", false};
    }
    if (auto it = ids_.find(inv->iri); it != ids_.end()) {
      return RefType{ns1(it->second), false};
    }
    return std::nullopt;
  }

  std::string data_type_of(const OntologyProperty& p) const {
    return std::string(ua_data_type(p.range == kNoTerm ? std::string_view{} : d_.term(p.range).text).name);
  }

  // A variable under parent: a data variable (HasComponent) for live values, else a property.
  pugi::xml_node variable(std::uint32_t parent, const OntologyProperty& p, const std::string& data_type,
                          bool declaration) {
    const std::uint32_t id = next_++;
    auto v = node("UAVariable", id, p.name, p.label, declaration ? p.comment : std::string());
    v.append_attribute("ParentNodeId") = ns1(parent).c_str();
    v.append_attribute("DataType") = data_type.c_str();
    if (p.live) {
      v.append_attribute("AccessLevel") = "3";  // CurrentRead | CurrentWrite: live values are written
    }
    auto refs = references(v);
    ref(refs, "HasTypeDefinition", ns0(p.live ? kBaseDataVariableType : kPropertyType));
    if (declaration) {
      ref(refs, "HasModellingRule", ns0(kModellingRuleOptional));
    }
    ref(refs, p.live ? "HasComponent" : "HasProperty", ns1(parent), false);
    return v;
  }

  // owl:Class → UAObjectType with HasSubtype from its first named superclass, and an optional
  // variable for every datatype property whose rdfs:domain it is.
  void object_type(const OntologyClass& c) {
    const std::uint32_t id = ids_.at(c.iri);
    auto n = node("UAObjectType", id, c.name, c.label, c.comment);
    std::string super = ns0(kBaseObjectType);
    if (!c.parents.empty()) {
      super = ns1(ids_.at(c.parents.front()));  // OPC UA types have one supertype
    }
    ref(references(n), "HasSubtype", super, false);
    for (const OntologyProperty& p : m_.properties) {
      if (!p.object && std::find(p.domains.begin(), p.domains.end(), c.iri) != p.domains.end()) {
        variable(id, p, data_type_of(p), true);
      }
    }
  }

  void folder() {
    const std::string name = m_.label.empty() ? std::string("Ontology") : m_.label;
    auto f = node("UAObject", folder_id_, name, name, "Individuals of " + m_.namespace_uri);
    auto refs = references(f);
    ref(refs, "Organizes", ns0(kObjectsFolder), false);
    ref(refs, "HasTypeDefinition", ns0(kFolderType));
  }

  // The most specific asserted class: one that is no ancestor of another asserted class.
  TermId type_of(const OntologyIndividual& i) const {
    std::vector<TermId> candidates;
    for (TermId t : i.types) {
      bool ancestor = false;
      for (TermId u : i.types) {
        ancestor = ancestor || (u != t && is_ancestor(t, u));
      }
      if (!ancestor) {
        candidates.push_back(t);
      }
    }
    return candidates.empty() ? kNoTerm : candidates.front();
  }

  bool is_ancestor(TermId a, TermId c) const {
    std::set<TermId> seen;
    std::vector<TermId> todo{c};
    while (!todo.empty()) {
      const TermId x = todo.back();
      todo.pop_back();
      if (!seen.insert(x).second) {
        continue;
      }
      if (const OntologyClass* k = m_.find_class(x)) {
        for (TermId p : k->parents) {
          if (p == a) {
            return true;
          }
          todo.push_back(p);
        }
      }
    }
    return false;
  }

  void object(const OntologyIndividual& i) {
    const std::uint32_t id = ids_.at(i.iri);
    auto n = node("UAObject", id, i.name, i.label, {});
    const TermId parent = component_parent(i.iri);
    if (parent != kNoTerm) {
      n.append_attribute("ParentNodeId") = ns1(ids_.at(parent)).c_str();
    }
    auto refs = references(n);
    const TermId type = type_of(i);
    ref(refs, "HasTypeDefinition", type == kNoTerm ? ns0(kBaseObjectType) : ns1(ids_.at(type)));
    if (parent == kNoTerm) {
      ref(refs, "Organizes", ns1(folder_id_), false);
    }
    for (const auto& [prop, target] : i.links) {
      const OntologyProperty* p = m_.find_property(prop);
      auto how = p == nullptr ? std::nullopt : link_type(*p);
      if (how && (how->forward || !p->part_of)) {
        ref(refs, how->target, ns1(ids_.at(target)), how->forward);
      }
    }
    std::set<TermId> done;
    for (const auto& [prop, value] : i.values) {
      const OntologyProperty* p = m_.find_property(prop);
      if (p == nullptr || !done.insert(prop).second) {
        continue;  // one variable per property (BrowseNames are unique among siblings)
      }
      const Term lit = d_.term(value);
      const UaDataType ua = ua_data_type(p->range == kNoTerm ? lit.datatype : d_.term(p->range).text);
      auto v = variable(id, *p, std::string(ua.name), false);
      ref(refs, p->live ? "HasComponent" : "HasProperty", v.attribute("NodeId").value());
      value_element(v, ua, value);
    }
  }

  // The individual this one is a component of (the subject of a hasComponent link to it).
  TermId component_parent(TermId child) {
    if (parents_.empty()) {
      for (const OntologyIndividual& i : m_.individuals) {
        for (const auto& [prop, target] : i.links) {
          const OntologyProperty* p = m_.find_property(prop);
          if (p != nullptr && is_has_component(*p)) {
            parents_.emplace(target, i.iri);
          } else if (p != nullptr && p->inverse != kNoTerm && m_.find_property(p->inverse) != nullptr &&
                     is_has_component(*m_.find_property(p->inverse))) {
            parents_.emplace(i.iri, target);
          }
        }
      }
      parents_.emplace(kNoTerm, kNoTerm);  // computed
    }
    auto it = parents_.find(child);
    return it == parents_.end() ? kNoTerm : it->second;
  }

  // <Value><Double xmlns="...Types.xsd">85.5</Double></Value> (OPC 10000-6 §5.3.1).
  void value_element(pugi::xml_node v, const UaDataType& ua, TermId literal) const {
    const LiteralValue* val = d_.value(literal);
    if (val == nullptr || ua.id == 24 || (val->cls == ValueClass::other)) {
      return;
    }
    std::string text(d_.term(literal).text);
    if (val->cls == ValueClass::boolean) {
      text = val->boolean ? "true" : "false";
    } else if (val->cls == ValueClass::decimal && ua.id <= 9) {
      if (!val->decimal.integral()) {
        return;
      }
      text = std::to_string(val->decimal.mantissa);
    } else if (val->cls == ValueClass::decimal) {
      text = decimal_string(val->decimal);
    }
    auto e = v.append_child("Value").append_child(std::string(ua.name).c_str());
    e.append_attribute("xmlns") = kUaTypes;
    e.text() = text.c_str();
  }

  const Dictionary& d_;
  const OntologyModel& m_;
  const NodesetOptions& opts_;
  pugi::xml_document doc_;
  pugi::xml_node root_;
  std::uint32_t next_ = 0;
  std::uint32_t folder_id_ = 0;
  std::unordered_map<TermId, std::uint32_t> ids_;
  std::unordered_map<TermId, TermId> parents_;
};

}  // namespace

Status write_nodeset(std::ostream& out, const Dictionary& dict, const OntologyModel& model,
                     const NodesetOptions& options) {
  return Writer(dict, model, options).write(out);
}

}  // namespace sf::knowledge
