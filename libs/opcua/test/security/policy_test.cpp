// The three OpenSSL policies: registry, key derivation (known answers computed with node-opcua's
// computeDerivedKeys), asymmetric and symmetric crypto of each, session signatures and token
// secrets.
#include "sf/opcua/security/policies.hpp"

#include <gtest/gtest.h>

#include "sf/opcua/status_codes.hpp"
#include "test_keys.hpp"

namespace sf::opcua::security::test {
namespace {

Bytes from_hex(std::string_view hex) {
  Bytes out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    out.push_back(static_cast<std::uint8_t>(std::stoul(std::string(hex.substr(i, 2)), nullptr, 16)));
  }
  return out;
}

Bytes counting(std::size_t n, std::uint8_t first) {
  Bytes out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = static_cast<std::uint8_t>(first + i);
  }
  return out;
}

class PolicyTest : public ::testing::TestWithParam<std::string> {
 protected:
  std::shared_ptr<const SecurityPolicy> policy() const { return make_security_policy(GetParam()); }
  const SecurityCredentials& server() const {
    static const SecurityCredentials c = app_certificate("urn:test:server", "server");
    return c;
  }
  const SecurityCredentials& client() const {
    static const SecurityCredentials c = app_certificate("urn:test:client", "client");
    return c;
  }
};

TEST(Policies, RegistryNamesAndStrength) {
  auto registry = full_registry();
  for (const auto& uri : secure_policy_uris()) {
    ASSERT_NE(registry->find(uri), nullptr) << uri;
    EXPECT_TRUE(registry->find(uri)->uses_certificates());
    EXPECT_EQ(*policy_uri_from_name(policy_name(uri)), uri);
  }
  EXPECT_NE(registry->find(kSecurityPolicyNoneUri), nullptr);
  EXPECT_EQ(*policy_uri_from_name("basic256sha256"), kBasic256Sha256Uri);
  EXPECT_EQ(*policy_uri_from_name("None"), kSecurityPolicyNoneUri);
  EXPECT_EQ(status_of(policy_uri_from_name("Basic128Rsa15").error()), status::BadSecurityPolicyRejected);
  EXPECT_GT(policy_strength(kAes256Sha256RsaPssUri), policy_strength(kBasic256Sha256Uri));
  EXPECT_GT(policy_strength(kBasic256Sha256Uri), policy_strength(kAes128Sha256RsaOaepUri));
  EXPECT_EQ(policy_strength(kSecurityPolicyNoneUri), 0);
  EXPECT_FALSE(make_registry({"urn:nope"}).ok());
}

// OPC 10000-6 §6.7.5, cross-checked with node-opcua 2.186's computeDerivedKeys: client keys =
// P_SHA256(serverNonce, clientNonce), server keys = P_SHA256(clientNonce, serverNonce), each split
// into signing key | encrypting key | IV.
TEST(Policies, KeyDerivationMatchesNodeOpcua) {
  const Bytes client_nonce = counting(32, 0x00);
  const Bytes server_nonce = counting(32, 0x80);
  const Bytes client_keys = from_hex(
      "2af527aa718110faf5eb0d676e2a0985495125fd62e6ad63b129793f8f6f4316"
      "1b4b5e8d4e842728e1f9a047e998615c9bd646d620ab90a6cf46eea29d6c9842"
      "c3c4f8750b47e94eac19e52a5439dd1e");
  const Bytes server_keys = from_hex(
      "a32cfbeae0a5afe142dadbecb94195a2685c99541cf5b71e9efd592a4b3648ff"
      "e7689712d1babf38c6352b86e5c0881a52af7b418d551caa289df8cf84278e70"
      "8081af129e631f1a8c56f073c2d50ce8");
  for (const auto& uri : secure_policy_uris()) {
    auto policy = make_security_policy(uri);
    const std::size_t length =
        policy->signing_key_length() + policy->encrypting_key_length() + policy->encrypting_block_size();
    EXPECT_EQ(policy->signing_key_length(), 32U);
    EXPECT_EQ(policy->nonce_length(), 32U);
    EXPECT_EQ(policy->encrypting_key_length(), uri == kAes128Sha256RsaOaepUri ? 16U : 32U);
    // The Aes128 split differs, but P_SHA256's stream is the same: the first `length` bytes.
    EXPECT_EQ(*policy->derive(server_nonce, client_nonce, length),
              Bytes(client_keys.begin(), client_keys.begin() + static_cast<std::ptrdiff_t>(length)))
        << uri;
    EXPECT_EQ(*policy->derive(client_nonce, server_nonce, length),
              Bytes(server_keys.begin(), server_keys.begin() + static_cast<std::ptrdiff_t>(length)))
        << uri;
  }
}

