// Decoding hostile input: truncation, lengths beyond the input, limits, nesting depth and
// corrupted bytes must give the right Bad status with a message that says where.
#include <gtest/gtest.h>

#include "sf/opcua/encoding.hpp"
#include "test_util.hpp"

namespace sf::opcua {
namespace {

using test::encoded;
using test::hex;
using test::status_name;

PublishResponse sample_publish_response() {
  DataChangeNotification change;
  for (std::uint32_t handle = 1; handle <= 3; ++handle) {
    MonitoredItemNotification item;
    item.client_handle = handle;
    item.value = DataValue(Variant(Array<double>{1.5, 2.5}));
    item.value.source_timestamp = DateTime{133'000'000'000'000'000};
    change.monitored_items.push_back(item);
  }
  PublishResponse response;
  response.response_header.string_table = Array<String>{String("a"), String("bc")};
  response.subscription_id = 5;
  response.available_sequence_numbers = Array<std::uint32_t>{1, 2};
  response.notification_message.sequence_number = 2;
  response.notification_message.notification_data.push_back(ExtensionObject::make(change));
  response.results = Array<StatusCode>{StatusCode{}};
  DiagnosticInfo diag;
  diag.additional_info = String("x");
  diag.inner_diagnostic_info.emplace().symbolic_id = 1;
  response.diagnostic_infos.push_back(diag);
  return response;
}

TEST(HostileInput, EveryTruncationIsADecodingError) {
  const Bytes bytes = *encode_message(sample_publish_response());
  ASSERT_TRUE(decode_message(bytes).ok());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    auto message = decode_message(ByteSpan(bytes).first(n));
    ASSERT_FALSE(message.ok()) << "prefix of " << n << " bytes decoded";
    EXPECT_EQ(status_name(message.error()), "BadDecodingError") << n << ": " << message.error().message;
  }
}

TEST(HostileInput, CorruptedBytesNeverCrashAndFailWithABadStatus) {
  const Bytes original = *encode_message(sample_publish_response());
  std::size_t failures = 0;
  for (std::size_t i = 0; i < original.size(); ++i) {
    for (std::uint8_t flip : {std::uint8_t{0xFF}, std::uint8_t{0x80}, std::uint8_t{0x01}}) {
      Bytes bytes = original;
      bytes[i] = static_cast<std::uint8_t>(bytes[i] ^ flip);
      auto message = decode_message(bytes);
      if (!message.ok()) {
        ++failures;
        EXPECT_TRUE(status_of(message.error()).is_bad()) << message.error().message;
        EXPECT_FALSE(status_of(message.error()).name().empty()) << message.error().message;
      }
    }
  }
  EXPECT_GT(failures, original.size());  // most corruptions are detected
}

TEST(HostileInput, ArrayLengthBeyondTheInputFailsBeforeAllocating) {
  // ReadRequest with a default header, then nodesToRead claiming 100000 elements of at least 16
  // bytes each: rejected from the length alone.
  Bytes bytes = *encode_message(ReadRequest{});
  store_le<std::int32_t>(bytes.data() + bytes.size() - 4, 100'000);
  auto message = decode_message(bytes);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(status_name(message.error()), "BadDecodingError");
  EXPECT_NE(message.error().message.find(
                "ReadRequest.nodesToRead: array length 100000 needs at least 1600000 bytes but 0 remain"),
            std::string::npos)
      << message.error().message;
  EXPECT_EQ(status_name(test::decode_error<Variant>(hex("8b a0860100 00"))), "BadDecodingError");

  // Beyond the array limit the limit is reported, whatever the input holds.
  store_le<std::int32_t>(bytes.data() + bytes.size() - 4, 0x7FFFFFFF);
  auto huge = decode_message(bytes);
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(status_name(huge.error()), "BadEncodingLimitsExceeded");
  EXPECT_EQ(status_name(test::decode_error<Variant>(hex("8b ffffff7f 00"))), "BadEncodingLimitsExceeded");
}

TEST(HostileInput, ArrayLengthLimit) {
  ReadRequest request;
  request.nodes_to_read.resize(3);
  const Bytes bytes = *encode_message(request);
  DecodeOptions options;
  options.limits.max_array_length = 2;
  auto message = decode_message(bytes, options);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(status_of(message.error()), status::BadEncodingLimitsExceeded);
  EXPECT_NE(message.error().message.find("ReadRequest.nodesToRead: array length 3 exceeds the limit 2"),
            std::string::npos)
      << message.error().message;
  options.limits.max_array_length = 3;
  EXPECT_TRUE(decode_message(bytes, options).ok());
}

TEST(HostileInput, StringLimitInsideANestedStructure) {
  GetEndpointsResponse response;
  response.endpoints.resize(1);
  response.endpoints[0].server.application_uri = String(std::string(100, 'u'));
  const Bytes bytes = *encode_message(response);
  DecodeOptions options;
  options.limits.max_string_length = 99;
  auto message = decode_message(bytes, options);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(status_name(message.error()), "BadEncodingLimitsExceeded");
  EXPECT_NE(message.error().message.find("GetEndpointsResponse.endpoints[0].server.applicationUri"),
            std::string::npos)
      << message.error().message;
}

// `levels` Variants, each an array holding the next one, around a Null Variant.
Bytes nested_variant_arrays(std::size_t levels) {
  Bytes bytes;
  for (std::size_t i = 0; i < levels; ++i) {
    const Bytes level = hex("98 01000000");
    bytes.insert(bytes.end(), level.begin(), level.end());
  }
  bytes.push_back(0x00);
  return bytes;
}

TEST(HostileInput, VariantNestingStopsAtTheDepthLimit) {
  // The innermost Null Variant is level levels + 1; the default limit is 100 levels.
  EXPECT_TRUE(decode<Variant>(nested_variant_arrays(99)).ok());
  const Error deep = test::decode_error<Variant>(nested_variant_arrays(100));
  EXPECT_EQ(status_name(deep), "BadEncodingLimitsExceeded");
  EXPECT_NE(deep.message.find("Variant nested deeper than the limit of 100 levels"), std::string::npos)
      << deep.message;
  // A deep enough input to overflow the stack without the limit.
  EXPECT_EQ(status_name(test::decode_error<Variant>(nested_variant_arrays(100'000))),
            "BadEncodingLimitsExceeded");

  DecodeOptions options;
  options.limits.max_depth = 3;
  EXPECT_TRUE(decode<Variant>(nested_variant_arrays(2), options).ok());
  EXPECT_EQ(status_name(test::decode_error<Variant>(nested_variant_arrays(3), options)),
            "BadEncodingLimitsExceeded");
}

// A ContentFilterElement whose operand is a LiteralOperand holding the next element, `levels`
// deep: structures nested through ExtensionObject and Variant.
ContentFilterElement nested_filter(std::size_t levels) {
  ContentFilterElement element;
  element.filter_operator = FilterOperator::Not;
  for (std::size_t i = 0; i < levels; ++i) {
    LiteralOperand literal;
    literal.value = Variant(ExtensionObject::make(element));
    ContentFilterElement outer;
    outer.filter_operator = FilterOperator::Not;
    outer.filter_operands.push_back(ExtensionObject::make(literal));
    element = outer;
  }
  return element;
}

TEST(HostileInput, ExtensionObjectNestingCountsTowardsTheDepthLimit) {
  // Each level costs three: the operand's ExtensionObject, the Variant and its ExtensionObject.
  EXPECT_TRUE(decode<ContentFilterElement>(encoded(nested_filter(30))).ok());

  ByteWriter w;
  Encoder deep_encoder(w, 1000);
  encode_binary(deep_encoder, nested_filter(40));
  ASSERT_TRUE(deep_encoder.ok());
  const Error e = test::decode_error<ContentFilterElement>(w.data());
  EXPECT_EQ(status_name(e), "BadEncodingLimitsExceeded");
  EXPECT_NE(e.message.find("ContentFilterElement.filterOperands[0]{LiteralOperand}.value{ExtensionObject}"),
            std::string::npos)
      << e.message;

  // The encoder refuses to write what the decoder would refuse to read.
  auto refused = encode(nested_filter(40));
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(status_name(refused.error()), "BadEncodingLimitsExceeded");
}

TEST(HostileInput, NegativeLengthsOtherThanNullAreRejected) {
  ReadRequest request;
  Bytes bytes = *encode_message(request);
  store_le<std::int32_t>(bytes.data() + bytes.size() - 4, -2);
  auto message = decode_message(bytes);
  ASSERT_FALSE(message.ok());
  EXPECT_EQ(status_name(message.error()), "BadDecodingError");
  EXPECT_NE(message.error().message.find("array length -2 is negative"), std::string::npos)
      << message.error().message;
}

TEST(HostileInput, ErrorsCarryStatusCodeAndOffset) {
  const Error e = test::decode_error<QualifiedName>(hex("0100 05000000 6162"));
  EXPECT_EQ(status_of(e), status::BadDecodingError);
  EXPECT_EQ(e.code, Errc::malformed);
  EXPECT_NE(e.message.find("(offset 6)"), std::string::npos) << e.message;
  const Error limit = status_error(status::BadEncodingLimitsExceeded, "x");
  EXPECT_EQ(limit.code, Errc::limit_exceeded);
  EXPECT_EQ(status_of(limit), status::BadEncodingLimitsExceeded);
}

}  // namespace
}  // namespace sf::opcua
