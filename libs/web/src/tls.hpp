// The server's TLS context (RFC 8446, RFC 5246 as RFC 9325 recommends them): the certificate
// chain and private key of ServerConfig::tls, checked before the server listens so that a
// configuration it cannot serve fails in start() with what is wrong, not in every handshake.
#pragma once

#include <boost/asio/ssl/context.hpp>
#include <memory>

#include "sf/core/result.hpp"
#include "sf/web/server.hpp"

namespace sf::web {

// TLS 1.2 minimum (1.3 is taken whenever the client offers it), forward-secret AEAD ciphers
// only, no renegotiation, no compression. Errors name the file and say what is wrong with it:
// missing, not PEM, expired or not yet valid, a key that does not match the certificate.
Result<std::shared_ptr<boost::asio::ssl::context>> make_tls_context(const TlsConfig& config);

}  // namespace sf::web
