// CreateSession/ActivateSession security (OPC 10000-4 §5.6.2, §5.6.3, §7.36, §7.40).
#include "session_security.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/opcua/security/certificate.hpp"
#include "sf/opcua/security/policies.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::server::detail {

namespace sec = ::sf::opcua::security;
namespace {

constexpr std::size_t kMinClientNonce = 32;

bool policy_is_none(std::string_view policy_uri) {
  return policy_uri.empty() || policy_uri == kSecurityPolicyNoneUri;
}

std::string policy_of(const ChannelInfo& channel) {
  return policy_is_none(channel.security_policy_uri) ? std::string(kSecurityPolicyNoneUri)
                                                     : channel.security_policy_uri;
}

Bytes concat(const ByteString& a, const ByteString& b) {
  Bytes out = a.bytes();
  out.insert(out.end(), b.bytes().begin(), b.bytes().end());
  return out;
}

// A status from a lower layer, reported under the code the service defines for the failure.
Error as(StatusCode code, const Error& error) {
  return status_error(code, error.message);
}

const UserTokenPolicy* find_token_policy(const std::vector<UserTokenPolicy>& policies,
                                         const String& policy_id, UserTokenType type) {
  const auto it = std::find_if(policies.begin(), policies.end(), [&](const UserTokenPolicy& p) {
    return p.token_type == type &&
           (p.policy_id == policy_id || (type == UserTokenType::Anonymous && policy_id.empty()));
  });
  return it == policies.end() ? nullptr : &*it;
}

// The policy that protects a token's secret or signature (§7.41 securityPolicyUri, or the channel's).
std::string token_policy(const UserTokenPolicy& policy, const ChannelInfo& channel) {
  return policy.security_policy_uri.empty() ? policy_of(channel) : policy.security_policy_uri.str();
}

Result<SessionIdentity> anonymous(const ServerSecurity& security,
                                  const std::vector<UserTokenPolicy>& policies, const String& policy_id) {
  if (find_token_policy(policies, policy_id, UserTokenType::Anonymous) == nullptr) {
    return status_error(status::BadIdentityTokenRejected, "anonymous access is not allowed");
  }
  SessionIdentity identity;
  identity.token_type = UserTokenType::Anonymous;
  identity.policy_id = policy_id.str();
  if (!security.anonymous_role.empty()) {
    identity.roles = {security.anonymous_role};
  }
  return identity;
}

Result<SessionIdentity> user_name(const ServerSecurity& security,
                                  const std::vector<UserTokenPolicy>& policies, const ChannelInfo& channel,
                                  const Session& session, const UserNameIdentityToken& token) {
  const UserTokenPolicy* policy = find_token_policy(policies, token.policy_id, UserTokenType::UserName);
  const auto users = security.current_users();
  if (policy == nullptr || !users) {
    return status_error(status::BadIdentityTokenRejected,
                        "user name tokens are not accepted on this endpoint");
  }
  const std::string protect = token_policy(*policy, channel);
  Bytes password;
  if (policy_is_none(protect)) {
    // Only over an encrypted channel may a password travel without its own encryption.
    if (channel.security_mode != MessageSecurityMode::SignAndEncrypt) {
      return status_error(status::BadIdentityTokenRejected,
                          "a password in clear over an unencrypted channel");
    }
    password = token.password.bytes();
  } else {
    if (token.encryption_algorithm.view() != sec::encryption_algorithm_uri(protect)) {
      return status_error(
          status::BadIdentityTokenInvalid,
          fmt::format("password encrypted with '{}', the token policy needs '{}'",
                      token.encryption_algorithm.view(), sec::encryption_algorithm_uri(protect)));
    }
    auto secret = sec::decrypt_secret(protect, security.credentials.private_key, token.password.span(),
                                      session.server_nonce.span());
    if (!secret) {
      return secret.error();
    }
    password = std::move(*secret);
  }
  auto user =
      users->authenticate(token.user_name.view(),
                          std::string_view(reinterpret_cast<const char*>(password.data()), password.size()));
  std::fill(password.begin(), password.end(), 0);
  if (!user) {
    return user.error();
  }
  SessionIdentity identity;
  identity.token_type = UserTokenType::UserName;
  identity.policy_id = token.policy_id.str();
  identity.user_name = (*user)->name;
  identity.roles = (*user)->roles;
  return identity;
}

Result<SessionIdentity> certificate(const ServerSecurity& security,
                                    const std::vector<UserTokenPolicy>& policies, const ChannelInfo& channel,
                                    const Session& session, const X509IdentityToken& token,
                                    const SignatureData& signature, const Clock& clock) {
  const UserTokenPolicy* policy = find_token_policy(policies, token.policy_id, UserTokenType::Certificate);
  const auto users = security.current_users();
  if (policy == nullptr || !users) {
    return status_error(status::BadIdentityTokenRejected,
                        "certificate tokens are not accepted on this endpoint");
  }
  const std::string protect = token_policy(*policy, channel);
  if (policy_is_none(protect)) {
    return status_error(status::BadIdentityTokenRejected, "a certificate token needs a security policy");
  }
  // §7.40.5: the user proves the key with a signature over serverCertificate + serverNonce.
  const Bytes data = concat(security.credentials.certificate, session.server_nonce);
  if (auto st = sec::verify(protect, token.certificate_data, data, signature); !st) {
    return as(status::BadUserSignatureInvalid, st.error());
  }
  auto info = sec::inspect_certificate(token.certificate_data.span());
  if (!info) {
    return as(status::BadIdentityTokenInvalid, info.error());
  }
  const auto now = clock.utc_now();
  if (now < info->not_before || now > info->not_after) {
    return status_error(status::BadIdentityTokenRejected,
                        fmt::format("user certificate '{}' is outside its validity period", info->subject));
  }
  const sec::User* user = users->find_by_certificate(info->thumbprint);
  if (user == nullptr) {
    return status_error(status::BadUserAccessDenied, fmt::format("no user has the certificate '{}' ({})",
                                                                 info->subject, info->thumbprint));
  }
  SessionIdentity identity;
  identity.token_type = UserTokenType::Certificate;
  identity.policy_id = token.policy_id.str();
  identity.user_name = user->name;
  identity.certificate_thumbprint = info->thumbprint;
  identity.roles = user->roles;
  return identity;
}

Result<SessionIdentity> identify(const ServerSecurity& security, const ChannelInfo& channel,
                                 const Session& session, const ActivateSessionRequest& request,
                                 const Clock& clock) {
  const auto policies =
      user_token_policies(security, EndpointSecurity{policy_of(channel), channel.security_mode});
  const ExtensionObject& token = request.user_identity_token;
  if (token.empty()) {
    return anonymous(security, policies, String());  // §7.40: a null token means anonymous
  }
  if (const auto* t = token.get_if<AnonymousIdentityToken>()) {
    return anonymous(security, policies, t->policy_id);
  }
  if (const auto* t = token.get_if<UserNameIdentityToken>()) {
    return user_name(security, policies, channel, session, *t);
  }
  if (const auto* t = token.get_if<X509IdentityToken>()) {
    return certificate(security, policies, channel, session, *t, request.user_token_signature, clock);
  }
  if (token.get_if<IssuedIdentityToken>() != nullptr ||
      token.type_id() == NodeId(0, id::IssuedIdentityToken_Encoding_DefaultBinary)) {
    return status_error(status::BadIdentityTokenRejected, "issued identity tokens are not accepted");
  }
  return status_error(status::BadIdentityTokenInvalid, "the user identity token is not a known token type");
}

const sec::UserDatabase& builtin_roles() {
  static const sec::UserDatabase db;
  return db;
}

}  // namespace

