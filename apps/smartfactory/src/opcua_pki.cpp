// `smartfactory opcua pki init|list|trust|reject`: the PKI folder of OPC UA servers and clients
// (OPC 10000-12 §F.1 layout, see sf/opcua/security/pki.hpp).
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "opcua_security.hpp"
#include "sf/opcua/security/pki.hpp"

namespace sf::app {
namespace {

namespace sec = sf::opcua::security;
using nlohmann::json;
using Folder = sec::PkiStore::Folder;

struct PkiOptions {
  std::string pki = sec::default_pki_dir();
  bool json = false;
  // init
  std::string uri;
  std::string name;
  std::vector<std::string> dns;
  std::vector<std::string> ip;
  unsigned days = 5 * 365;
  unsigned key_bits = 2048;
  bool force = false;
  // trust / reject
  std::string certificate;
};

std::string date(std::chrono::system_clock::time_point t) {
  return fmt::format("{:%Y-%m-%d}", fmt::gmtime(std::chrono::system_clock::to_time_t(t)));
}

json entry_json(const sec::PkiStore::Entry& e) {
  return json{{"folder", std::string(sec::PkiStore::folder_name(e.folder))},
              {"file", e.file.string()},
              {"subject", e.info.subject},
              {"applicationUri", e.info.application_uri},
              {"thumbprint", e.info.thumbprint},
              {"notBefore", date(e.info.not_before)},
              {"notAfter", date(e.info.not_after)},
              {"ca", e.info.is_ca},
              {"selfSigned", e.info.self_signed}};
}

void print_entry(const sec::PkiStore::Entry& e) {
  std::printf("  %-8s %s  %s%s  %s .. %s\n    %s\n",
              std::string(sec::PkiStore::folder_name(e.folder)).c_str(), e.info.thumbprint.c_str(),
              e.info.subject.c_str(), e.info.is_ca ? " (CA)" : "", date(e.info.not_before).c_str(),
              date(e.info.not_after).c_str(),
              e.info.application_uri.empty() ? e.file.string().c_str()
                                             : (e.info.application_uri + "  " + e.file.string()).c_str());
}

int run_init(const PkiOptions& o) {
  sec::PkiStore store(o.pki);
  sec::CertificateRequest request = sec::own_certificate_request();
  if (!o.uri.empty()) {
    request.application_uri = o.uri;
  }
  if (!o.name.empty()) {
    request.common_name = o.name;
  }
  request.dns_names.insert(request.dns_names.end(), o.dns.begin(), o.dns.end());
  request.ip_addresses.insert(request.ip_addresses.end(), o.ip.begin(), o.ip.end());
  request.validity = std::chrono::hours(24) * o.days;
  request.key_bits = o.key_bits;
  auto own = o.force ? store.create_own(request) : store.ensure_own(request);
  if (!own) {
    std::cerr << "opcua pki init: " << own.error().message << "\n";
    return kExitFailure;
  }
  auto info = sec::inspect_certificate(own->certificate.span());
  std::printf("PKI %s\n  certificate %s\n  %s  %s\n  thumbprint %s, valid until %s\n", o.pki.c_str(),
              store.own_certificate().c_str(), info->subject.c_str(), info->application_uri.c_str(),
              info->thumbprint.c_str(), date(info->not_after).c_str());
  return kExitOk;
}

int run_list(const PkiOptions& o) {
  const sec::PkiStore store(o.pki);
  const auto entries = store.certificates();
  if (o.json) {
    json out = json::array();
    for (const auto& e : entries) {
      out.push_back(entry_json(e));
    }
    json crls = json::array();
    for (const auto& file : store.crls()) {
      crls.push_back(file.string());
    }
    std::cout << json{{"pki", o.pki}, {"certificates", out}, {"crls", crls}}.dump() << "\n";
    return kExitOk;
  }
  std::printf("PKI %s\n", o.pki.c_str());
  for (const auto& e : entries) {
    print_entry(e);
  }
  for (const auto& file : store.crls()) {
    std::printf("  crl      %s\n", file.c_str());
  }
  return kExitOk;
}

// trust: a file to add to trusted/, or the thumbprint of a certificate in rejected/.
int run_move(const PkiOptions& o, Folder from, Folder to, const char* command) {
  const sec::PkiStore store(o.pki);
  Result<std::filesystem::path> done = make_error(Errc::not_found, "");
  std::error_code ec;
  if (to == Folder::Trusted && std::filesystem::is_regular_file(o.certificate, ec)) {
    auto der = sec::read_certificate_file(o.certificate);
    done = der ? store.add(Folder::Trusted, *der) : Result<std::filesystem::path>(der.error());
  } else {
    done = store.move(o.certificate, from, to);
  }
  if (!done) {
    std::cerr << "opcua pki " << command << ": " << done.error().message << "\n";
    return kExitFailure;
  }
  std::printf("%s\n", done->c_str());
  return kExitOk;
}

}  // namespace

void register_opcua_pki(CLI::App& group, CommandResult& result) {
  auto* pki =
      group.add_subcommand("pki", "The PKI folder: own certificate, trusted, issuers, rejected, CRLs");
  pki->require_subcommand(1);
  pki->footer(
      "A peer whose certificate is not trusted is refused and its certificate copied to rejected/certs;\n"
      "trust it with `pki trust THUMBPRINT` (servers and clients see it at once, without a restart).\n"
      "CA certificates go to issuers/certs (they only complete chains) or trusted/certs (they vouch for\n"
      "what they issue); CRLs to trusted/crl or issuers/crl.");
  auto o = std::make_shared<PkiOptions>();
  const auto folder_option = [&o](CLI::App* cmd) {
    cmd->add_option("--pki", o->pki, "PKI folder")->capture_default_str();
  };

  auto* init = pki->add_subcommand("init", "Create the folders and our self-signed certificate (once)");
  folder_option(init);
  init->add_option("--uri", o->uri, "ApplicationUri (default urn:<host>:smartfactory)");
  init->add_option("--name", o->name, "Common name (default smartfactory@<host>)");
  init->add_option("--dns", o->dns, "More DNS names (host name and localhost are always in)");
  init->add_option("--ip", o->ip, "More IP addresses (127.0.0.1 and ::1 are always in)");
  init->add_option("--days", o->days, "Validity in days")->capture_default_str();
  init->add_option("--key-bits", o->key_bits, "RSA key size")
      ->check(CLI::Range(2048U, 4096U))
      ->capture_default_str();
  init->add_flag("--force", o->force, "Replace an existing own certificate");
  init->callback([o, &result] { result.exit_code = run_init(*o); });

  auto* list = pki->add_subcommand("list", "List the certificates and CRLs of every folder");
  folder_option(list);
  list->add_flag("--json", o->json, "Print JSON instead of text");
  list->callback([o, &result] { result.exit_code = run_list(*o); });

  auto* trust =
      pki->add_subcommand("trust", "Trust a certificate: a file, or a thumbprint (prefix) from rejected/");
  folder_option(trust);
  trust
      ->add_option("certificate", o->certificate, "Certificate file, or thumbprint of a rejected certificate")
      ->required();
  trust->callback(
      [o, &result] { result.exit_code = run_move(*o, Folder::Rejected, Folder::Trusted, "trust"); });

  auto* reject =
      pki->add_subcommand("reject", "Stop trusting a certificate: move it from trusted/ to rejected/");
  folder_option(reject);
  reject->add_option("certificate", o->certificate, "Thumbprint (prefix) of a trusted certificate")
      ->required();
  reject->callback(
      [o, &result] { result.exit_code = run_move(*o, Folder::Trusted, Folder::Rejected, "reject"); });
}

}  // namespace sf::app
