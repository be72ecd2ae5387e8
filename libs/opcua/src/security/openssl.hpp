// Thin RAII and Result wrappers over the OpenSSL 3 EVP/X509 calls the security policies,
// certificates and the PKI use. Internal to sf_opcua_security; nothing here knows OPC UA.
#pragma once

#include <openssl/evp.h>
#include <openssl/x509.h>

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/status_code.hpp"

namespace sf::opcua::security::ossl {

struct Free {
  void operator()(EVP_PKEY* p) const { EVP_PKEY_free(p); }
  void operator()(EVP_PKEY_CTX* p) const { EVP_PKEY_CTX_free(p); }
  void operator()(EVP_MD_CTX* p) const { EVP_MD_CTX_free(p); }
  void operator()(EVP_CIPHER_CTX* p) const { EVP_CIPHER_CTX_free(p); }
  void operator()(EVP_MAC_CTX* p) const { EVP_MAC_CTX_free(p); }
  void operator()(X509* p) const { X509_free(p); }
  void operator()(X509_CRL* p) const { X509_CRL_free(p); }
  void operator()(X509_STORE* p) const { X509_STORE_free(p); }
  void operator()(X509_STORE_CTX* p) const { X509_STORE_CTX_free(p); }
  void operator()(BIO* p) const { BIO_free_all(p); }
  void operator()(stack_st_X509* p) const { sk_X509_free(p); }
  void operator()(ASN1_STRING* p) const { ASN1_STRING_free(p); }
};
template <typename T>
using Ptr = std::unique_ptr<T, Free>;
using Key = std::shared_ptr<EVP_PKEY>;  // shared by the crypto objects of one channel
using Cert = Ptr<X509>;
using Crl = Ptr<X509_CRL>;

// The OpenSSL error queue as text (and emptied), for error messages.
std::string last_error();
// status_error(code, "<what>: <OpenSSL's reason>").
Error failure(StatusCode code, std::string_view what);

Key share(EVP_PKEY* key);
// A private key from DER (PKCS#8 or PKCS#1) or PEM bytes.
Result<Key> load_private_key(ByteSpan bytes);
// The private key as PKCS#8 DER / PEM ("-----BEGIN PRIVATE KEY-----").
Result<Bytes> private_key_der(EVP_PKEY* key);
Result<std::string> private_key_pem(EVP_PKEY* key);
// The first certificate of `der` (a chain is DER certificates back to back, OPC 10000-6
// §6.7.2.3); `used` gets the bytes it took.
Result<Cert> load_certificate(ByteSpan der, std::size_t* used = nullptr);
// Every certificate of a DER chain, leaf first.
Result<std::vector<Cert>> load_chain(ByteSpan der);
// A certificate from DER or PEM bytes (files of a PKI folder may be either).
Result<Cert> load_certificate_file_bytes(ByteSpan bytes);
Result<Crl> load_crl_bytes(ByteSpan bytes);
Bytes der_of(X509* cert);
Bytes der_of(X509_CRL* crl);
std::string pem_of(X509* cert);
// The public key of a certificate (DER, possibly a chain: the leaf's).
Result<Key> public_key_of(ByteSpan certificate_der);
// RSA modulus size in bytes (0 for other key types).
std::size_t rsa_bytes(EVP_PKEY* key);

// OPC 10000-7: the asymmetric algorithms of the current policies.
enum class Signature { Pkcs1v15Sha256, PssSha256 };
enum class Encryption { OaepSha1, OaepSha256 };

Result<Bytes> sign(EVP_PKEY* private_key, Signature algorithm, ByteSpan data);
// BadSecurityChecksFailed when it does not verify.
Status verify(EVP_PKEY* public_key, Signature algorithm, ByteSpan data, ByteSpan signature);
// Plaintext bytes one RSA-OAEP block carries: k - 2·hLen - 2 (RFC 8017 §7.1.1).
std::size_t oaep_plain_block(std::size_t key_bytes, Encryption algorithm);
// Encrypts block by block: plain.size() must be a multiple of oaep_plain_block (the last block
// may be shorter when `whole_blocks` is false, as for secrets of user tokens).
Result<Bytes> encrypt(EVP_PKEY* public_key, Encryption algorithm, ByteSpan plain, bool whole_blocks = true);
// Decrypts block by block (cipher.size() a multiple of the key size).
Result<Bytes> decrypt(EVP_PKEY* private_key, Encryption algorithm, ByteSpan cipher);

Bytes sha1(ByteSpan data);
Bytes hmac_sha256(ByteSpan key, ByteSpan data);

// HMAC-SHA256 with a fixed key, keyed once (each message copies the keyed context).
class HmacSha256 {
 public:
  explicit HmacSha256(ByteSpan key);
  [[nodiscard]] Bytes mac(ByteSpan data) const;

 private:
  std::shared_ptr<EVP_MAC_CTX> keyed_;
};
// AES-CBC without padding over whole 16-byte blocks; key of 16 or 32 bytes.
Result<Bytes> aes_cbc(bool encrypt, ByteSpan key, ByteSpan iv, ByteSpan data);
// From OpenSSL's CSPRNG.
Result<Bytes> random_bytes(std::size_t size);

Result<Bytes> base64_decode(std::string_view text);
std::string base64_encode(ByteSpan bytes);
std::string hex(ByteSpan bytes);

}  // namespace sf::opcua::security::ossl
