// Helpers for the dds tests: a loopback participant in a partition private to
// this test process, and an executor pump with a generous real-time bound
// (the assertion is that something happens, never how fast).
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "dds_test_types.h"
#include "sf/dds/dds.hpp"

SF_DDS_TOPIC_TYPE(sf_ddstest_Reading);

namespace sf::dds::test {

inline constexpr DomainId kTestDomain = 77;

inline std::string private_partition(std::string_view tag) {
  return fmt::format("sf-dds-test-{}-{}", ::getpid(), tag);
}

inline Participant make_participant(std::string name, std::string partition,
                                    const NetworkConfig& network = loopback_network()) {
  auto xml = cyclone_config_xml(network);
  EXPECT_TRUE(xml.ok());
  auto p = Participant::create(kTestDomain, {*xml, std::move(name), std::move(partition)});
  if (!p) {
    ADD_FAILURE() << p.error().describe();
    std::abort();
  }
  return std::move(*p);
}

inline bool pump_until(Executor& ex, const std::function<bool()>& done,
                       std::chrono::seconds bound = std::chrono::seconds{20}) {
  const auto end = std::chrono::steady_clock::now() + bound;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) {
      return false;
    }
    ex.wait_for(std::chrono::milliseconds{10});
    ex.run_pending();
  }
  return true;
}

inline sf_ddstest_Reading reading(std::string_view sensor, std::int64_t value) {
  sf_ddstest_Reading r{};
  const auto n = std::min(sensor.size(), sizeof(r.sensor) - 1);
  std::copy_n(sensor.data(), n, r.sensor);
  r.value = value;
  return r;
}

}  // namespace sf::dds::test
