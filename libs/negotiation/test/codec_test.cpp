// The IDL codec: every message kind survives a round trip; bounds are
// enforced on encoding; malformed samples are refused on decoding; instance
// keys are the FNV-1a hashes of the strings they stand for.
#include "dds_codec.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;

const UtcTime kT{std::chrono::seconds{1'700'000'000} + 123456789ns};

TEST(Codec, AnnounceRoundTrip) {
  const Announce a{"P1/OP1/ab.1", "P1", "OP1", 3, {{"mass", 1.5}, {"colour", 2.0}}, kT};
  codec::ParamStorage storage;
  auto s = codec::encode(a, storage);
  ASSERT_TRUE(s.ok()) << s.error().describe();
  auto back = codec::decode(*s);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->conversation, a.conversation);
  EXPECT_EQ(back->product, "P1");
  EXPECT_EQ(back->operation, "OP1");
  EXPECT_EQ(back->round, 3U);
  EXPECT_EQ(back->params, a.params);
  EXPECT_EQ(back->bid_deadline, kT);
}

TEST(Codec, EveryContractorMessageKindRoundTrips) {
  const std::vector<ContractorBody> bodies{Bid{kT, kT + 5s, 2.5, 4}, Refuse{0, "busy"}, Confirm{2},
                                           InformDone{2, "done"}, Failure{2, "jammed"}};
  codec::ParamStorage storage;
  for (const auto& body : bodies) {
    const ContractorMessage m{"c", "M1", "OP2", 7, body};
    auto s = codec::encode(m, storage);
    ASSERT_TRUE(s.ok());
    auto back = codec::decode(*s);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(describe(*back), describe(m));
    EXPECT_EQ(back->body.index(), body.index());
  }
  auto bid = codec::decode(
      *codec::encode(ContractorMessage{"c", "M1", "OP2", 1, Bid{kT, kT + 5s, 2.5, 4}}, storage));
  const auto& b = std::get<Bid>(bid->body);
  EXPECT_EQ(b.estimated_start, kT);
  EXPECT_EQ(b.estimated_finish, kT + 5s);
  EXPECT_DOUBLE_EQ(b.cost, 2.5);
  EXPECT_EQ(b.queue_length, 4U);
  auto refuse =
      codec::decode(*codec::encode(ContractorMessage{"c", "M1", "OP2", 1, Refuse{3, "queue full"}}, storage));
  EXPECT_EQ(std::get<Refuse>(refuse->body).reason, "queue full");
  EXPECT_EQ(std::get<Refuse>(refuse->body).award_id, 3U);
  const InformDone uploaded{1, "box 7 at conveyor1/upload", {{"box", 7}, {"weight_g", 40.5}}};
  auto done = codec::decode(*codec::encode(ContractorMessage{"c", "M1", "OP2", 1, uploaded}, storage));
  ASSERT_TRUE(done.ok()) << done.error().describe();
  EXPECT_EQ(std::get<InformDone>(done->body).results, uploaded.results);
  const std::vector<Param> nine(kMaxParams + 1, Param{"x", 1.0});
  EXPECT_FALSE(codec::encode(ContractorMessage{"c", "M1", "OP2", 1, InformDone{1, "", nine}}, storage));
}

TEST(Codec, EveryManagerMessageKindRoundTrips) {
  codec::ParamStorage storage;
  const ManagerMessage d{"c", "P1", "OP1", "M3", 0, DirectedAward{1, kT, {{"x", 1.0}}}};
  auto back = codec::decode(*codec::encode(d, storage));
  ASSERT_TRUE(back.ok());
  const auto& da = std::get<DirectedAward>(back->body);
  EXPECT_EQ(da.award_id, 1U);
  EXPECT_EQ(da.confirm_by, kT);
  EXPECT_EQ(da.params, (std::vector<Param>{{"x", 1.0}}));
  EXPECT_EQ(back->contractor, "M3");
  auto award =
      codec::decode(*codec::encode(ManagerMessage{"c", "P1", "OP1", "M3", 2, Award{4, kT}}, storage));
  EXPECT_EQ(std::get<Award>(award->body).award_id, 4U);
  EXPECT_EQ(award->round, 2U);
  auto cancel =
      codec::decode(*codec::encode(ManagerMessage{"c", "P1", "OP1", "M3", 2, Cancel{4, "late"}}, storage));
  EXPECT_EQ(std::get<Cancel>(cancel->body).reason, "late");
}

// The machines' AWARD filter: the whole name, read no further than its bound.
TEST(Codec, AManagerMessageIsAddressedToItsContractorOnly) {
  codec::ParamStorage storage;
  auto s = *codec::encode(ManagerMessage{"c", "P1", "OP1", "M1", 1, Award{1, kT}}, storage);
  EXPECT_TRUE(codec::addressed_to(s, "M1"));
  EXPECT_FALSE(codec::addressed_to(s, "M10"));
  EXPECT_FALSE(codec::addressed_to(s, "M"));
  EXPECT_FALSE(codec::addressed_to(s, ""));
  std::memset(s.contractor, 'm', sizeof(s.contractor));  // no terminating NUL
  EXPECT_TRUE(codec::addressed_to(s, std::string(sizeof(s.contractor), 'm')));
  EXPECT_FALSE(codec::addressed_to(s, std::string(sizeof(s.contractor) + 1, 'm')));
}

TEST(Codec, TransportMessagesRoundTrip) {
  auto r = codec::decode(*codec::encode(TransportRequest{"r", "P1", "Input", "M2", kT}));
  EXPECT_EQ(r->from, "Input");
  EXPECT_EQ(r->to, "M2");
  EXPECT_EQ(r->earliest_start, kT);
  auto i = codec::decode(
      *codec::encode(TransportInform{"r", "C1", "conveyor1/upload", "conveyor3", 1500ms, kT, 2}));
  EXPECT_EQ(i->conveyor, "C1");
  EXPECT_EQ(i->from, "conveyor1/upload");
  EXPECT_EQ(i->transit_time, 1500ms);
  EXPECT_EQ(i->eta, kT);
  EXPECT_EQ(i->hops, 2U);
  auto none = *codec::encode(TransportInform{"r", "C1", "A", "B", 1s, kT});
  none.hops = 0;  // an INFORM is a segment: a count of none is a peer's bug
  EXPECT_FALSE(codec::decode(none).ok());
}

TEST(Codec, EncodingRefusesWhatDoesNotFitTheBounds) {
  codec::ParamStorage storage;
  const std::string long_name(32, 'x');
  auto e = codec::encode(ContractorMessage{"c", long_name, "OP1", 1, Confirm{1}}, storage);
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().code, Errc::limit_exceeded);
  EXPECT_FALSE(codec::encode(Announce{std::string(64, 'c'), "P", "OP1", 1, {}, kT}, storage).ok());
  EXPECT_FALSE(codec::encode(Announce{"c", "P", "OP1", 1, std::vector<Param>(9), kT}, storage).ok());
  EXPECT_FALSE(
      codec::encode(ContractorMessage{"c", "M", "OP1", 1, Failure{1, std::string(96, 'r')}}, storage).ok());
  EXPECT_TRUE(
      codec::encode(ContractorMessage{"c", std::string(31, 'x'), "OP1", 1, Confirm{1}}, storage).ok());
}

