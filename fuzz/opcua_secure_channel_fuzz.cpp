// Fuzzes the secured message path of a server-role SecureChannel with Basic256Sha256
// SignAndEncrypt (OPC 10000-6 §6.7.2): whatever arrives must be refused or delivered without
// reading out of bounds, crashing or leaving the channel open after an error. The first byte
// picks where the input lands:
//   0: raw bytes after a real secured OPN (HEL/ACK and the RSA handshake done);
//   1: an OPN chunk with a valid asymmetric security header (our policy, the client's
//      certificate, the server's thumbprint) whose encrypted part is the input (RSA-OAEP
//      decryption and signature checks of garbage);
//   2: MSG chunks whose plaintext (sequence number onwards: request id, body, padding) comes from
//      the input and which the harness signs and encrypts with the client's real keys, so the
//      fuzzer gets past HMAC and AES to the padding checks, sequence numbers and body decoding.
// Every input does an RSA handshake (modes 0 and 2) or RSA decryption (1): about 100 runs/s.
// Seeds (fuzz/corpus/opcua_secure_channel_fuzz): mode 2 with the requests of opcua_server_fuzz's
// corpus after a request id, validly padded (PaddingSize n and n bytes n) to whole AES blocks, one
// of them split over two chunks, an abort chunk; a plain CLO (mode 0); one zero RSA block (1).
#include <cstddef>
#include <cstdint>
#include <memory>

#include "opcua_channel_fuzz.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/encoding.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/transport/secure_channel.hpp"

namespace {

using namespace sf::opcua;
using namespace opcua_fuzz;

SecurityCredentials make_credentials(const char* uri) {
  security::CertificateRequest request;
  request.application_uri = uri;
  request.common_name = uri;
  auto made = security::create_certificate(request);
  check(made.ok());
  return *made;
}

// RSA key generation is slow: one pair of certificates for the whole run.
const SecurityCredentials& server_credentials() {
  static const SecurityCredentials c = make_credentials("urn:fuzz:server");
  return c;
}
const SecurityCredentials& client_credentials() {
  static const SecurityCredentials c = make_credentials("urn:fuzz:client");
  return c;
}

// Basic256Sha256 that remembers the keys the client derived for sending (the server's receiving
// keys), so the harness can secure chunks of its own.
class KeyRecorder final : public ForwardingSecurityPolicy {
 public:
  explicit KeyRecorder(std::shared_ptr<SymmetricKeys> keys)
      : ForwardingSecurityPolicy(security::make_security_policy(security::kBasic256Sha256Uri)),
        keys_(std::move(keys)) {}
  sf::Result<ChannelCrypto> symmetric(MessageSecurityMode mode, const SymmetricKeys& sending,
                                      const SymmetricKeys& receiving) const override {
    *keys_ = sending;
    return ForwardingSecurityPolicy::symmetric(mode, sending, receiving);
  }