Status check_endpoint(const ServerSecurity& security, const ChannelInfo& channel) {
  if (!security.offers(policy_of(channel), channel.security_mode)) {
    return status_error(status::BadSecurityPolicyRejected,
                        fmt::format("no endpoint with {} and {} (a None channel is for discovery only)",
                                    sec::policy_name(policy_of(channel)), to_string(channel.security_mode)));
  }
  return {};
}

Status secure_create_session(const ServerSecurity& security, const ChannelInfo& channel,
                             const CreateSessionRequest& request, Session& session,
                             CreateSessionResponse& response) {
  session.security_policy_uri = policy_of(channel);
  session.security_mode = channel.security_mode;
  if (!security.credentials.certificate.empty()) {
    response.server_certificate = security.credentials.certificate;
  }
  if (policy_is_none(session.security_policy_uri)) {
    return {};
  }
  auto requested = sec::leaf_certificate(request.client_certificate.span());
  auto of_channel = sec::leaf_certificate(channel.client_certificate.span());
  if (!requested || !of_channel || !(*requested == *of_channel)) {
    return status_error(status::BadCertificateInvalid, "the client certificate is not the secure channel's");
  }
  if (request.client_nonce.size() < kMinClientNonce) {
    return status_error(status::BadNonceInvalid, fmt::format("client nonce of {} bytes, at least {} needed",
                                                             request.client_nonce.size(), kMinClientNonce));
  }
  SF_TRY(sec::check_application_uri(*requested, request.client_description.application_uri.view()));
  auto signature = sec::sign(session.security_policy_uri, security.credentials.private_key,
                             concat(request.client_certificate, request.client_nonce));
  if (!signature) {
    return signature.error();
  }
  response.server_signature = std::move(*signature);
  session.client_certificate = std::move(*requested);
  return {};
}

Result<SessionIdentity> authenticate_activation(const ServerSecurity& security, const ChannelInfo& channel,
                                                const Session& session, const ActivateSessionRequest& request,
                                                const Clock& clock) {
  if (policy_of(channel) != session.security_policy_uri || channel.security_mode != session.security_mode) {
    return status_error(status::BadSecurityPolicyRejected,
                        "ActivateSession over a channel with other security than the session's");
  }
  if (!policy_is_none(session.security_policy_uri)) {
    // The client proves it holds the key of the certificate the session was created with.
    const Bytes data = concat(security.credentials.certificate, session.server_nonce);
    if (auto st = sec::verify(session.security_policy_uri, session.client_certificate, data,
                              request.client_signature);
        !st) {
      return as(status::BadApplicationSignatureInvalid, st.error());
    }
  }
  auto identity = identify(security, channel, session, request, clock);
  if (!identity) {
    log::get("opcua")->info("session {}: user refused: {}", to_string(session.session_id),
                            identity.error().message);
  }
  return identity;
}

std::shared_ptr<const UserContext> access_for(const ServerSecurity& security, const AddressSpace& space,
                                              const SessionIdentity& identity) {
  if (identity.token_type == UserTokenType::Anonymous && identity.roles.empty()) {
    return nullptr;
  }
  const auto users = security.current_users();
  const sec::UserDatabase& db = users ? *users : builtin_roles();
  std::vector<sec::Role> roles;
  for (const auto& name : identity.roles) {
    if (const sec::Role* role = db.role(name)) {
      roles.push_back(*role);
    }
  }
  return std::make_shared<RoleAccess>(space, std::move(roles));
}

}  // namespace sf::opcua::server::detail