TEST(Codec, DecodingRefusesMalformedSamples) {
  codec::ParamStorage storage;
  auto s = *codec::encode(ContractorMessage{"c", "M1", "OP1", 1, Confirm{1}}, storage);
  s.body._d = static_cast<sf_cnp_ContractorKind>(7);
  auto m = codec::decode(s);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, Errc::malformed);

  auto a = *codec::encode(Announce{"c", "P", "OP1", 1, {{"p", 1.0}}, kT}, storage);
  a.params._length = 1000;  // more than the bound and than the buffer
  EXPECT_FALSE(codec::decode(a).ok());
  a.params._length = 1;
  a.params._buffer = nullptr;
  EXPECT_FALSE(codec::decode(a).ok());

  // A string without its terminating NUL is read up to the array bound only.
  auto t = *codec::encode(TransportRequest{"r", "P1", "A", "B", kT});
  std::memset(t.from, 'z', sizeof(t.from));
  auto r = codec::decode(t);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->from, std::string(sizeof(t.from), 'z'));
}

// Test vectors of the FNV specification (FNV-1a, 64 bit).
TEST(Codec, KeyHashIsFnv1a64) {
  EXPECT_EQ(codec::key_hash(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(codec::key_hash("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(codec::key_hash("foobar"), 0x85944171f73967e8ULL);
}

TEST(Codec, KeysAreTheHashesOfTheirStrings) {
  codec::ParamStorage storage;
  const auto a = *codec::encode(Announce{"P1/OP1/ab.1", "P1", "OP1", 1, {}, kT}, storage);
  EXPECT_EQ(a.conversation_hash, codec::key_hash("P1/OP1/ab.1"));
  EXPECT_EQ(codec::announce_key("P1/OP1/ab.1").conversation_hash, a.conversation_hash);
  const auto b = *codec::encode(ContractorMessage{"c", "M1", "OP1", 1, Confirm{1}}, storage);
  EXPECT_EQ(b.conversation_hash, codec::key_hash("c"));
  EXPECT_EQ(b.contractor_hash, codec::key_hash("M1"));
  const auto k = codec::contractor_key("c", "M1");
  EXPECT_EQ(std::make_pair(k.conversation_hash, k.contractor_hash),
            std::make_pair(b.conversation_hash, b.contractor_hash));
  const auto i = *codec::encode(TransportInform{"r", "C1", "A", "B", 1s, kT});
  EXPECT_EQ(i.conveyor_hash, codec::key_hash("C1"));
  EXPECT_EQ(codec::inform_key("r", "C1").conveyor_hash, i.conveyor_hash);
  EXPECT_EQ(codec::manager_key("x").conversation_hash, codec::key_hash("x"));
  EXPECT_EQ(codec::request_key("x").conversation_hash, codec::key_hash("x"));
}

// A hash that is not its string's would put the sample in another conversation's instance.
TEST(Codec, DecodingRefusesAKeyHashThatIsNotItsStrings) {
  codec::ParamStorage storage;
  auto b = *codec::encode(ContractorMessage{"c", "M1", "OP1", 1, Confirm{1}}, storage);
  b.contractor_hash ^= 1;
  auto m = codec::decode(b);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().code, Errc::malformed);
  auto a = *codec::encode(Announce{"c", "P", "OP1", 1, {}, kT}, storage);
  a.conversation_hash = codec::key_hash("d");
  EXPECT_FALSE(codec::decode(a).ok());
  auto w = *codec::encode(ManagerMessage{"c", "P", "OP1", "M1", 1, Award{1, kT}}, storage);
  w.conversation_hash = 0;
  EXPECT_FALSE(codec::decode(w).ok());
  auto r = *codec::encode(TransportRequest{"r", "P1", "A", "B", kT});
  r.conversation_hash = 0;
  EXPECT_FALSE(codec::decode(r).ok());
  auto i = *codec::encode(TransportInform{"r", "C1", "A", "B", 1s, kT});
  i.conveyor_hash = 0;
  EXPECT_FALSE(codec::decode(i).ok());
}

}  // namespace
}  // namespace sf::negotiation
