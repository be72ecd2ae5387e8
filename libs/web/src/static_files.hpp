// Static files from one directory (the dashboard's pages, scripts and styles). A request path
// never leaves the directory: '.' and '..' segments are refused before the file system is
// asked, and a path that resolves (through links) outside the directory is not found.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::web {

struct StaticFile {
  std::string content_type;
  std::string body;
};

// The media type of a file by its extension (RFC 9110 §8.3); application/octet-stream for
// others. Text types carry charset=utf-8.
std::string_view content_type_for(const std::filesystem::path& file);

// The file for a decoded request path: "/" and paths ending in '/' name index.html.
// Errc::invalid_argument for a path that tries to leave the root, Errc::not_found otherwise.
Result<StaticFile> read_static_file(const std::filesystem::path& root, std::string_view path);

}  // namespace sf::web
