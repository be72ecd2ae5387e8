// Every structure generated from schema/types.txt: default and populated round trips, inside
// ExtensionObjects, and the service-message envelope.
#include <tuple>
#include <type_traits>

#include <gtest/gtest.h>

#include "sf/opcua/encoding.hpp"
#include "test_util.hpp"

namespace sf::opcua {
namespace {

using test::encoded;
using test::hex;
using test::round_trip;
using test::status_name;

// Fills every field with a distinct non-default value (arrays get two elements, nested
// structures are filled recursively), so that a field the codec skipped or swapped shows up.
class Populator {
 public:
  template <typename T>
  void fill(T& v) {
    ++seed_;
    if constexpr (std::is_same_v<T, bool>) {
      v = true;
    } else if constexpr (std::is_enum_v<T>) {
      v = static_cast<T>(1 + seed_ % 2);
    } else if constexpr (std::is_arithmetic_v<T>) {
      v = static_cast<T>(seed_);
    } else if constexpr (std::is_same_v<T, String>) {
      v = String("s" + std::to_string(seed_));
    } else if constexpr (std::is_same_v<T, ByteString>) {
      v = ByteString{static_cast<std::uint8_t>(seed_), 0xAB};
    } else if constexpr (std::is_same_v<T, XmlElement>) {
      v = XmlElement{String("<x/>")};
    } else if constexpr (std::is_same_v<T, DateTime>) {
      v = DateTime{133'000'000'000'000'000 + seed_};
    } else if constexpr (std::is_same_v<T, Guid>) {
      v = Guid{static_cast<std::uint32_t>(seed_), 2, 3, {4, 5, 6, 7, 8, 9, 10, 11}};
    } else if constexpr (std::is_same_v<T, NodeId>) {
      v = NodeId(2, String("node" + std::to_string(seed_)));
    } else if constexpr (std::is_same_v<T, ExpandedNodeId>) {
      v.node_id.namespace_index = 3;
      v.node_id.identifier.template emplace<std::uint32_t>(static_cast<std::uint32_t>(seed_));
      v.namespace_uri = String("urn:x");
      v.server_index = 1;
    } else if constexpr (std::is_same_v<T, StatusCode>) {
      v = StatusCode{0x80340000};
    } else if constexpr (std::is_same_v<T, QualifiedName>) {
      v = QualifiedName(1, String("q" + std::to_string(seed_)));
    } else if constexpr (std::is_same_v<T, LocalizedText>) {
      v = LocalizedText(String("en"), String("t" + std::to_string(seed_)));
    } else if constexpr (std::is_same_v<T, Variant>) {
      v = Variant(Array<std::int32_t>{static_cast<std::int32_t>(seed_), -1});
    } else if constexpr (std::is_same_v<T, DataValue>) {
      v = DataValue(Variant(static_cast<double>(seed_)));
      v.status = StatusCode{0x40900000};
      v.source_timestamp = DateTime{seed_};
      v.server_picoseconds = 5;
    } else if constexpr (std::is_same_v<T, DiagnosticInfo>) {
      v.symbolic_id = static_cast<std::int32_t>(seed_);
      v.additional_info = String("diag");
      v.inner_diagnostic_info.emplace().locale = 1;
    } else if constexpr (std::is_same_v<T, ExtensionObject>) {
      ReadValueId id;
      id.node_id = NodeId(0, static_cast<std::uint32_t>(seed_));
      id.attribute_id = 13;
      v = ExtensionObject::make(id);
    } else if constexpr (requires {
                           v.is_null();
                           v.resize(2);
                         }) {
      v.resize(2);
      for (auto& element : v) {
        fill(element);
      }
    } else {
      visit_fields(v, [this](std::string_view, auto& field) { fill(field); });
    }
  }

 private:
  std::int64_t seed_ = 0;
};

template <typename T>
T populated() {
  T value{};
  Populator{}.fill(value);
  return value;
}

template <typename F, typename... T>
void for_each_type(std::tuple<T...>* /*types*/, F&& f) {
  (f(static_cast<T*>(nullptr)), ...);
}

template <typename F>
void for_each_structure(F&& f) {
  for_each_type(static_cast<AllStructures*>(nullptr), std::forward<F>(f));
}

TEST(GeneratedStructures, DefaultValuesRoundTripAtTheirMinimalSize) {
  for_each_structure([](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    const T value{};
    const Bytes bytes = encoded(value);
    // A default structure holds only null strings, empty arrays and short NodeIds: exactly the
    // minimal size the decoder uses to bound array lengths.
    EXPECT_EQ(bytes.size(), T::kMinEncodedSize) << T::kTypeName;
    EXPECT_EQ(round_trip(value), value) << T::kTypeName;
  });
}

TEST(GeneratedStructures, PopulatedValuesRoundTrip) {
  for_each_structure([](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    const T value = populated<T>();
    EXPECT_NE(value, T{}) << T::kTypeName;
    const Bytes bytes = encoded(value);
    EXPECT_GE(bytes.size(), T::kMinEncodedSize) << T::kTypeName;
    EXPECT_EQ(round_trip(value), value) << T::kTypeName << ": " << to_string(value);
  });
}

TEST(GeneratedStructures, DecodingIntoAReusedValueOverwritesEveryField) {
  for_each_structure([](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    T reused = populated<T>();
    // A value with null arrays and strings where `reused` has contents, and the other way round.
    T other{};
    visit_fields(other, [](std::string_view, auto& field) {
      if constexpr (requires {
                      field.set_null();
                      field.begin();
                    }) {
        field.set_null();
      }
    });
    for (const T& next : {other, T{}, populated<T>()}) {
      const Bytes bytes = encoded(next);
      ByteReader reader(bytes);
      ASSERT_TRUE(decode(reader, reused).ok()) << T::kTypeName;
      EXPECT_EQ(reused, next) << T::kTypeName;
    }
  });
}

TEST(GeneratedStructures, EveryStructureTravelsInAnExtensionObject) {
  EXPECT_EQ(ExtensionRegistry::standard().size(), std::tuple_size_v<AllStructures>);
  for_each_structure([](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    const T value = populated<T>();
    const ExtensionObject back = round_trip(ExtensionObject::make(value));
    ASSERT_NE(back.get_if<T>(), nullptr) << T::kTypeName;
    EXPECT_EQ(*back.get_if<T>(), value) << T::kTypeName;
    EXPECT_EQ(back.type_id(), NodeId(0, T::kBinaryEncodingId));
  });
}

TEST(GeneratedStructures, EncodingIdsAreTheSpecsDefaultBinaryIds) {
  // OPC 10000-6 Annex A / NodeIds.csv: <Type>_Encoding_DefaultBinary.
  EXPECT_EQ(ReadRequest::kBinaryEncodingId, 631U);
  EXPECT_EQ(ReadResponse::kBinaryEncodingId, 634U);
  EXPECT_EQ(ReadValueId::kBinaryEncodingId, 628U);
  EXPECT_EQ(BrowseRequest::kBinaryEncodingId, 527U);
  EXPECT_EQ(CreateSubscriptionRequest::kBinaryEncodingId, 787U);
  EXPECT_EQ(PublishResponse::kBinaryEncodingId, 829U);
  EXPECT_EQ(ServiceFault::kBinaryEncodingId, 397U);
  EXPECT_EQ(OpenSecureChannelRequest::kBinaryEncodingId, 446U);
  EXPECT_EQ(CloseSecureChannelRequest::kBinaryEncodingId, 452U);
  EXPECT_EQ(GetEndpointsRequest::kBinaryEncodingId, 428U);
  EXPECT_EQ(CreateSessionRequest::kBinaryEncodingId, 461U);
  EXPECT_EQ(ActivateSessionRequest::kBinaryEncodingId, 467U);
  EXPECT_EQ(AnonymousIdentityToken::kBinaryEncodingId, 321U);
  EXPECT_EQ(UserNameIdentityToken::kBinaryEncodingId, 324U);
  EXPECT_EQ(X509IdentityToken::kBinaryEncodingId, 327U);
  EXPECT_EQ(DataChangeFilter::kBinaryEncodingId, 724U);
  EXPECT_EQ(EventFilter::kBinaryEncodingId, 727U);
  EXPECT_EQ(DataChangeNotification::kBinaryEncodingId, 811U);
  EXPECT_EQ(EventNotificationList::kBinaryEncodingId, 916U);
  EXPECT_EQ(StatusChangeNotification::kBinaryEncodingId, 820U);
  EXPECT_EQ(ReadRawModifiedDetails::kBinaryEncodingId, 649U);
  EXPECT_EQ(HistoryData::kBinaryEncodingId, 658U);
  EXPECT_EQ(ServerStatusDataType::kBinaryEncodingId, 864U);
  EXPECT_EQ(Range::kBinaryEncodingId, 886U);
  EXPECT_EQ(EUInformation::kBinaryEncodingId, 889U);
  EXPECT_EQ(ReadRequest::kTypeId, 629U);
  EXPECT_EQ(id::Server, 2253U);
  EXPECT_EQ(id::HasComponent, 47U);
}

TEST(GeneratedStructures, FieldsAreEncodedInSchemaOrder) {
  ReadValueId r;
  r.node_id = NodeId(0, 2258U);
  r.attribute_id = 13;
  r.data_encoding = QualifiedName(0, String("Default Binary"));
  EXPECT_EQ(encoded(r), hex("01 00 d208 0d000000 ffffffff 0000 0e000000 44656661756c742042696e617279"));
  EXPECT_EQ(to_string(r),
            "ReadValueId{nodeId=i=2258, attributeId=13, indexRange=null, dataEncoding=Default Binary}");
}

TEST(GeneratedEnums, HaveNamesAndKeepUnknownValues) {
  EXPECT_EQ(to_string(NodeClass::Variable), "Variable");
  EXPECT_EQ(to_string(static_cast<NodeClass>(3)), "NodeClass(3)");
  EXPECT_EQ(to_string(TimestampsToReturn::Both), "Both");
  EXPECT_EQ(static_cast<std::int32_t>(MessageSecurityMode::SignAndEncrypt), 3);
  EXPECT_EQ(static_cast<std::int32_t>(ServerState::CommunicationFault), 6);
  EXPECT_EQ(encoded(BrowseDirection::Inverse), hex("01000000"));
  auto unknown = decode<NodeClass>(hex("03000000"));
  ASSERT_TRUE(unknown.ok());
  EXPECT_EQ(static_cast<std::int32_t>(*unknown), 3);
}

// ---- Service messages (OPC 10000-6 §5.2.9) ----------------------------------------------------

template <typename F, typename... T>
void for_each_alternative(std::variant<T...>* /*types*/, F&& f) {
  (f(static_cast<T*>(nullptr)), ...);
}

TEST(ServiceMessages, EveryMessageRoundTripsThroughTheEnvelope) {
  EXPECT_EQ(std::variant_size_v<Message>, 53U);
  for_each_alternative(static_cast<Message*>(nullptr), [](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    const T value = populated<T>();
    auto bytes = encode_message(value);
    ASSERT_TRUE(bytes.ok()) << T::kTypeName;
    // The envelope starts with the encoding NodeId, here always in the four-byte form.
    ASSERT_GE(bytes->size(), 4U);
    EXPECT_EQ((*bytes)[0], 0x01);
    EXPECT_EQ(load_le<std::uint16_t>(bytes->data() + 2), T::kBinaryEncodingId);
    auto message = decode_message(*bytes);
    ASSERT_TRUE(message.ok()) << T::kTypeName << ": " << message.error().describe();
    ASSERT_TRUE(std::holds_alternative<T>(*message)) << message_type_name(*message);
    EXPECT_EQ(std::get<T>(*message), value);
    EXPECT_EQ(message_type_name(*message), T::kTypeName);
    auto again = encode_message(*message);
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(*again, *bytes);
  });
}

TEST(ServiceMessages, AppendToAnExistingBuffer) {
  Bytes buffer = {0xAA, 0xBB};
  ByteWriter writer(buffer);
  CloseSessionRequest request;
  request.delete_subscriptions = true;
  ASSERT_TRUE(encode_message(request, writer).ok());
  EXPECT_EQ(buffer[0], 0xAA);
  EXPECT_EQ(Bytes(buffer.begin() + 2, buffer.begin() + 6), hex("0100d901"));  // i=473
  auto back = decode_message(ByteSpan(buffer).subspan(2));
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(std::get<CloseSessionRequest>(*back).delete_subscriptions);
}

TEST(ServiceMessages, UnknownTypeIdsAreNamed) {
  auto structure = decode_message(hex("01 00 7402"));  // ReadValueId: a structure, not a message
  ASSERT_FALSE(structure.ok());
  EXPECT_EQ(status_name(structure.error()), "BadDataTypeIdUnknown");
  EXPECT_NE(structure.error().message.find("i=628 (ReadValueId_Encoding_DefaultBinary)"), std::string::npos)
      << structure.error().message;

  auto foreign = decode_message(hex("03 0500 01000000 78"));
  ASSERT_FALSE(foreign.ok());
  EXPECT_EQ(status_name(foreign.error()), "BadDataTypeIdUnknown");
  EXPECT_NE(foreign.error().message.find("ns=5;s=x"), std::string::npos) << foreign.error().message;

  auto empty = decode_message({});
  ASSERT_FALSE(empty.ok());
  EXPECT_EQ(status_name(empty.error()), "BadDecodingError");
}

TEST(ServiceMessages, TrailingBytesAreADecodingError) {
  Bytes bytes = *encode_message(CloseSessionRequest{});
  bytes.push_back(0);
  auto message = decode_message(bytes);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(status_name(message.error()), "BadDecodingError");
  EXPECT_NE(message.error().message.find("1 trailing byte(s) after the CloseSessionRequest"),
            std::string::npos)
      << message.error().message;
}

TEST(ServiceMessages, ErrorsNameTheFieldPath) {
  ReadRequest request;
  request.nodes_to_read.resize(3);
  request.nodes_to_read[2].index_range = String("1:2");
  Bytes bytes = *encode_message(request);
  // Corrupt the length of nodesToRead[2].indexRange: it precedes "1:2" and the 6-byte dataEncoding.
  const std::size_t at = bytes.size() - 6 - 4 - 3;
  store_le<std::int32_t>(bytes.data() + at, 1000);
  auto message = decode_message(bytes);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(status_of(message.error()), status::BadDecodingError);
  EXPECT_NE(message.error().message.find("ReadRequest.nodesToRead[2].indexRange: String length 1000"),
            std::string::npos)
      << message.error().message;
}

}  // namespace
}  // namespace sf::opcua
