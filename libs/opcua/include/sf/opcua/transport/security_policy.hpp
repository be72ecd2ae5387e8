// Pluggable message security for the secure channel (OPC 10000-6 §6.7.2, §6.7.4, §6.7.5).
//
// The chunk writer/reader in secure_channel.cpp knows only this interface:
//   - a SecurityPolicy describes one policy URI: nonce length, the key derivation lengths, the
//     pseudo-random function, certificate thumbprints, and it builds the MessageCrypto objects;
//   - a MessageCrypto does the cryptography of ONE direction with ONE set of keys: the
//     asymmetric algorithms for OPN chunks (own private key, peer certificate) or the symmetric
//     ones for MSG/CLO chunks (keys derived for one token). It reports the sizes the chunk
//     layout needs and signs/encrypts/decrypts/verifies byte ranges.
// Chunk layout (§6.7.2.2): MessageHeader | SecurityHeader | SequenceHeader | Body | Padding |
// Signature. The signature covers everything before it; encryption covers SequenceHeader to
// the end. Padding (only when encrypting) is PaddingSize byte + PaddingSize bytes of value
// PaddingSize, plus ExtraPaddingSize byte when the asymmetric key is > 2048 bits (§6.7.2.5).
// SecurityPolicy None needs none of it; Basic256Sha256, Aes128_Sha256_RsaOaep and
// Aes256_Sha256_RsaPss (OPC 10000-7) implement these classes over OpenSSL and register themselves.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/builtin_types.hpp"
#include "sf/opcua/codec.hpp"
#include "sf/opcua/types.hpp"

namespace sf::opcua {

inline constexpr std::string_view kSecurityPolicyNoneUri = "http://opcfoundation.org/UA/SecurityPolicy#None";

// §6.7.2.3: the security header of OPN chunks.
struct AsymmetricSecurityHeader {
  String security_policy_uri;
  ByteString sender_certificate;               // DER, null when not signed
  ByteString receiver_certificate_thumbprint;  // SHA-1 of the receiver's DER cert, null when not encrypted

  friend bool operator==(const AsymmetricSecurityHeader&, const AsymmetricSecurityHeader&) = default;
};
void encode_binary(Encoder& e, const AsymmetricSecurityHeader& v);
void decode_binary(Decoder& d, AsymmetricSecurityHeader& v);

// The own application instance certificate and its private key, for policies that sign.
struct SecurityCredentials {
  ByteString certificate;  // DER
  Bytes private_key;       // DER (PKCS#8)
};

// The cryptography of one direction of a channel with one set of keys.
class MessageCrypto {
 public:
  virtual ~MessageCrypto() = default;

  // 0 when chunks are not signed.
  [[nodiscard]] virtual std::size_t signature_size() const = 0;
  [[nodiscard]] virtual bool encrypts() const = 0;
  // Sizes of a plaintext block and of the ciphertext block it becomes (1 and 1 when not
  // encrypting; 16/16 for AES-CBC; e.g. 214/256 for RSA-OAEP-2048).
  [[nodiscard]] virtual std::size_t plain_block_size() const = 0;
  [[nodiscard]] virtual std::size_t cipher_block_size() const = 0;
  // True when the padding ends with an ExtraPaddingSize byte (asymmetric key > 2048 bits).
  [[nodiscard]] virtual bool extra_padding_byte() const = 0;

  // Sending: the signature of `data` (signature_size() bytes).
  virtual Result<Bytes> sign(ByteSpan data) const = 0;
  // Sending: encrypts a whole number of plain blocks into as many cipher blocks.
  virtual Result<Bytes> encrypt(ByteSpan plain) const = 0;
  // Receiving: decrypts a whole number of cipher blocks (BadSecurityChecksFailed otherwise).
  virtual Result<Bytes> decrypt(ByteSpan cipher) const = 0;
  // Receiving: checks `signature` over `data`; BadSecurityChecksFailed when it does not match.
  virtual Status verify(ByteSpan data, ByteSpan signature) const = 0;
};

// Both directions of one channel for one key set.
struct ChannelCrypto {
  std::shared_ptr<const MessageCrypto> sending;
  std::shared_ptr<const MessageCrypto> receiving;
};

// §6.7.5: the keys one side uses to sign/encrypt what it sends.
struct SymmetricKeys {
  Bytes signing_key;
  Bytes encrypting_key;
  Bytes initialization_vector;
};

class SecurityPolicy {
 public:
  virtual ~SecurityPolicy() = default;

  [[nodiscard]] virtual std::string_view uri() const = 0;
  // False for None: no certificates, no thumbprints, no signatures, OPN not encrypted.
  [[nodiscard]] virtual bool uses_certificates() const = 0;
  // Length of the ClientNonce/ServerNonce of OPN (0: the nonces are empty).
  [[nodiscard]] virtual std::size_t nonce_length() const = 0;
  // Lengths of the derived symmetric keys (§6.7.5 table "DerivedSignatureKeyLength" ...).
  [[nodiscard]] virtual std::size_t signing_key_length() const = 0;
  [[nodiscard]] virtual std::size_t encrypting_key_length() const = 0;
  [[nodiscard]] virtual std::size_t encrypting_block_size() const = 0;

  // A fresh random nonce of nonce_length() bytes (empty ByteString for None).
  virtual Result<ByteString> create_nonce() const = 0;
  // The key derivation PRF, P_SHA256(secret, seed) for current policies (§6.7.5).
  virtual Result<Bytes> derive(ByteSpan secret, ByteSpan seed, std::size_t length) const = 0;
  // ReceiverCertificateThumbprint: the SHA-1 of a DER certificate.
  virtual Result<ByteString> thumbprint(const ByteString& certificate) const = 0;

