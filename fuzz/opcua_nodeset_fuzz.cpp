// Fuzzes NodeSet2 import (OPC 10000-6 Annex F) with arbitrary documents: import_nodeset must
// accept or refuse without crashing; a refused document leaves the address space as it was
// (same node count), and an accepted one exports and imports again into a fresh space.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/server/ns0.hpp"

namespace {

using namespace sf::opcua::server;

void check(bool ok) {
  if (!ok) {
    __builtin_trap();
  }
}

AddressSpace namespace0() {
  AddressSpace space;
  check(build_namespace0(space).ok());
  return space;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view xml(reinterpret_cast<const char*>(data), size);
  AddressSpace space = namespace0();
  const std::size_t before = space.size();
  auto report = import_nodeset(space, xml);
  if (!report) {
    check(space.size() == before);
    return 0;
  }
  auto exported = export_nodeset(space, {.namespace_uris = report->namespace_uris});
  if (exported && !report->namespace_uris.empty()) {
    AddressSpace again = namespace0();
    check(import_nodeset(again, *exported).ok());
  }
  return 0;
}