TEST_P(PolicyTest, AsymmetricBothWays) {
  auto client_side = policy()->asymmetric(client(), server().certificate);
  auto server_side = policy()->asymmetric(server(), client().certificate);
  ASSERT_TRUE(client_side.ok()) << client_side.error().message;
  ASSERT_TRUE(server_side.ok()) << server_side.error().message;
  const MessageCrypto& out = *client_side->sending;
  const MessageCrypto& in = *server_side->receiving;
  EXPECT_EQ(out.signature_size(), 256U);
  EXPECT_EQ(out.cipher_block_size(), 256U);
  EXPECT_EQ(out.plain_block_size(), GetParam() == kAes256Sha256RsaPssUri ? 190U : 214U);
  EXPECT_FALSE(out.extra_padding_byte());
  const Bytes plain = counting(out.plain_block_size() * 3, 7);
  auto cipher = out.encrypt(plain);
  ASSERT_TRUE(cipher.ok());
  EXPECT_EQ(cipher->size(), 3 * 256U);
  EXPECT_EQ(*in.decrypt(*cipher), plain);
  auto signature = out.sign(plain);
  ASSERT_TRUE(signature.ok());
  EXPECT_TRUE(in.verify(plain, *signature).ok());
  Bytes tampered = plain;
  tampered[10] ^= 1U;
  EXPECT_EQ(status_of(in.verify(tampered, *signature).error()), status::BadSecurityChecksFailed);
  // The client cannot read what it sent: only the server's key decrypts it.
  EXPECT_FALSE(client_side->receiving->decrypt(*cipher).ok());
}

TEST_P(PolicyTest, SymmetricBothModes) {
  const ByteString client_nonce = *policy()->create_nonce();
  const ByteString server_nonce = *policy()->create_nonce();
  EXPECT_NE(client_nonce, server_nonce);
  for (const auto mode : {MessageSecurityMode::Sign, MessageSecurityMode::SignAndEncrypt}) {
    auto client = make_symmetric_crypto(*policy(), mode, true, client_nonce, server_nonce);
    auto server = make_symmetric_crypto(*policy(), mode, false, client_nonce, server_nonce);
    ASSERT_TRUE(client.ok() && server.ok());
    const bool encrypt = mode == MessageSecurityMode::SignAndEncrypt;
    EXPECT_EQ(client->sending->encrypts(), encrypt);
    EXPECT_EQ(client->sending->signature_size(), 32U);
    EXPECT_EQ(client->sending->plain_block_size(), encrypt ? 16U : 1U);
    const Bytes plain = counting(64, 3);
    auto mac = client->sending->sign(plain);
    EXPECT_TRUE(server->receiving->verify(plain, *mac).ok());
    EXPECT_FALSE(client->receiving->verify(plain, *mac).ok());  // each direction has its keys
    if (encrypt) {
      auto cipher = client->sending->encrypt(plain);
      ASSERT_TRUE(cipher.ok());
      EXPECT_NE(*cipher, plain);
      EXPECT_EQ(*server->receiving->decrypt(*cipher), plain);
      EXPECT_FALSE(client->sending->encrypt(counting(15, 0)).ok());  // not a whole block
    }
  }
  EXPECT_EQ(status_of(policy()->symmetric(MessageSecurityMode::None, {}, {}).error()),
            status::BadSecurityModeRejected);
}

TEST_P(PolicyTest, LargeKeysUseTheExtraPaddingByte) {
  const SecurityCredentials big = app_certificate("urn:test:big", "big", 3072);
  auto crypto = policy()->asymmetric(client(), big.certificate);
  ASSERT_TRUE(crypto.ok());
  EXPECT_TRUE(crypto->sending->extra_padding_byte());
  EXPECT_EQ(crypto->sending->cipher_block_size(), 384U);
  EXPECT_FALSE(crypto->receiving->extra_padding_byte());  // the client's own key is 2048 bits
}

TEST_P(PolicyTest, KeysOutsideThePolicyRangeAreRefused) {
  const SecurityCredentials small = app_certificate("urn:test:small", "small", 1024);
  auto crypto = policy()->asymmetric(client(), small.certificate);
  ASSERT_FALSE(crypto.ok());
  EXPECT_EQ(status_of(crypto.error()), status::BadCertificatePolicyCheckFailed);
}

