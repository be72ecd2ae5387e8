#include <gtest/gtest.h>

#include "dds_test_support.hpp"

namespace sf::dds {
namespace {

using namespace std::chrono_literals;

TEST(QosBuilder, EveryPolicyReadsBackAsSet) {
  const Qos qos = QosBuilder{}
                      .reliable(250ms)
                      .durability(Durability::TransientLocal)
                      .deadline(2s)
                      .liveliness(Liveliness::Automatic, 1500ms)
                      .keep_last(8)
                      .partition("line-1")
                      .entity_name("M1")
                      .user_data("machine")
                      .build();
  const QosSettings s = read_settings(qos);
  EXPECT_EQ(s.reliability, Reliability::Reliable);
  EXPECT_EQ(s.max_blocking_time, std::chrono::nanoseconds{250ms});
  EXPECT_EQ(s.durability, Durability::TransientLocal);
  EXPECT_EQ(s.deadline, std::chrono::nanoseconds{2s});
  EXPECT_EQ(s.liveliness, Liveliness::Automatic);
  EXPECT_EQ(s.lease_duration, std::chrono::nanoseconds{1500ms});
  EXPECT_EQ(s.history, History::KeepLast);
  EXPECT_EQ(s.history_depth, 8);
  ASSERT_TRUE(s.partitions.has_value());
  EXPECT_EQ(*s.partitions, std::vector<std::string>{"line-1"});
  EXPECT_EQ(s.entity_name, "M1");
  EXPECT_EQ(s.user_data, "machine");
}

TEST(QosBuilder, UnsetPoliciesStayUnsetAndInfiniteRoundTrips) {
  const QosSettings s = read_settings(QosBuilder{}.best_effort().keep_all().deadline(kInfinite).build());
  EXPECT_EQ(s.reliability, Reliability::BestEffort);
  EXPECT_EQ(s.history, History::KeepAll);
  EXPECT_EQ(s.deadline, kInfinite);
  EXPECT_FALSE(s.durability.has_value());
  EXPECT_FALSE(s.liveliness.has_value());
  EXPECT_FALSE(s.partitions.has_value());
}

TEST(QosBuilder, CopiesAreIndependent) {
  Qos a = QosBuilder{}.keep_last(3).build();
  Qos b = a;
  dds_qset_history(b.get(), DDS_HISTORY_KEEP_LAST, 9);
  EXPECT_EQ(read_settings(a).history_depth, 3);
  EXPECT_EQ(read_settings(b).history_depth, 9);
}

TEST(CycloneConfig, LoopbackUsesLoWithoutMulticastAndUnicastPeers) {
  auto xml = cyclone_config_xml(loopback_network());
  ASSERT_TRUE(xml.ok()) << xml.error().describe();
  EXPECT_NE(xml->find("<NetworkInterface name=\"lo\"/>"), std::string::npos);
  EXPECT_NE(xml->find("<AllowMulticast>false</AllowMulticast>"), std::string::npos);
  EXPECT_NE(xml->find("<Peer address=\"127.0.0.1\"/>"), std::string::npos);
  EXPECT_NE(xml->find("<MaxAutoParticipantIndex>119</MaxAutoParticipantIndex>"), std::string::npos);
  // Writer flushes every write; end_instances flushes once for many (end_instances_test.cpp).
  EXPECT_NE(xml->find("<WriteBatch>true</WriteBatch>"), std::string::npos);
  auto unbatched = loopback_network();
  unbatched.write_batch = false;
  EXPECT_NE(cyclone_config_xml(unbatched)->find("<WriteBatch>false</WriteBatch>"), std::string::npos);
  EXPECT_EQ(xml->find("HeartbeatInterval"), std::string::npos);  // Cyclone's default
}

TEST(CycloneConfig, HeartbeatIntervalIsItsValueAndItsUpperBound) {
  auto c = loopback_network();
  c.heartbeat_interval = std::chrono::minutes{2};
  auto xml = cyclone_config_xml(c);
  ASSERT_TRUE(xml.ok()) << xml.error().describe();
  EXPECT_NE(xml->find("<Internal><WriteBatch>true</WriteBatch>"
                      "<HeartbeatInterval max=\"120000ms\">120000ms</HeartbeatInterval></Internal>"),
            std::string::npos);
  c.heartbeat_interval = std::chrono::milliseconds{0};
  EXPECT_FALSE(cyclone_config_xml(c).ok());
}

TEST(CycloneConfig, NamedInterfaceUsesMulticastDiscovery) {
  auto xml = cyclone_config_xml(interface_network("eth1"));
  ASSERT_TRUE(xml.ok());
  EXPECT_NE(xml->find("<NetworkInterface name=\"eth1\"/>"), std::string::npos);
  EXPECT_NE(xml->find("<AllowMulticast>true</AllowMulticast>"), std::string::npos);
  EXPECT_EQ(xml->find("<Peers>"), std::string::npos);
  auto by_address = cyclone_config_xml(interface_network("10.0.0.7"));
  ASSERT_TRUE(by_address.ok());
  EXPECT_NE(by_address->find("<NetworkInterface address=\"10.0.0.7\"/>"), std::string::npos);
}

TEST(CycloneConfig, RejectsUnsafeNamesAndOutOfRangeSettings) {
  auto bad = interface_network("eth0\"/><Evil");
  EXPECT_EQ(cyclone_config_xml(bad).error().code, Errc::invalid_argument);
  auto many = loopback_network();
  many.max_participant_index = 500;
  EXPECT_EQ(cyclone_config_xml(many).error().code, Errc::invalid_argument);
  auto peer = loopback_network();
  peer.peers = {"<x>"};
  EXPECT_FALSE(cyclone_config_xml(peer).ok());
  EXPECT_FALSE(validate_domain_id(233).ok());
  EXPECT_TRUE(validate_domain_id(232).ok());
}

TEST(Participant, CreatesWithTheLoopbackConfigAndRefusesAConflictingOne) {
  auto first = test::make_participant("a", test::private_partition("cfg"));
  EXPECT_EQ(first.domain_id(), test::kTestDomain);
  EXPECT_EQ(first.name(), "a");
  // A second participant in the same domain shares the domain...
  auto second = test::make_participant("b", test::private_partition("cfg"));
  EXPECT_GT(second.handle(), 0);
  // ...but a different configuration for a running domain is refused, not ignored.
  auto other = interface_network("lo");
  auto xml = cyclone_config_xml(other);
  ASSERT_TRUE(xml.ok());
  auto conflicting = Participant::create(test::kTestDomain, {*xml, "c", ""});
  ASSERT_FALSE(conflicting.ok());
  EXPECT_EQ(conflicting.error().code, Errc::invalid_argument);
  EXPECT_FALSE(Participant::create(300).ok());
}

}  // namespace
}  // namespace sf::dds
