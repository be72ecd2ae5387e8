// Salted password hashes with scrypt (RFC 7914) for the users file.
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/kdf.h>

#include <charconv>
#include <vector>

#include <fmt/format.h>

#include "openssl.hpp"
#include "sf/core/text.hpp"
#include "sf/opcua/security/users.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace {

constexpr std::size_t kSaltBytes = 16;
constexpr std::size_t kHashBytes = 32;

struct Encoded {
  PasswordHashParams params;
  Bytes salt;
  Bytes hash;
};

// Bounds for parameters read from a file, so a hostile file cannot ask for gigabytes.
bool sane(const PasswordHashParams& p) {
  return p.log2_n >= 1 && p.log2_n <= 20 && p.r >= 1 && p.r <= 32 && p.p >= 1 && p.p <= 16;
}

bool parse_param(std::string_view field, std::string_view name, unsigned& value) {
  if (field.size() <= name.size() + 1 || field.substr(0, name.size()) != name || field[name.size()] != '=') {
    return false;
  }
  const auto digits = field.substr(name.size() + 1);
  return std::from_chars(digits.data(), digits.data() + digits.size(), value).ec == std::errc{};
}

std::optional<Encoded> decode(std::string_view text) {
  const auto parts = split(text, '$');
  // "", "scrypt", "ln=..,r=..,p=..", salt, hash
  if (parts.size() != 5 || !parts[0].empty() || parts[1] != "scrypt") {
    return std::nullopt;
  }
  const auto params = split(parts[2], ',');
  Encoded e;
  if (params.size() != 3 || !parse_param(params[0], "ln", e.params.log2_n) ||
      !parse_param(params[1], "r", e.params.r) || !parse_param(params[2], "p", e.params.p) ||
      !sane(e.params)) {
    return std::nullopt;
  }
  auto salt = ossl::base64_decode(parts[3]);
  auto hash = ossl::base64_decode(parts[4]);
  if (!salt || !hash || salt->empty() || hash->size() != kHashBytes) {
    return std::nullopt;
  }
  e.salt = std::move(*salt);
  e.hash = std::move(*hash);
  return e;
}

Result<Bytes> scrypt(std::string_view password, ByteSpan salt, const PasswordHashParams& p) {
  const std::uint64_t n = std::uint64_t{1} << p.log2_n;
  // RFC 7914 §6 needs 128·r·(N + p + 2) bytes; give OpenSSL room for that.
  const std::uint64_t memory = 128ULL * p.r * (n + p.p + 2) + (1ULL << 20U);
  Bytes out(kHashBytes);
  if (EVP_PBE_scrypt(password.data(), password.size(), salt.data(), salt.size(), n, p.r, p.p, memory,
                     out.data(), out.size()) != 1) {
    return ossl::failure(status::BadInternalError, "scrypt failed");
  }
  return out;
}

}  // namespace

Result<std::string> hash_password(std::string_view password, PasswordHashParams params) {
  if (!sane(params)) {
    return make_error(Errc::invalid_argument, "scrypt parameters out of range");
  }
  auto salt = ossl::random_bytes(kSaltBytes);
  if (!salt) {
    return salt.error();
  }
  auto hash = scrypt(password, *salt, params);
  if (!hash) {
    return hash.error();
  }
  return fmt::format("$scrypt$ln={},r={},p={}${}${}", params.log2_n, params.r, params.p,
                     ossl::base64_encode(*salt), ossl::base64_encode(*hash));
}

bool verify_password(std::string_view password, std::string_view encoded) {
  const auto e = decode(encoded);
  if (!e) {
    return false;
  }
  auto hash = scrypt(password, e->salt, e->params);
  return hash && hash->size() == e->hash.size() &&
         CRYPTO_memcmp(hash->data(), e->hash.data(), e->hash.size()) == 0;
}

}  // namespace sf::opcua::security
