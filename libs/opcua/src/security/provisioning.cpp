#include "sf/opcua/security/provisioning.hpp"

#include <arpa/inet.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

#include "sf/core/text.hpp"
#include "sf/net/tcp.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/policies.hpp"

namespace sf::opcua::security {
namespace {

namespace fs = std::filesystem;

bool is_ip(const std::string& text) {
  std::array<unsigned char, 16> buffer{};
  return inet_pton(AF_INET, text.c_str(), buffer.data()) == 1 ||
         inet_pton(AF_INET6, text.c_str(), buffer.data()) == 1;
}

// The non-empty items of a comma-separated list, without surrounding spaces, in lower case.
std::vector<std::string> split_list(std::string_view text) {
  std::vector<std::string> out;
  for (const auto item : split(text, ',')) {
    if (!trim(item).empty()) {
      out.push_back(lower(trim(item)));
    }
  }
  return out;
}

}  // namespace

std::string default_pki_dir() {
  const char* state = std::getenv("XDG_STATE_HOME");  // NOLINT(concurrency-mt-unsafe): nobody sets it
  if (state != nullptr && *state != '\0') {
    return (fs::path(state) / "smartfactory" / "opcua" / "pki").string();
  }
  const char* home = std::getenv("HOME");  // NOLINT(concurrency-mt-unsafe): nobody sets it
  if (home != nullptr && *home != '\0') {
    return (fs::path(home) / ".local" / "state" / "smartfactory" / "opcua" / "pki").string();
  }
  return fmt::format("/tmp/smartfactory-{}/opcua/pki", ::getuid());
}

CertificateRequest own_certificate_request(const std::string& extra_host) {
  const std::string host = net::host_name();
  CertificateRequest request;
  request.application_uri = fmt::format("urn:{}:smartfactory", host);
  request.common_name = fmt::format("smartfactory@{}", host);
  request.dns_names = {host};
  if (host != "localhost") {
    request.dns_names.emplace_back("localhost");
  }
  request.ip_addresses = {"127.0.0.1", "::1"};
  if (!extra_host.empty() && extra_host != host && extra_host != "localhost") {
    auto& list = is_ip(extra_host) ? request.ip_addresses : request.dns_names;
    if (std::find(list.begin(), list.end(), extra_host) == list.end()) {
      list.push_back(extra_host);
    }
  }
  return request;
}

Result<SecurityCredentials> own_credentials(const std::string& pki, const std::string& extra_host) {
  PkiStore store(pki);
  auto own = store.ensure_own(own_certificate_request(extra_host));
  if (!own) {
    return own.error().with_context("PKI " + pki);
  }
  return own;
}

Result<MessageSecurityMode> parse_security_mode(std::string_view text) {
  const std::string mode = lower(text);
  if (mode == "none") {
    return MessageSecurityMode::None;
  }
  if (mode == "sign") {
    return MessageSecurityMode::Sign;
  }
  if (mode == "encrypt" || mode == "signandencrypt") {
    return MessageSecurityMode::SignAndEncrypt;
  }
  return make_error(Errc::invalid_argument,
                    fmt::format("unknown security mode '{}' (none, sign, encrypt / SignAndEncrypt)", text));
}

Result<std::vector<MessageSecurityMode>> parse_security_modes(std::string_view text) {
  std::vector<MessageSecurityMode> modes;
  for (const auto& item : split_list(text)) {
    auto mode = parse_security_mode(item);
    if (!mode) {
      return mode.error();
    }
    if (std::find(modes.begin(), modes.end(), *mode) == modes.end()) {
      modes.push_back(*mode);
    }
  }
  if (modes.empty()) {
    return make_error(Errc::invalid_argument, "security modes: at least one of none, sign, encrypt");
  }
  return modes;
}

Result<std::vector<std::string>> parse_security_policies(std::string_view text) {
  std::vector<std::string> uris;
  for (const auto& item : split_list(text)) {
    auto uri = policy_uri_from_name(item);
    if (!uri || *uri == kSecurityPolicyNoneUri) {
      return make_error(Errc::invalid_argument, fmt::format("unknown security policy '{}'", item));
    }
    uris.push_back(*uri);
  }
  return uris;
}

}  // namespace sf::opcua::security
