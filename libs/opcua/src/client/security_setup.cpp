#include "sf/opcua/client/security_setup.hpp"

#include <memory>

#include "sf/core/text.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/security/provisioning.hpp"

namespace sf::opcua {

Status configure_client_security(const ClientSecuritySettings& settings, ClientConfig& config) {
  ClientSecuritySettings o = settings;
  if (o.pki.empty()) {
    o.pki = security::default_pki_dir();
  }
  const std::string wanted = lower(o.security);
  ClientSecurity& out = config.security;
  if (wanted == "none") {
    out.policy_uri = std::string(kSecurityPolicyNoneUri);
    out.mode = MessageSecurityMode::None;
  } else if (wanted == "auto") {
    out.policy_uri.clear();
    out.mode = MessageSecurityMode::None;
  } else {
    const auto colon = wanted.find(':');
    auto policy = security::policy_uri_from_name(wanted.substr(0, colon));
    auto mode = colon == std::string::npos ? Result<MessageSecurityMode>(MessageSecurityMode::SignAndEncrypt)
                                           : security::parse_security_mode(wanted.substr(colon + 1));
    if (!policy || !mode) {
      return !policy ? policy.error() : mode.error();
    }
    out.policy_uri = *policy;
    out.mode = *mode;
  }
  // A password over a None channel is still encrypted for the server's certificate, which the PKI
  // checks; our certificate goes into CreateSession so that every server names its own.
  if (wanted != "none" || (!o.user.empty() && o.user_certificate.empty())) {
    auto own = security::own_credentials(o.pki);
    if (!own) {
      return own.error();
    }
    config.application_uri = security::inspect_certificate(own->certificate.span())->application_uri;
    out.credentials = std::move(*own);
    auto validator = std::make_shared<security::CertificateValidator>(security::PkiStore(o.pki));
    out.validate_server_certificate = [validator](const ByteString& c) { return validator->validate(c); };
  }
  if (!o.user_certificate.empty()) {
    auto certificate = security::read_certificate_file(o.user_certificate);
    auto key = certificate ? security::read_private_key_file(o.user_key) : Result<Bytes>(certificate.error());
    if (!key) {
      return key.error();
    }
    config.user = UserIdentity::x509(SecurityCredentials{std::move(*certificate), std::move(*key)});
  } else if (!o.user.empty()) {
    config.user = UserIdentity::user(o.user, o.password);
  }
  return {};
}

}  // namespace sf::opcua
