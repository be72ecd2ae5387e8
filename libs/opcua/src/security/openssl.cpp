#include "openssl.hpp"

#include <openssl/core_names.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/rand.h>
#include <openssl/rsa.h>

#include <algorithm>
#include <climits>

#include <fmt/format.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security::ossl {
namespace {

const unsigned char* data_of(ByteSpan bytes) {
  return bytes.data();
}

bool looks_like_pem(ByteSpan bytes) {
  return bytes.size() > 5 && bytes[0] == '-' && bytes[1] == '-' && bytes[2] == '-';
}

Ptr<BIO> memory_bio(ByteSpan bytes) {
  return Ptr<BIO>(
      BIO_new_mem_buf(bytes.data(), static_cast<int>(std::min<std::size_t>(bytes.size(), INT_MAX))));
}

std::string bio_text(BIO* bio) {
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio, &data);
  return size > 0 ? std::string(data, static_cast<std::size_t>(size)) : std::string();
}

const EVP_MD* oaep_digest(Encryption algorithm) {
  return algorithm == Encryption::OaepSha256 ? EVP_sha256() : EVP_sha1();
}

// Padding parameters of a signature context (RFC 8017 §8.1 PSS: MGF1 with SHA-256 and a salt as
// long as the digest, as OPC 10000-7 Aes256_Sha256_RsaPss and node-opcua use).
bool set_signature_padding(EVP_PKEY_CTX* pctx, Signature algorithm) {
  if (algorithm == Signature::Pkcs1v15Sha256) {
    return EVP_PKEY_CTX_set_rsa_padding(pctx, RSA_PKCS1_PADDING) > 0;
  }
  return EVP_PKEY_CTX_set_rsa_padding(pctx, RSA_PKCS1_PSS_PADDING) > 0 &&
         EVP_PKEY_CTX_set_rsa_pss_saltlen(pctx, RSA_PSS_SALTLEN_DIGEST) > 0 &&
         EVP_PKEY_CTX_set_rsa_mgf1_md(pctx, EVP_sha256()) > 0;
}

bool set_oaep(EVP_PKEY_CTX* ctx, Encryption algorithm) {
  return EVP_PKEY_CTX_set_rsa_padding(ctx, RSA_PKCS1_OAEP_PADDING) > 0 &&
         EVP_PKEY_CTX_set_rsa_oaep_md(ctx, oaep_digest(algorithm)) > 0 &&
         EVP_PKEY_CTX_set_rsa_mgf1_md(ctx, oaep_digest(algorithm)) > 0;
}

EVP_MAC* hmac_algorithm() {
  static EVP_MAC* const mac = EVP_MAC_fetch(nullptr, "HMAC", nullptr);
  return mac;
}

const EVP_CIPHER* aes_cipher(std::size_t key_size) {
  static const EVP_CIPHER* const aes128 = EVP_CIPHER_fetch(nullptr, "AES-128-CBC", nullptr);
  static const EVP_CIPHER* const aes256 = EVP_CIPHER_fetch(nullptr, "AES-256-CBC", nullptr);
  return key_size == 16 ? aes128 : key_size == 32 ? aes256 : nullptr;
}

}  // namespace

std::string last_error() {
  std::string out;
  while (const unsigned long code = ERR_get_error()) {
    char buffer[256];
    ERR_error_string_n(code, buffer, sizeof buffer);
    if (!out.empty()) {
      out += "; ";
    }
    out += buffer;
  }
  return out.empty() ? std::string("unknown OpenSSL error") : out;
}

Error failure(StatusCode code, std::string_view what) {
  return status_error(code, fmt::format("{}: {}", what, last_error()));
}

Key share(EVP_PKEY* key) {
  return Key(key, EVP_PKEY_free);
}

Result<Key> load_private_key(ByteSpan bytes) {
  EVP_PKEY* key = nullptr;
  if (looks_like_pem(bytes)) {
    auto bio = memory_bio(bytes);
    key = PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr);
  } else {
    const unsigned char* p = data_of(bytes);
    key = d2i_AutoPrivateKey(nullptr, &p, static_cast<long>(bytes.size()));
  }
  if (key == nullptr) {
    return failure(status::BadSecurityChecksFailed, "cannot read the private key");
  }
  return share(key);
}

