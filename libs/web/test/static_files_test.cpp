#include "static_files.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "sf/testing/temp_dir.hpp"

namespace sf::web {
namespace {

void write_file(const std::filesystem::path& path, std::string_view text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

TEST(StaticFiles, ContentTypesByExtension) {
  const std::pair<const char*, const char*> cases[] = {{"index.html", "text/html; charset=utf-8"},
                                                       {"js/app.js", "text/javascript; charset=utf-8"},
                                                       {"a.css", "text/css; charset=utf-8"},
                                                       {"a.svg", "image/svg+xml"},
                                                       {"a.json", "application/json"},
                                                       {"a.bin", "application/octet-stream"}};
  for (const auto& [file, type] : cases) {
    EXPECT_EQ(content_type_for(file), type) << file;
  }
}

TEST(StaticFiles, ServesIndexAndNestedFiles) {
  sf::testing::TempDir dir;
  write_file(dir.path() / "site/index.html", "<html>");
  write_file(dir.path() / "site/js/app.js", "export {}");
  auto index = read_static_file(dir.path() / "site", "/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->body, "<html>");
  EXPECT_EQ(index->content_type, "text/html; charset=utf-8");
  auto script = read_static_file(dir.path() / "site", "/js//app.js");
  ASSERT_TRUE(script);
  EXPECT_EQ(script->body, "export {}");
  EXPECT_EQ(read_static_file(dir.path() / "site", "/js/none.js").error().code, Errc::not_found);
  EXPECT_EQ(read_static_file(dir.path() / "site", "/js").error().code, Errc::not_found);  // a directory
}

TEST(StaticFiles, NeverLeavesTheRoot) {
  sf::testing::TempDir dir;
  write_file(dir.path() / "secret.txt", "secret");
  write_file(dir.path() / "site/index.html", "<html>");
  std::filesystem::create_symlink(dir.path() / "secret.txt", dir.path() / "site/link.txt");
  const auto root = dir.path() / "site";
  for (const char* path : {"/../secret.txt", "/js/../../secret.txt", "/./index.html", "/..", "secret.txt"}) {
    EXPECT_EQ(read_static_file(root, path).error().code, Errc::invalid_argument) << path;
  }
  EXPECT_EQ(read_static_file(root, "//" + (dir.path() / "secret.txt").string()).error().code,
            Errc::not_found);
  EXPECT_EQ(read_static_file(root, "/link.txt").error().code, Errc::not_found);  // a link out of the root
}

}  // namespace
}  // namespace sf::web