  // The asymmetric algorithms for OPN chunks: sign with `local`'s private key, encrypt with the
  // peer's public key; receive the other way round. None: nothing is signed or encrypted.
  virtual Result<ChannelCrypto> asymmetric(const SecurityCredentials& local,
                                           const ByteString& peer_certificate) const = 0;
  // The symmetric algorithms of MSG/CLO chunks for one token. mode Sign signs only,
  // SignAndEncrypt both, None neither.
  virtual Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& sending,
                                          const SymmetricKeys& receiving) const = 0;
};

// §6.7.5: client keys = PRF(secret = ServerNonce, seed = ClientNonce), server keys =
// PRF(secret = ClientNonce, seed = ServerNonce), each split into signing key, encrypting key
// and IV. Then builds the symmetric crypto of the side `is_client`.
Result<ChannelCrypto> make_symmetric_crypto(const SecurityPolicy& policy, MessageSecurityMode mode,
                                            bool is_client, const ByteString& client_nonce,
                                            const ByteString& server_nonce);
// The P_hash of RFC 5246 §5 that §6.7.5 uses: A(0) = seed, A(i) = HMAC(secret, A(i-1)),
// output = HMAC(secret, A(1) + seed) + HMAC(secret, A(2) + seed) + ... cut to `length`.
// Policies pass their HMAC (HMAC-SHA256 for P_SHA256).
using HmacFunction = std::function<Bytes(ByteSpan key, ByteSpan data)>;
Bytes p_hash(const HmacFunction& hmac, ByteSpan secret, ByteSpan seed, std::size_t length);

// A policy that forwards everything to another one: the base of decorators that change one
// step (e.g. tests that record the derived keys or tamper with what is sent).
class ForwardingSecurityPolicy : public SecurityPolicy {
 public:
  explicit ForwardingSecurityPolicy(std::shared_ptr<const SecurityPolicy> inner) : inner_(std::move(inner)) {}
  [[nodiscard]] std::string_view uri() const override { return inner_->uri(); }
  [[nodiscard]] bool uses_certificates() const override { return inner_->uses_certificates(); }
  [[nodiscard]] std::size_t nonce_length() const override { return inner_->nonce_length(); }
  [[nodiscard]] std::size_t signing_key_length() const override { return inner_->signing_key_length(); }
  [[nodiscard]] std::size_t encrypting_key_length() const override { return inner_->encrypting_key_length(); }
  [[nodiscard]] std::size_t encrypting_block_size() const override { return inner_->encrypting_block_size(); }
  Result<ByteString> create_nonce() const override { return inner_->create_nonce(); }
  Result<Bytes> derive(ByteSpan secret, ByteSpan seed, std::size_t length) const override {
    return inner_->derive(secret, seed, length);
  }
  Result<ByteString> thumbprint(const ByteString& certificate) const override {
    return inner_->thumbprint(certificate);
  }
  Result<ChannelCrypto> asymmetric(const SecurityCredentials& local,
                                   const ByteString& peer_certificate) const override {
    return inner_->asymmetric(local, peer_certificate);
  }
  Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& sending,
                                  const SymmetricKeys& receiving) const override {
    return inner_->symmetric(mode, sending, receiving);
  }

 private:
  std::shared_ptr<const SecurityPolicy> inner_;
};

// http://opcfoundation.org/UA/SecurityPolicy#None
class SecurityPolicyNone final : public SecurityPolicy {
 public:
  [[nodiscard]] std::string_view uri() const override { return kSecurityPolicyNoneUri; }
  [[nodiscard]] bool uses_certificates() const override { return false; }
  [[nodiscard]] std::size_t nonce_length() const override { return 0; }
  [[nodiscard]] std::size_t signing_key_length() const override { return 0; }
  [[nodiscard]] std::size_t encrypting_key_length() const override { return 0; }
  [[nodiscard]] std::size_t encrypting_block_size() const override { return 1; }
  Result<ByteString> create_nonce() const override;
  Result<Bytes> derive(ByteSpan secret, ByteSpan seed, std::size_t length) const override;
  Result<ByteString> thumbprint(const ByteString& certificate) const override;
  Result<ChannelCrypto> asymmetric(const SecurityCredentials& local,
                                   const ByteString& peer_certificate) const override;
  Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& sending,
                                  const SymmetricKeys& receiving) const override;

  // The shared no-op crypto (no signature, no encryption).
  static std::shared_ptr<const MessageCrypto> plain();
};

// The policies an endpoint offers, by URI.
class SecurityPolicyRegistry {
 public:
  SecurityPolicyRegistry() = default;
  // A registry holding SecurityPolicyNone only (OPC 10000-7 SecurityPolicy [None]).
  static std::shared_ptr<const SecurityPolicyRegistry> standard();

  // Replaces a policy of the same URI.
  void add(std::shared_ptr<const SecurityPolicy> policy);
  // nullptr when unknown.
  [[nodiscard]] std::shared_ptr<const SecurityPolicy> find(std::string_view uri) const;
  // BadSecurityPolicyRejected when unknown.
  [[nodiscard]] Result<std::shared_ptr<const SecurityPolicy>> get(std::string_view uri) const;
  [[nodiscard]] std::vector<std::string> uris() const;

 private:
  std::map<std::string, std::shared_ptr<const SecurityPolicy>, std::less<>> policies_;
};

}  // namespace sf::opcua
