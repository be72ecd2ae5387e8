// The client's security (OPC 10000-2 §4): endpoint selection and the server certificate check
// (OPC 10000-4 §5.4.4, §6.1.3), the secured channel, CreateSession's signature and endpoint
// list (§5.6.2), ActivateSession's signature and user identity tokens (§5.6.3, §7.40).
#include <algorithm>
#include <tuple>

#include <fmt/format.h>

#include "client_impl.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/policies.hpp"

namespace sf::opcua {
namespace {

constexpr std::string_view kTransportProfile =
    "http://opcfoundation.org/UA-Profile/Transport/uatcp-uasc-uabinary";

bool is_none(std::string_view policy_uri) {
  return policy_uri.empty() || policy_uri == kSecurityPolicyNoneUri;
}

Bytes concat(const ByteString& a, const ByteString& b) {
  Bytes out = a.bytes();
  out.insert(out.end(), b.bytes().begin(), b.bytes().end());
  return out;
}

bool has_token(const EndpointDescription& endpoint, UserTokenType type) {
  return std::any_of(endpoint.user_identity_tokens.begin(), endpoint.user_identity_tokens.end(),
                     [type](const UserTokenPolicy& p) { return p.token_type == type; });
}

bool same_leaf(const ByteString& a, const ByteString& b) {
  auto la = security::leaf_certificate(a.span());
  auto lb = security::leaf_certificate(b.span());
  return la && lb && *la == *lb;
}

// §5.4.4 leaves the choice among equal securityLevels to the client: SignAndEncrypt over Sign
// (MessageSecurityMode's values rise with protection), then the stronger policy.
bool more_secure(const EndpointDescription& a, const EndpointDescription& b) {
  const auto rank = [](const EndpointDescription& e) {
    return std::tuple(e.security_level, static_cast<int>(e.security_mode),
                      security::policy_strength(e.security_policy_uri.view()));
  };
  return rank(a) > rank(b);
}

std::string host_of(std::string_view url) {
  auto parsed = parse_endpoint_url(url);
  return parsed ? parsed->first : std::string();
}

}  // namespace

Result<EndpointDescription> select_endpoint(const std::vector<EndpointDescription>& endpoints,
                                            std::string_view policy_uri, MessageSecurityMode mode,
                                            UserTokenType user) {
  const EndpointDescription* best = nullptr;
  for (const auto& e : endpoints) {
    const bool transport = e.transport_profile_uri.empty() || e.transport_profile_uri == kTransportProfile;
    const bool known = security::full_registry()->find(e.security_policy_uri.view()) != nullptr;
    const bool policy_ok = policy_uri.empty() ? known : e.security_policy_uri == policy_uri;
    const bool mode_ok = (policy_uri.empty() && mode == MessageSecurityMode::None) || e.security_mode == mode;
    if (!transport || !policy_ok || !mode_ok || !has_token(e, user)) {
      continue;
    }
    if (best == nullptr || more_secure(e, *best)) {
      best = &e;
    }
  }
  if (best == nullptr) {
    return status_error(
        status::BadSecurityPolicyRejected,
        fmt::format("the server has no endpoint with {} and {} for a {} login",
                    policy_uri.empty() ? "any policy" : security::policy_name(policy_uri),
                    policy_uri.empty() && mode == MessageSecurityMode::None ? "any mode" : to_string(mode),
                    to_string(user)));
  }
  return *best;
}

bool Client::Impl::plain() const {
  return config.security.policy_uri == kSecurityPolicyNoneUri &&
         config.security.mode == MessageSecurityMode::None;
}

void Client::Impl::discover_endpoint(std::uint64_t generation,
                                     std::function<void(Result<EndpointDescription>)> done) {
  get_endpoints([this, generation,
                 done = std::move(done)](Result<std::vector<EndpointDescription>> endpoints) {
    if (generation != channel_generation) {
      return;
    }
    if (!endpoints) {
      done(client_detail::error_of(endpoints));
      return;
    }
    auto chosen =
        select_endpoint(*endpoints, config.security.policy_uri, config.security.mode, config.user.type);
    if (!chosen) {
      done(chosen.error());
      return;
    }
    if (!is_none(chosen->security_policy_uri.view())) {
      if (config.security.credentials.certificate.empty()) {
        done(status_error(status::BadConfigurationError,
                          fmt::format("{} needs a client certificate", chosen->security_policy_uri.view())));
        return;
      }
      const ByteString& certificate = chosen->server_certificate;
      if (auto st = security::check_application_uri(certificate, chosen->server.application_uri.view());
          !st) {
        done(st.error());
        return;
      }
      if (config.security.validate_server_certificate) {
        if (auto st = config.security.validate_server_certificate(certificate); !st) {
          done(st.error());
          return;
        }
      }
      if (auto st = security::check_host_name(certificate, host_of(config.endpoint_url)); !st) {
        // Not fatal: servers reached through another name than their certificate's are common.
        logger->warn("opcua client {}: {}", config.endpoint_url, st.error().message);
      }
    }
    discovered = std::move(*endpoints);
    done(std::move(*chosen));
  });
}

ClientTransportConfig Client::Impl::transport_config() const {
  ClientTransportConfig transport;
  transport.endpoint_url = config.endpoint_url;
  transport.limits = config.limits;
  transport.connect_timeout = config.request_timeout;
  if (endpoint && !is_none(endpoint->security_policy_uri.view())) {
    transport.security_policy_uri = endpoint->security_policy_uri.str();
    transport.security_mode = endpoint->security_mode;
    transport.policies = security::full_registry();
    transport.credentials = config.security.credentials;
    transport.server_certificate = endpoint->server_certificate;
  }
  return transport;
}

void Client::Impl::secure_create_request(CreateSessionRequest& request) {
  // Our certificate also goes over a None channel when we have one: some servers name theirs,
  // which an encrypted password needs, only to a client that named its own.
  const bool secure = endpoint && !is_none(endpoint->security_policy_uri.view());
  if (secure || !config.security.credentials.certificate.empty()) {
    request.client_certificate = config.security.credentials.certificate;
  }
  client_nonce = request.client_nonce;
}

Status Client::Impl::check_create_response(const CreateSessionResponse& response) {
  if (!endpoint) {
    // No discovery (None/None): the endpoint and its token policies come with the session.
    for (const auto& e : response.server_endpoints) {
      if (is_none(e.security_policy_uri.view()) && e.security_mode == MessageSecurityMode::None) {
        endpoint = e;
        break;
      }
    }
    return {};
  }
  if (is_none(endpoint->security_policy_uri.view())) {
    return {};
  }
  const std::string policy = endpoint->security_policy_uri.str();
  if (!same_leaf(response.server_certificate, endpoint->server_certificate)) {
    return status_error(status::BadCertificateInvalid, "CreateSession names another server certificate");
  }
  // §5.6.2: the server signs our certificate and nonce, proving it holds its key.
  if (auto st = security::verify(policy, endpoint->server_certificate,
                                 concat(config.security.credentials.certificate, client_nonce),
                                 response.server_signature);
      !st) {
    return status_error(status::BadApplicationSignatureInvalid,
                        "the server's signature: " + st.error().message);
  }
  // §5.6.2: the endpoints must be those of GetEndpoints, so nobody downgraded our choice.
  for (const auto& found : discovered) {
    const bool listed = std::any_of(response.server_endpoints.begin(), response.server_endpoints.end(),
                                    [&found](const EndpointDescription& e) {
                                      return e.security_policy_uri == found.security_policy_uri &&
                                             e.security_mode == found.security_mode;
                                    });
    if (!listed) {
      return status_error(status::BadSecurityChecksFailed,
                          "CreateSession's endpoints differ from those of GetEndpoints");
    }
  }
  return {};
}

// §7.41.2.1: a secret is encrypted only for a server certificate the client trusts. Over a
// secured channel discovery checked it; over a None channel nothing has yet.
Status Client::Impl::check_token_certificate(const ByteString& certificate,
                                             std::string_view channel_policy) const {
  if (certificate.empty()) {
    return status_error(status::BadCertificateInvalid,
                        "the server named no certificate to encrypt the password with");
  }
  if (is_none(channel_policy) && config.security.validate_server_certificate) {
    return config.security.validate_server_certificate(certificate);
  }
  return {};
}

Status Client::Impl::fill_activation(ActivateSessionRequest& request) const {
  // §5.6.2: a server may leave CreateSession's serverCertificate empty on a None channel (some
  // do when the client sent no certificate); the endpoint's is the same application's.
  const ByteString& server_certificate = session->server_certificate.empty() && endpoint
                                             ? endpoint->server_certificate
                                             : session->server_certificate;
  const std::string channel_policy = endpoint ? endpoint->security_policy_uri.str() : std::string();
  const MessageSecurityMode channel_mode = endpoint ? endpoint->security_mode : MessageSecurityMode::None;
  const Bytes signed_data = concat(server_certificate, session->server_nonce);
  if (!is_none(channel_policy)) {
    auto signature = security::sign(channel_policy, config.security.credentials.private_key, signed_data);
    if (!signature) {
      return signature.error();
    }
    request.client_signature = std::move(*signature);
  }
  const UserIdentity& user = config.user;
  const UserTokenPolicy* policy = nullptr;
  if (endpoint) {
    for (const auto& p : endpoint->user_identity_tokens) {
      if (p.token_type == user.type) {
        policy = &p;
        break;
      }
    }
  }
  if (user.type == UserTokenType::Anonymous) {
    request.user_identity_token = ExtensionObject::make(
        AnonymousIdentityToken{policy != nullptr ? policy->policy_id : String(session->anonymous_policy_id)});
    return {};
  }
  if (policy == nullptr) {
    return status_error(status::BadIdentityTokenRejected,
                        fmt::format("the endpoint offers no {} login", to_string(user.type)));
  }
  // §7.41: the token policy's securityPolicyUri protects the secret, else the channel's.
  const std::string protect =
      policy->security_policy_uri.empty() ? channel_policy : policy->security_policy_uri.str();
  if (user.type == UserTokenType::UserName) {
    UserNameIdentityToken token;
    token.policy_id = policy->policy_id;
    token.user_name = user.user_name;
    const ByteSpan password(reinterpret_cast<const std::uint8_t*>(user.password.data()),
                            user.password.size());
    if (is_none(protect)) {
      if (channel_mode != MessageSecurityMode::SignAndEncrypt) {
        return status_error(status::BadSecurityModeInsufficient,
                            "the endpoint would carry the password in clear; choose an encrypted endpoint");
      }
      token.password = ByteString(password);
    } else {
      SF_TRY(check_token_certificate(server_certificate, channel_policy));
      auto secret =
          security::encrypt_secret(protect, server_certificate, password, session->server_nonce.span());
      if (!secret) {
        return secret.error();
      }
      token.password = std::move(*secret);
      token.encryption_algorithm = String(security::encryption_algorithm_uri(protect));
    }
    request.user_identity_token = ExtensionObject::make(std::move(token));
    return {};
  }
  if (is_none(protect)) {
    return status_error(status::BadSecurityModeInsufficient, "a certificate login needs a security policy");
  }
  X509IdentityToken token;
  token.policy_id = policy->policy_id;
  token.certificate_data = user.certificate.certificate;
  auto signature = security::sign(protect, user.certificate.private_key, signed_data);
  if (!signature) {
    return signature.error();
  }
  request.user_identity_token = ExtensionObject::make(std::move(token));
  request.user_token_signature = std::move(*signature);
  return {};
}

}  // namespace sf::opcua
