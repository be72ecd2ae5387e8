// What an installation's servers and clients share to be secured without setup (OPC 10000-2
// §4, OPC 10000-4 §6.1): a PKI folder whose own application instance certificate is made (and
// trusted) on first use, and the names of security modes and policies as a user writes them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/transport/security_policy.hpp"

namespace sf::opcua::security {

// $XDG_STATE_HOME/smartfactory/opcua/pki (~/.local/state/... without it, /tmp/smartfactory-<uid>
// without a home).
std::string default_pki_dir();

// urn:<host name>:smartfactory and a self-signed certificate for it: CN smartfactory@<host>,
// DNS <host> and localhost, IP 127.0.0.1 and ::1, plus `extra_host` (a name or an address).
CertificateRequest own_certificate_request(const std::string& extra_host = "");

// The own certificate of the PKI folder `pki`, made on first use (own_certificate_request).
Result<SecurityCredentials> own_credentials(const std::string& pki, const std::string& extra_host = "");

// "none", "sign", "encrypt" (or "signandencrypt"), in any case.
Result<MessageSecurityMode> parse_security_mode(std::string_view text);
// A comma list of modes, each once, at least one.
Result<std::vector<MessageSecurityMode>> parse_security_modes(std::string_view text);
// A comma list of policy names or URIs (Basic256Sha256, ...), not None: their URIs.
Result<std::vector<std::string>> parse_security_policies(std::string_view text);

}  // namespace sf::opcua::security
