// The security policies of OPC 10000-7 this stack implements over OpenSSL 3, as plug-ins of the
// secure channel (sf/opcua/transport/security_policy.hpp), and the session-level asymmetric
// operations that use the same algorithms (OPC 10000-4 §5.6.2, §5.6.3, §7.36, §7.40).
//
//   policy                  sym. encryption   sym. signature   asym. encryption    asym. signature
//   Basic256Sha256          AES-256-CBC       HMAC-SHA256      RSA-OAEP-SHA1       RSA-PKCS1-v1_5-SHA256
//   Aes128_Sha256_RsaOaep   AES-128-CBC       HMAC-SHA256      RSA-OAEP-SHA1       RSA-PKCS1-v1_5-SHA256
//   Aes256_Sha256_RsaPss    AES-256-CBC       HMAC-SHA256      RSA-OAEP-SHA256     RSA-PSS-SHA256
// All three: key derivation P_SHA256, derived signing key 32 bytes, nonces of 32 bytes, AES block
// 16 bytes, RSA keys of 2048 to 4096 bits (certificates outside get BadCertificatePolicyCheckFailed).
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/transport/security_policy.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua::security {

inline constexpr std::string_view kBasic256Sha256Uri =
    "http://opcfoundation.org/UA/SecurityPolicy#Basic256Sha256";
inline constexpr std::string_view kAes128Sha256RsaOaepUri =
    "http://opcfoundation.org/UA/SecurityPolicy#Aes128_Sha256_RsaOaep";
inline constexpr std::string_view kAes256Sha256RsaPssUri =
    "http://opcfoundation.org/UA/SecurityPolicy#Aes256_Sha256_RsaPss";

// The policies with certificates, strongest first.
std::vector<std::string> secure_policy_uris();
// A policy by URI (None too); nullptr when unknown.
std::shared_ptr<const SecurityPolicy> make_security_policy(std::string_view uri);
// None plus the given policies; BadSecurityPolicyRejected for an unknown URI.
Result<std::shared_ptr<const SecurityPolicyRegistry>> make_registry(const std::vector<std::string>& uris);
// None plus every policy of secure_policy_uris().
std::shared_ptr<const SecurityPolicyRegistry> full_registry();

// "Basic256Sha256", "basic256sha256", "none" or a full URI → the URI (BadSecurityPolicyRejected
// when unknown). policy_name is the part after '#'.
Result<std::string> policy_uri_from_name(std::string_view name);
std::string_view policy_name(std::string_view uri);
// For ordering endpoints (securityLevel): None 0, then Aes128_Sha256_RsaOaep, Basic256Sha256,
// Aes256_Sha256_RsaPss.
int policy_strength(std::string_view uri);

// The algorithm URIs of a policy's asymmetric signature / encryption ("" for None/unknown).
std::string_view signature_algorithm_uri(std::string_view policy_uri);
std::string_view encryption_algorithm_uri(std::string_view policy_uri);

// SignatureData (OPC 10000-4 §7.36) over `data` with a PKCS#8 private key.
Result<SignatureData> sign(std::string_view policy_uri, ByteSpan private_key, ByteSpan data);
// Checks a SignatureData against the (leaf of the) certificate: the algorithm must be the
// policy's. BadSecurityChecksFailed when anything does not match.
Status verify(std::string_view policy_uri, const ByteString& certificate, ByteSpan data,
              const SignatureData& signature);

// The legacy encrypted secret of user identity tokens (OPC 10000-4 §7.41.2.2, "legacy
// encrypted token secret format"): UInt32 length of secret + nonce, secret, server nonce,
// encrypted with the asymmetric encryption of the policy for the (leaf of the) certificate.
Result<ByteString> encrypt_secret(std::string_view policy_uri, const ByteString& certificate, ByteSpan secret,
                                  ByteSpan nonce);
// The secret back; BadIdentityTokenInvalid when it does not decrypt, has the wrong layout,
// carries another nonce or padding that is not zero (zero padding after the nonce is accepted).
Result<Bytes> decrypt_secret(std::string_view policy_uri, ByteSpan private_key, ByteSpan cipher,
                             ByteSpan nonce);

}  // namespace sf::opcua::security