Result<Bytes> private_key_der(EVP_PKEY* key) {
  Ptr<BIO> bio(BIO_new(BIO_s_mem()));
  if (i2d_PKCS8PrivateKey_bio(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1) {
    return failure(status::BadInternalError, "cannot encode the private key");
  }
  const std::string text = bio_text(bio.get());
  return Bytes(text.begin(), text.end());
}

Result<std::string> private_key_pem(EVP_PKEY* key) {
  Ptr<BIO> bio(BIO_new(BIO_s_mem()));
  if (PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1) {
    return failure(status::BadInternalError, "cannot encode the private key");
  }
  return bio_text(bio.get());
}

Result<Cert> load_certificate(ByteSpan der, std::size_t* used) {
  const unsigned char* p = data_of(der);
  X509* cert = d2i_X509(nullptr, &p, static_cast<long>(std::min<std::size_t>(der.size(), LONG_MAX)));
  if (cert == nullptr) {
    return failure(status::BadCertificateInvalid, "not a DER X.509 certificate");
  }
  if (used != nullptr) {
    *used = static_cast<std::size_t>(p - data_of(der));
  }
  return Cert(cert);
}

Result<std::vector<Cert>> load_chain(ByteSpan der) {
  std::vector<Cert> chain;
  while (!der.empty()) {
    std::size_t used = 0;
    auto cert = load_certificate(der, &used);
    if (!cert) {
      return cert.error();
    }
    chain.push_back(std::move(*cert));
    der = der.subspan(used);
  }
  if (chain.empty()) {
    return status_error(status::BadCertificateInvalid, "empty certificate");
  }
  return chain;
}

Result<Cert> load_certificate_file_bytes(ByteSpan bytes) {
  if (!looks_like_pem(bytes)) {
    return load_certificate(bytes);
  }
  auto bio = memory_bio(bytes);
  X509* cert = PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr);
  if (cert == nullptr) {
    return failure(status::BadCertificateInvalid, "not a PEM X.509 certificate");
  }
  return Cert(cert);
}

Result<Crl> load_crl_bytes(ByteSpan bytes) {
  X509_CRL* crl = nullptr;
  if (looks_like_pem(bytes)) {
    auto bio = memory_bio(bytes);
    crl = PEM_read_bio_X509_CRL(bio.get(), nullptr, nullptr, nullptr);
  } else {
    const unsigned char* p = data_of(bytes);
    crl = d2i_X509_CRL(nullptr, &p, static_cast<long>(bytes.size()));
  }
  if (crl == nullptr) {
    return failure(status::BadCertificateInvalid, "not a certificate revocation list");
  }
  return Crl(crl);
}

Bytes der_of(X509* cert) {
  const int size = i2d_X509(cert, nullptr);
  if (size <= 0) {
    return {};
  }
  Bytes out(static_cast<std::size_t>(size));
  unsigned char* p = out.data();
  i2d_X509(cert, &p);
  return out;
}

Bytes der_of(X509_CRL* crl) {
  const int size = i2d_X509_CRL(crl, nullptr);
  if (size <= 0) {
    return {};
  }
  Bytes out(static_cast<std::size_t>(size));
  unsigned char* p = out.data();
  i2d_X509_CRL(crl, &p);
  return out;
}

std::string pem_of(X509* cert) {
  Ptr<BIO> bio(BIO_new(BIO_s_mem()));
  PEM_write_bio_X509(bio.get(), cert);
  return bio_text(bio.get());
}

Result<Key> public_key_of(ByteSpan certificate_der) {
  auto cert = load_certificate(certificate_der);
  if (!cert) {
    return cert.error();
  }
  EVP_PKEY* key = X509_get_pubkey(cert->get());
  if (key == nullptr) {
    return failure(status::BadCertificateInvalid, "certificate without a usable public key");
  }
  return share(key);
}

std::size_t rsa_bytes(EVP_PKEY* key) {
  if (key == nullptr || EVP_PKEY_get_base_id(key) != EVP_PKEY_RSA) {
    return 0;
  }
  return static_cast<std::size_t>(EVP_PKEY_get_size(key));
}

Result<Bytes> sign(EVP_PKEY* private_key, Signature algorithm, ByteSpan data) {
  Ptr<EVP_MD_CTX> ctx(EVP_MD_CTX_new());
  EVP_PKEY_CTX* pctx = nullptr;  // owned by ctx
  if (EVP_DigestSignInit(ctx.get(), &pctx, EVP_sha256(), nullptr, private_key) != 1 ||
      !set_signature_padding(pctx, algorithm)) {
    return failure(status::BadInternalError, "cannot set up RSA signing");
  }
  std::size_t size = 0;
  if (EVP_DigestSign(ctx.get(), nullptr, &size, data.data(), data.size()) != 1) {
    return failure(status::BadInternalError, "RSA signing failed");
  }
  Bytes signature(size);
  if (EVP_DigestSign(ctx.get(), signature.data(), &size, data.data(), data.size()) != 1) {
    return failure(status::BadInternalError, "RSA signing failed");
  }
  signature.resize(size);
  return signature;
}

