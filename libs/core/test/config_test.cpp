#include "sf/core/config.hpp"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace sf::config {
namespace {

constexpr const char* kYaml = R"(historian:
  url: sqlite:/tmp/h.db
  batch: 500
servers:
  - url: opc.tcp://127.0.0.1:4840
    port: 70000
  - url: [1, 2]
ratio: 0.25
enabled: yes
)";

TEST(Config, ReadsTypedValues) {
  auto root = load_string(kYaml, "cloud.yaml");
  ASSERT_TRUE(root.ok()) << root.error().describe();
  auto hist = root->child("historian");
  ASSERT_TRUE(hist.ok());
  EXPECT_EQ(*hist->get<std::string>("url"), "sqlite:/tmp/h.db");
  EXPECT_EQ(*hist->get<int>("batch"), 500);
  EXPECT_EQ(*hist->get_or<int>("flush_ms", 100), 100);
  EXPECT_DOUBLE_EQ(*root->get<double>("ratio"), 0.25);
  EXPECT_TRUE(*root->get<bool>("enabled"));
}

TEST(Config, ErrorNamesFileLineAndKey) {
  auto root = load_string(kYaml, "cloud.yaml");
  ASSERT_TRUE(root.ok());
  auto servers = root->child("servers")->items();
  ASSERT_TRUE(servers.ok());
  ASSERT_EQ(servers->size(), 2U);
  auto port = (*servers)[0].get<std::uint16_t>("port");
  ASSERT_FALSE(port.ok());
  EXPECT_EQ(port.error().message, "cloud.yaml:6:11: servers[0].port: integer out of range for this setting");
  auto url = (*servers)[1].get<std::string>("url");
  ASSERT_FALSE(url.ok());
  EXPECT_EQ(url.error().message, "cloud.yaml:7:10: servers[1].url: expected a value, found a list");
}

TEST(Config, MissingKeyNamesParent) {
  auto root = load_string(kYaml, "cloud.yaml");
  auto missing = root->child("historian")->get<std::string>("user");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "cloud.yaml:2:3: historian: missing required key 'user'");
}

TEST(Config, WrongScalarType) {
  auto root = load_string("batch: many\n", "x.yaml");
  auto v = root->get<int>("batch");
  ASSERT_FALSE(v.ok());
  EXPECT_EQ(v.error().message, "x.yaml:1:8: batch: expected an integer, found 'many'");
  EXPECT_FALSE(load_string("flag: maybe\n")->get<bool>("flag").ok());
  EXPECT_FALSE(load_string("n: -3\n")->get<unsigned>("n").ok());
  EXPECT_EQ(*load_string("n: 0x1C12\n")->get<std::uint16_t>("n"), 0x1C12);
}

TEST(Config, SyntaxErrorNamesLineAndColumn) {
  auto root = load_string("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml");
  ASSERT_FALSE(root.ok());
  EXPECT_EQ(root.error().code, Errc::malformed);
  EXPECT_EQ(root.error().message.rfind("bad.yaml:", 0), 0U) << root.error().message;
}

TEST(Config, LoadFileAndMissingFile) {
  const auto path = std::filesystem::temp_directory_path() / "sf_config_test.yaml";
  {
    std::ofstream out{path};
    out << "names: [a, b, c]\n";
  }
  auto root = load_file(path);
  ASSERT_TRUE(root.ok());
  auto names = root->get<std::vector<std::string>>("names");
  ASSERT_TRUE(names.ok());
  EXPECT_EQ(*names, (std::vector<std::string>{"a", "b", "c"}));
  std::filesystem::remove(path);
  auto missing = load_file(path);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, Errc::not_found);
  EXPECT_NE(missing.error().message.find(path.string()), std::string::npos);
}

}  // namespace
}  // namespace sf::config
