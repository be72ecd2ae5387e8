// NodeSet2 XML (OPC 10000-6 Annex F, UANodeSet schema): import an information model into an
// address space and export namespaces of one.
//
//   auto report = import_nodeset_file(space, "model.xml");   // all or nothing
//   auto xml = export_nodeset(space, {.namespace_uris = {"urn:smartfactory:demo"}});
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/server/address_space.hpp"

namespace sf::opcua::server {

struct NodeSetImportOptions {
  // Name used in error messages ("model.xml:12:5: ..."); the file name for import_nodeset_file.
  std::string source_name = "<nodeset>";
  // Nodes of namespace 0 that the address space already has are skipped (a file may repeat
  // standard nodes); other existing NodeIds are an error (BadNodeIdExists).
  bool skip_existing_namespace0 = true;
};

struct NodeSetImportReport {
  std::size_t nodes_added = 0;
  std::size_t nodes_skipped = 0;  // existing namespace-0 nodes
  std::size_t references_added = 0;
  // The file's NamespaceUris in file order, as registered in the address space.
  std::vector<std::string> namespace_uris;
  // References that could not be added (their other end or type is neither in the file nor in
  // the address space), one line each with its location.
  std::vector<std::string> warnings;
};

// Parses the whole document first and applies it only when it is valid: on error (malformed
// XML, an unknown alias, a bad NodeId, a value that does not decode, a duplicate or existing
// NodeId) the address space is unchanged except for namespaces the file registers, and the
// error names source_name:line:column.
Result<NodeSetImportReport> import_nodeset(AddressSpace& space, std::string_view xml,
                                           const NodeSetImportOptions& options = {});
Result<NodeSetImportReport> import_nodeset_file(AddressSpace& space, const std::filesystem::path& path,
                                                NodeSetImportOptions options = {});
// Imports the files in order (a later file may use an earlier one's nodes); stops at the first
// that fails (its error names it), the files before it stay imported. One report per file.
Result<std::vector<NodeSetImportReport>> import_nodeset_files(AddressSpace& space,
                                                              const std::vector<std::string>& files);

struct NodeSetExportOptions {
  // The namespaces whose nodes are written; empty = every namespace but 0.
  std::vector<std::string> namespace_uris;
  // <Models><Model ModelUri=...> entries, one per exported namespace (OPC 10000-6 §F.2).
  std::string model_version = "1.0.0";
  // LastModified of the file (OPC 10000-6 §F.1): this clock's time.
  const Clock* clock = &SteadyClock::instance();
};

// The nodes of the chosen namespaces with all their references, values (OPC 10000-6 §5.3 XML
// encoding) and aliases for the namespace-0 reference types and data types they use. Method
// and value callbacks are code, not model: values read through a callback are written as their
// current value.
Result<std::string> export_nodeset(const AddressSpace& space, const NodeSetExportOptions& options = {});

}  // namespace sf::opcua::server
