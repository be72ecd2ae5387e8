// `smartfactory opcua nodeset`: checks NodeSet2 files the way the server loads them and exports
// information models (the demo model, imported files) as NodeSet2 XML.
#include "opcua_nodeset.hpp"

#include <fstream>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "sf/examples/opcua_demo.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/server/ns0.hpp"

namespace sf::app {
namespace {

namespace ua = sf::opcua;

void print_report(const std::string& file, const ua::server::NodeSetImportReport& report) {
  std::cerr << fmt::format(
      "{}: {} nodes added, {} existing namespace-0 nodes skipped, {} references, {} warnings\n", file,
      report.nodes_added, report.nodes_skipped, report.references_added, report.warnings.size());
  for (const std::string& warning : report.warnings) {
    std::cerr << "  warning: " << warning << "\n";
  }
}

Status import_all(ua::server::AddressSpace& space, const std::vector<std::string>& files) {
  auto reports = ua::server::import_nodeset_files(space, files);
  if (!reports) {
    return reports.error();
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    print_report(files[i], reports->at(i));
  }
  return {};
}

struct NodeSetOptions {
  std::vector<std::string> files;
  bool demo_model = false;
  std::string export_path;
  std::vector<std::string> namespaces;
};

int run_nodeset(const NodeSetOptions& o) {
  ua::server::AddressSpace space;
  if (auto st = ua::server::build_namespace0(space); !st) {
    std::cerr << "opcua nodeset: namespace 0: " << st.error().message << "\n";
    return kExitFailure;
  }
  if (o.demo_model) {
    if (auto st = examples::add_demo_nodes(space); !st) {
      std::cerr << "opcua nodeset: demo model: " << st.error().message << "\n";
      return kExitFailure;
    }
  }
  if (auto st = import_all(space, o.files); !st) {
    std::cerr << "opcua nodeset: " << st.error().message << "\n";
    return kExitFailure;
  }
  if (o.export_path.empty()) {
    return kExitOk;
  }
  auto xml = ua::server::export_nodeset(space, {.namespace_uris = o.namespaces});
  if (!xml) {
    std::cerr << "opcua nodeset: export: " << xml.error().message << "\n";
    return kExitFailure;
  }
  if (o.export_path == "-") {
    std::cout << *xml;
    return kExitOk;
  }
  std::ofstream out(o.export_path, std::ios::binary);
  out << *xml;
  if (!out.flush()) {
    std::cerr << "opcua nodeset: cannot write " << o.export_path << "\n";
    return kExitFailure;
  }
  std::cerr << fmt::format("opcua nodeset: wrote {} ({} bytes)\n", o.export_path, xml->size());
  return kExitOk;
}

}  // namespace

Status load_nodesets(ua::server::Server& server, const std::vector<std::string>& files) {
  Status result;
  server.with_address_space([&](ua::server::AddressSpace& space) { result = import_all(space, files); });
  return result;
}

void register_opcua_nodeset(CLI::App& group, CommandResult& result) {
  auto o = std::make_shared<NodeSetOptions>();
  auto* cmd = group.add_subcommand(
      "nodeset",
      "Check NodeSet2 XML files as the server would load them, and export information models as NodeSet2");
  cmd->add_option("files", o->files, "NodeSet2 files to import, in order (later files may use earlier ones)");
  cmd->add_flag("--demo-model", o->demo_model, "Add the demo model (urn:smartfactory:demo) first");
  cmd->add_option("-o,--export", o->export_path, "Write the namespaces as one NodeSet2 file ('-' = stdout)");
  cmd->add_option("--namespace", o->namespaces,
                  "Namespace URI to export (repeatable; default: every namespace but 0)");
  cmd->footer(
      "Examples:\n"
      "  smartfactory opcua nodeset --demo-model -o demo.xml\n"
      "  smartfactory opcua nodeset model.xml                 # import check, file:line:column errors\n"
      "  smartfactory opcua server --nodeset model.xml        # serve it");
  cmd->callback([o, &result] { result.exit_code = run_nodeset(*o); });
}

}  // namespace sf::app