 private:
  std::shared_ptr<SymmetricKeys> keys_;
};

SecureChannelConfig secured_server_config() {
  SecureChannelConfig c = server_config();
  c.policies = security::full_registry();
  c.credentials = server_credentials();
  return c;
}

// Opens the server with a Basic256Sha256 SignAndEncrypt client whose keys land in `keys`; returns
// the client's next sequence number.
std::uint32_t open_secured(SecureChannel& server, const sf::Clock& clock,
                           const std::shared_ptr<SymmetricKeys>& keys) {
  auto registry = std::make_shared<SecurityPolicyRegistry>();
  registry->add(std::make_shared<KeyRecorder>(keys));
  SecureChannelConfig c;
  c.policies = registry;
  c.security_policy_uri = std::string(security::kBasic256Sha256Uri);
  c.security_mode = MessageSecurityMode::SignAndEncrypt;
  c.credentials = client_credentials();
  c.server_certificate = server_credentials().certificate;
  return open(server, c, clock);
}

// An OPN whose security header is right and whose encrypted part is `cipher`.
void feed_open(SecureChannel& server, sf::ByteSpan cipher) {
  auto thumbprint = security::make_security_policy(security::kBasic256Sha256Uri)
                        ->thumbprint(server_credentials().certificate);
  check(thumbprint.ok());
  sf::ByteWriter w;
  w.bytes(sf::Bytes{'O', 'P', 'N', 'F'});
  w.u32(0);
  w.u32(0);
  Encoder e(w);
  encode_binary(e, String(security::kBasic256Sha256Uri));
  encode_binary(e, client_credentials().certificate);
  encode_binary(e, *thumbprint);
  w.bytes(cipher);
  (void)w.patch<std::uint32_t>(4, static_cast<std::uint32_t>(w.size()));
  server.receive(encode_hello(make_hello(TransportLimits{}, "opc.tcp://fuzz")));
  (void)server.take_output();
  server.receive(w.data());
}

// MSG chunks: [control][length u16][plaintext after the sequence number], secured with the keys.
void feed_secured(SecureChannel& server, sf::ByteSpan input, std::uint32_t sequence,
                  const SymmetricKeys& keys, bool& closed) {
  auto crypto = security::make_security_policy(security::kBasic256Sha256Uri)
                    ->symmetric(MessageSecurityMode::SignAndEncrypt, keys, keys);
  check(crypto.ok());
  const MessageCrypto& sending = *crypto->sending;
  sf::ByteReader r(input);
  while (r.remaining() >= 3 && !closed) {
    const std::uint8_t control = r.u8();
    const std::size_t length = r.u16();
    sf::Bytes plain;
    sf::ByteWriter p(plain);
    p.u32((control & 0x80U) != 0 ? sequence + 3 : sequence);
    p.bytes(r.bytes(std::min(length, r.remaining())));
    // Whole AES blocks once the 32-byte signature follows; what the padding says is the input's.
    plain.resize(plain.size() + (16 - (plain.size() + sending.signature_size()) % 16) % 16, control);
    sf::ByteWriter w;
    w.bytes(sf::Bytes{'M', 'S', 'G', static_cast<std::uint8_t>("FCAF"[control & 3U])});
    w.u32(0);
    w.u32(77);
    w.u32(1);  // the first token
    const std::size_t header = w.size();
    const std::size_t total = header + plain.size() + sending.signature_size();
    (void)w.patch<std::uint32_t>(4, static_cast<std::uint32_t>(total));
    w.bytes(plain);
    auto signature = sending.sign(w.data());
    check(signature.ok());
    plain.insert(plain.end(), signature->begin(), signature->end());
    auto cipher = sending.encrypt(plain);
    check(cipher.ok());
    sf::Bytes chunk(w.data().begin(), w.data().begin() + static_cast<std::ptrdiff_t>(header));
    chunk.insert(chunk.end(), cipher->begin(), cipher->end());
    ++sequence;
    server.receive(chunk);
    drain(server, closed);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)sf::log::set_level("off");
  (void)server_credentials();
  (void)client_credentials();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) {
    return 0;
  }
  sf::ManualClock clock;
  SecureChannel server(secured_server_config(), clock);
  const std::uint8_t mode = data[0] % 3U;
  const sf::ByteSpan input(data + 1, size - 1);
  bool closed = false;
  if (mode == 1) {
    feed_open(server, input);
    drain(server, closed);
  } else {
    auto keys = std::make_shared<SymmetricKeys>();
    const std::uint32_t sequence = open_secured(server, clock, keys);
    if (mode == 0) {
      server.receive(input);
      drain(server, closed);
    } else {
      feed_secured(server, input, sequence, *keys, closed);
    }
  }
  clock.advance(std::chrono::hours{2});  // past every token lifetime
  server.on_timer();
  drain(server, closed);
  check(!server.is_open());
  return 0;
}
