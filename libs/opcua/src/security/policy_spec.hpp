// The table of OPC 10000-7 security policies this stack implements (internal).
#pragma once

#include <cstddef>
#include <string_view>

#include "openssl.hpp"

namespace sf::opcua::security {

struct PolicySpec {
  std::string_view uri;
  std::size_t symmetric_key_length;  // AES key: 16 (AES-128-CBC) or 32 (AES-256-CBC)
  ossl::Signature signature;         // asymmetric signature
  ossl::Encryption encryption;       // asymmetric encryption
  std::string_view signature_uri;    // SignatureData.algorithm (OPC 10000-4 §7.36)
  std::string_view encryption_uri;   // UserNameIdentityToken.encryptionAlgorithm (§7.40.4)
  std::size_t min_key_bits;
  std::size_t max_key_bits;
  int strength;  // for securityLevel: higher is stronger
};

// nullptr for None and unknown URIs.
const PolicySpec* find_policy_spec(std::string_view uri);

}  // namespace sf::opcua::security