Status verify(EVP_PKEY* public_key, Signature algorithm, ByteSpan data, ByteSpan signature) {
  Ptr<EVP_MD_CTX> ctx(EVP_MD_CTX_new());
  EVP_PKEY_CTX* pctx = nullptr;
  if (EVP_DigestVerifyInit(ctx.get(), &pctx, EVP_sha256(), nullptr, public_key) != 1 ||
      !set_signature_padding(pctx, algorithm)) {
    return failure(status::BadInternalError, "cannot set up RSA verification");
  }
  if (EVP_DigestVerify(ctx.get(), signature.data(), signature.size(), data.data(), data.size()) != 1) {
    ERR_clear_error();
    return status_error(status::BadSecurityChecksFailed, "the RSA signature does not verify");
  }
  return {};
}

std::size_t oaep_plain_block(std::size_t key_bytes, Encryption algorithm) {
  const std::size_t overhead = algorithm == Encryption::OaepSha256 ? 66 : 42;
  return key_bytes > overhead ? key_bytes - overhead : 0;
}

Result<Bytes> encrypt(EVP_PKEY* public_key, Encryption algorithm, ByteSpan plain, bool whole_blocks) {
  const std::size_t key_bytes = rsa_bytes(public_key);
  const std::size_t block = oaep_plain_block(key_bytes, algorithm);
  if (block == 0 || (whole_blocks && plain.size() % block != 0)) {
    return status_error(status::BadInternalError, "RSA-OAEP input is not a whole number of blocks");
  }
  Ptr<EVP_PKEY_CTX> ctx(EVP_PKEY_CTX_new(public_key, nullptr));
  if (!ctx || EVP_PKEY_encrypt_init(ctx.get()) != 1 || !set_oaep(ctx.get(), algorithm)) {
    return failure(status::BadInternalError, "cannot set up RSA-OAEP encryption");
  }
  Bytes out;
  out.reserve((plain.size() + block - 1) / block * key_bytes);
  for (std::size_t offset = 0; offset < plain.size(); offset += block) {
    const std::size_t n = std::min(block, plain.size() - offset);
    std::size_t size = key_bytes;
    const std::size_t at = out.size();
    out.resize(at + key_bytes);
    if (EVP_PKEY_encrypt(ctx.get(), out.data() + at, &size, plain.data() + offset, n) != 1 ||
        size != key_bytes) {
      return failure(status::BadInternalError, "RSA-OAEP encryption failed");
    }
  }
  return out;
}

Result<Bytes> decrypt(EVP_PKEY* private_key, Encryption algorithm, ByteSpan cipher) {
  const std::size_t key_bytes = rsa_bytes(private_key);
  if (key_bytes == 0 || cipher.size() % key_bytes != 0) {
    return status_error(status::BadSecurityChecksFailed, "RSA ciphertext is not a whole number of blocks");
  }
  Ptr<EVP_PKEY_CTX> ctx(EVP_PKEY_CTX_new(private_key, nullptr));
  if (!ctx || EVP_PKEY_decrypt_init(ctx.get()) != 1 || !set_oaep(ctx.get(), algorithm)) {
    return failure(status::BadInternalError, "cannot set up RSA-OAEP decryption");
  }
  Bytes out;
  out.reserve(cipher.size());
  for (std::size_t offset = 0; offset < cipher.size(); offset += key_bytes) {
    std::size_t size = key_bytes;
    const std::size_t at = out.size();
    out.resize(at + key_bytes);
    if (EVP_PKEY_decrypt(ctx.get(), out.data() + at, &size, cipher.data() + offset, key_bytes) != 1) {
      // One message for every failure: no padding oracle (RFC 8017 §7.1.2 note).
      ERR_clear_error();
      return status_error(status::BadSecurityChecksFailed, "RSA-OAEP decryption failed");
    }
    out.resize(at + size);
  }
  return out;
}

Bytes sha1(ByteSpan data) {
  Bytes out(EVP_MAX_MD_SIZE);
  unsigned int size = 0;
  EVP_Digest(data.data(), data.size(), out.data(), &size, EVP_sha1(), nullptr);
  out.resize(size);
  return out;
}

