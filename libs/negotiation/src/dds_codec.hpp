// Conversions between the C++ messages and the idlc-generated C types of
// idl/cnp_messages.idl. Encoding checks every bound (a too-long name is an
// error, not a truncation); decoding never trusts a sample: strings are read
// up to their array bound, sequence lengths are checked, an unknown union
// discriminant is an error, and so is a key hash that does not match its string.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "cnp_messages.h"
#include "sf/core/result.hpp"
#include "sf/negotiation/messages.hpp"

namespace sf::negotiation::codec {

// Storage the encoded samples' sequences point into; keep it alive until written.
using ParamStorage = std::vector<sf_cnp_Param>;

Result<sf_cnp_Announce> encode(const Announce& m, ParamStorage& storage);
Result<sf_cnp_ContractorMessage> encode(const ContractorMessage& m, ParamStorage& storage);
Result<sf_cnp_ManagerMessage> encode(const ManagerMessage& m, ParamStorage& storage);
Result<sf_cnp_TransportRequest> encode(const TransportRequest& m);
Result<sf_cnp_TransportInform> encode(const TransportInform& m);

Result<Announce> decode(const sf_cnp_Announce& s);
Result<ContractorMessage> decode(const sf_cnp_ContractorMessage& s);
Result<ManagerMessage> decode(const sf_cnp_ManagerMessage& s);
Result<TransportRequest> decode(const sf_cnp_TransportRequest& s);
Result<TransportInform> decode(const sf_cnp_TransportInform& s);

// Whether a manager message (AWARD, DIRECTEDAWARD, CANCEL) is addressed to `contractor`; read
// up to the name's bound, as decoding does. Cheap: it runs in Cyclone's content filter.
bool addressed_to(const sf_cnp_ManagerMessage& s, std::string_view contractor);

// The IDL's KeyHash: FNV-1a 64 of the bytes of a conversation id, contractor or conveyor name.
std::uint64_t key_hash(std::string_view text);

// Key-only samples (for dispose / unregister).
sf_cnp_Announce announce_key(const std::string& conversation);
sf_cnp_ManagerMessage manager_key(const std::string& conversation);
sf_cnp_ContractorMessage contractor_key(const std::string& conversation, const std::string& contractor);
sf_cnp_TransportRequest request_key(const std::string& conversation);
sf_cnp_TransportInform inform_key(const std::string& conversation, const std::string& conveyor);

}  // namespace sf::negotiation::codec
