// The generated StatusCode and NodeId tables.
#include <gtest/gtest.h>

#include "sf/opcua/encoding.hpp"

namespace sf::opcua {
namespace {

TEST(StatusCodes, ConstantsCarryTheSpecValues) {
  EXPECT_EQ(status::Good.value(), 0x00000000U);
  EXPECT_EQ(status::BadDecodingError.value(), 0x80070000U);
  EXPECT_EQ(status::BadEncodingLimitsExceeded.value(), 0x80080000U);
  EXPECT_EQ(status::BadNodeIdUnknown.value(), 0x80340000U);
  EXPECT_EQ(status::BadTcpMessageTooLarge.value(), 0x80800000U);
  EXPECT_EQ(status::UncertainLastUsableValue.value(), 0x40900000U);
  EXPECT_EQ(status::GoodSubscriptionTransferred.value(), 0x002D0000U);
  EXPECT_EQ(status::BadDataSetIdInvalid.value(), 0x80E70000U);
}

TEST(StatusCodes, NamesAndDescriptionsLookUpByCode) {
  EXPECT_EQ(status::BadDecodingError.name(), "BadDecodingError");
  EXPECT_EQ(status::BadDecodingError.description(), "Decoding halted because of invalid data in the stream.");
  EXPECT_EQ(StatusCode{0x80070000}.name(), "BadDecodingError");
  EXPECT_EQ(status_code_from_name("BadSessionIdInvalid"), status::BadSessionIdInvalid);
  EXPECT_FALSE(status_code_from_name("BadNoSuchThing").has_value());
  EXPECT_TRUE(StatusCode{0x8FFF0000}.name().empty());
}

TEST(StatusCodes, SeverityAndInfoBits) {
  EXPECT_TRUE(status::Good.is_good());
  EXPECT_TRUE(status::GoodClamped.is_good());
  EXPECT_TRUE(status::UncertainInitialValue.is_uncertain());
  EXPECT_TRUE(status::BadTimeout.is_bad());
  EXPECT_FALSE(status::BadTimeout.is_good());
  // Info bits (the low 16) do not change the name, but show in the text.
  const StatusCode with_info{0x80070400};
  EXPECT_EQ(with_info.code(), 0x80070000U);
  EXPECT_EQ(with_info.name(), "BadDecodingError");
  EXPECT_EQ(to_string(with_info), "BadDecodingError (0x80070400)");
  EXPECT_EQ(to_string(StatusCode{0x8FFF0000}), "0x8FFF0000");
  EXPECT_EQ(to_string(status::Good), "Good");
}

TEST(StatusCodes, ErrorsRoundTripTheirStatusCode) {
  const Error e = status_error(status::BadTcpMessageTooLarge, "chunk of 70000 bytes");
  EXPECT_EQ(e.message, "BadTcpMessageTooLarge: chunk of 70000 bytes");
  EXPECT_EQ(e.code, Errc::limit_exceeded);
  EXPECT_EQ(status_of(e), status::BadTcpMessageTooLarge);
  // Errors from other modules map by their Errc; their text is never read for a code.
  EXPECT_EQ(status_of(Error{Errc::malformed, "x"}), status::BadDecodingError);
  EXPECT_EQ(status_of(Error{Errc::timeout, "x"}), status::BadTimeout);
  EXPECT_EQ(status_of(Error{Errc::remote, "BadNodeIdUnknown: only the text says so"}),
            status::BadUnexpectedError);
}

// The code is typed, so the context added on the way up does not lose it.
TEST(StatusCodes, ContextKeepsTheStatusCode) {
  const Error e =
      status_error(status::BadNodeIdUnknown, "ns=1;s=x").with_context("Read").with_context("plc7");
  EXPECT_EQ(status_of(e), status::BadNodeIdUnknown);
  EXPECT_EQ(e.message, "plc7: Read: BadNodeIdUnknown: ns=1;s=x");
}

TEST(NodeIds, NamesLookUpBothWays) {
  EXPECT_EQ(id::ObjectsFolder, 85U);
  EXPECT_EQ(id::ReadRequest_Encoding_DefaultBinary, 631U);
  EXPECT_EQ(id::Server_ServerStatus_CurrentTime, 2258U);
  EXPECT_EQ(id::BaseDataVariableType, 63U);
  EXPECT_EQ(node_id_name(631), "ReadRequest_Encoding_DefaultBinary");
  EXPECT_EQ(node_id_name(85), "ObjectsFolder");
  EXPECT_TRUE(node_id_name(999'999).empty());
  EXPECT_EQ(node_id_from_name("Server"), 2253U);
  EXPECT_FALSE(node_id_from_name("NoSuchNode").has_value());
}

}  // namespace
}  // namespace sf::opcua