TEST_P(PolicyTest, ThumbprintIsTheSha1OfTheLeaf) {
  ByteString chain = server().certificate;
  Bytes both = chain.bytes();
  both.insert(both.end(), client().certificate.bytes().begin(), client().certificate.bytes().end());
  auto single = policy()->thumbprint(chain);
  auto of_chain = policy()->thumbprint(ByteString(both));
  ASSERT_TRUE(single.ok() && of_chain.ok());
  EXPECT_EQ(single->size(), 20U);
  EXPECT_EQ(*single, *of_chain);
}

TEST_P(PolicyTest, SessionSignaturesAndSecrets) {
  const Bytes data = counting(100, 1);
  auto signature = sign(GetParam(), server().private_key, data);
  ASSERT_TRUE(signature.ok());
  EXPECT_EQ(signature->algorithm.view(), signature_algorithm_uri(GetParam()));
  EXPECT_TRUE(verify(GetParam(), server().certificate, data, *signature).ok());
  EXPECT_FALSE(verify(GetParam(), client().certificate, data, *signature).ok());
  SignatureData wrong_algorithm = *signature;
  wrong_algorithm.algorithm = String("http://www.w3.org/2000/09/xmldsig#rsa-sha1");
  EXPECT_FALSE(verify(GetParam(), server().certificate, data, wrong_algorithm).ok());

  const Bytes nonce = counting(32, 0x40);
  const std::string password = "correct horse battery staple";
  const ByteSpan secret(reinterpret_cast<const std::uint8_t*>(password.data()), password.size());
  auto cipher = encrypt_secret(GetParam(), server().certificate, secret, nonce);
  ASSERT_TRUE(cipher.ok());
  EXPECT_EQ(cipher->size(), 256U);
  auto plain = decrypt_secret(GetParam(), server().private_key, cipher->span(), nonce);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(std::string(plain->begin(), plain->end()), password);
  auto replayed = decrypt_secret(GetParam(), server().private_key, cipher->span(), counting(32, 0x41));
  EXPECT_EQ(status_of(replayed.error()), status::BadIdentityTokenInvalid);
  auto wrong_key = decrypt_secret(GetParam(), client().private_key, cipher->span(), nonce);
  EXPECT_EQ(status_of(wrong_key.error()), status::BadIdentityTokenInvalid);
}

// OPC 10000-4 §7.41.2.2: a client should not pad the legacy token secret, but some fill the RSA
// blocks with zeros after the server nonce; the server accepts zero padding and refuses any other.
TEST_P(PolicyTest, TokenSecretsPaddedByTheClient) {
  auto client_side = policy()->asymmetric(client(), server().certificate);
  ASSERT_TRUE(client_side.ok()) << client_side.error().message;
  const MessageCrypto& rsa = *client_side->sending;
  const Bytes nonce = counting(32, 0x40);
  const std::string password = "correct horse battery staple";
  // The token secret as a client builds it by hand: length, secret, nonce, then `padding` bytes.
  const auto token = [&](std::size_t blocks, std::uint8_t pad_byte, std::uint32_t length) {
    ByteWriter plain;
    plain.u32(length);
    plain.bytes(ByteSpan(reinterpret_cast<const std::uint8_t*>(password.data()), password.size()));
    plain.bytes(nonce);
    Bytes bytes = plain.data();
    bytes.resize(blocks * rsa.plain_block_size(), pad_byte);
    return *rsa.encrypt(bytes);
  };
  const auto exact = static_cast<std::uint32_t>(password.size() + nonce.size());
  for (const std::size_t blocks : {1U, 2U}) {
    auto plain = decrypt_secret(GetParam(), server().private_key, token(blocks, 0, exact), nonce);
    ASSERT_TRUE(plain.ok()) << blocks << " block(s): " << plain.error().message;
    EXPECT_EQ(std::string(plain->begin(), plain->end()), password);
  }
  auto nonzero = decrypt_secret(GetParam(), server().private_key, token(1, 0x20, exact), nonce);
  ASSERT_FALSE(nonzero.ok());
  EXPECT_EQ(status_of(nonzero.error()), status::BadIdentityTokenInvalid);
  // The length must still cover the nonce and stay inside the decrypted bytes.
  for (const std::uint32_t length : {std::uint32_t{31}, static_cast<std::uint32_t>(rsa.plain_block_size())}) {
    auto bad = decrypt_secret(GetParam(), server().private_key, token(1, 0, length), nonce);
    ASSERT_FALSE(bad.ok()) << length;
    EXPECT_EQ(status_of(bad.error()), status::BadIdentityTokenInvalid);
  }
}

INSTANTIATE_TEST_SUITE_P(AllPolicies, PolicyTest, ::testing::ValuesIn(secure_policy_uris()),
                         [](const auto& p) { return std::string(policy_name(p.param)); });

}  // namespace
}  // namespace sf::opcua::security::test