HmacSha256::HmacSha256(ByteSpan key) {
  EVP_MAC_CTX* ctx = EVP_MAC_CTX_new(hmac_algorithm());
  char digest[] = "SHA256";
  const OSSL_PARAM params[] = {OSSL_PARAM_construct_utf8_string(OSSL_MAC_PARAM_DIGEST, digest, 0),
                               OSSL_PARAM_construct_end()};
  // An empty key is legal for HMAC; OpenSSL wants a non-null pointer for it.
  static const unsigned char kNoKey = 0;
  if (ctx == nullptr || EVP_MAC_init(ctx, key.empty() ? &kNoKey : key.data(), key.size(), params) != 1) {
    EVP_MAC_CTX_free(ctx);
    ctx = nullptr;
  }
  keyed_ = std::shared_ptr<EVP_MAC_CTX>(ctx, EVP_MAC_CTX_free);
}

Bytes HmacSha256::mac(ByteSpan data) const {
  if (!keyed_) {
    return {};
  }
  Ptr<EVP_MAC_CTX> ctx(EVP_MAC_CTX_dup(keyed_.get()));
  Bytes out(32);
  std::size_t size = 0;
  if (!ctx || EVP_MAC_update(ctx.get(), data.data(), data.size()) != 1 ||
      EVP_MAC_final(ctx.get(), out.data(), &size, out.size()) != 1) {
    ERR_clear_error();
    return {};
  }
  out.resize(size);
  return out;
}

Bytes hmac_sha256(ByteSpan key, ByteSpan data) {
  return HmacSha256(key).mac(data);
}

Result<Bytes> aes_cbc(bool encrypt, ByteSpan key, ByteSpan iv, ByteSpan data) {
  const EVP_CIPHER* cipher = aes_cipher(key.size());
  if (cipher == nullptr || iv.size() != 16 || data.size() % 16 != 0 || data.size() > INT_MAX - 32) {
    return status_error(encrypt ? status::BadInternalError : status::BadSecurityChecksFailed,
                        "AES-CBC over a partial block or with a wrong key size");
  }
  Ptr<EVP_CIPHER_CTX> ctx(EVP_CIPHER_CTX_new());
  Bytes out(data.size() + 16);
  int n = 0;
  int last = 0;
  if (!ctx || EVP_CipherInit_ex2(ctx.get(), cipher, key.data(), iv.data(), encrypt ? 1 : 0, nullptr) != 1 ||
      EVP_CIPHER_CTX_set_padding(ctx.get(), 0) != 1 ||
      EVP_CipherUpdate(ctx.get(), out.data(), &n, data.data(), static_cast<int>(data.size())) != 1 ||
      EVP_CipherFinal_ex(ctx.get(), out.data() + n, &last) != 1) {
    return failure(status::BadSecurityChecksFailed, "AES-CBC failed");
  }
  out.resize(static_cast<std::size_t>(n + last));
  return out;
}

Result<Bytes> random_bytes(std::size_t size) {
  Bytes out(size);
  if (size > 0 && RAND_bytes(out.data(), static_cast<int>(size)) != 1) {
    return failure(status::BadInternalError, "no random bytes");
  }
  return out;
}

std::string base64_encode(ByteSpan bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3) + 1, '\0');
  const int n = EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()), bytes.data(),
                                static_cast<int>(bytes.size()));
  out.resize(static_cast<std::size_t>(std::max(n, 0)));
  return out;
}

Result<Bytes> base64_decode(std::string_view text) {
  if (text.size() % 4 != 0 || text.size() > INT_MAX) {
    return make_error(Errc::malformed, "base64 text of a length that is not a multiple of 4");
  }
  Bytes out(text.size() / 4 * 3);
  const int n = EVP_DecodeBlock(out.data(), reinterpret_cast<const unsigned char*>(text.data()),
                                static_cast<int>(text.size()));
  if (n < 0) {
    return make_error(Errc::malformed, "not base64 text");
  }
  std::size_t padding = 0;
  for (std::size_t i = text.size(); i > 0 && text[i - 1] == '=' && padding < 2; --i) {
    ++padding;
  }
  out.resize(static_cast<std::size_t>(n) - padding);
  return out;
}

std::string hex(ByteSpan bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (const auto b : bytes) {
    out.push_back(kDigits[b >> 4U]);
    out.push_back(kDigits[b & 0x0FU]);
  }
  return out;
}

}  // namespace sf::opcua::security::ossl
