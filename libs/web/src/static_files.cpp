#include "static_files.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>
#include <utility>

namespace sf::web {
namespace {

constexpr std::uintmax_t kMaxFileSize = 16ULL * 1024ULL * 1024ULL;

// Relative path inside the root, or invalid_argument when a segment could climb out of it.
Result<std::filesystem::path> relative_path(std::string_view path) {
  if (path.empty() || path.front() != '/') {
    return Error(Errc::invalid_argument, "static path must be absolute within the site");
  }
  std::filesystem::path relative;
  std::string_view rest = path.substr(1);
  while (true) {
    const auto slash = rest.find('/');
    const auto segment = rest.substr(0, slash);
    if (segment == "." || segment == "..") {
      return Error(Errc::invalid_argument, "static path contains a '.' or '..' segment");
    }
    if (slash == std::string_view::npos) {
      relative /= segment.empty() ? std::string_view("index.html") : segment;
      return relative;
    }
    if (!segment.empty()) {  // "//" collapses; a leading one would otherwise make it absolute
      relative /= segment;
    }
    rest.remove_prefix(slash + 1);
  }
}

bool inside(const std::filesystem::path& root, const std::filesystem::path& file) {
  const auto [end, _] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  return end == root.end();
}

}  // namespace

std::string_view content_type_for(const std::filesystem::path& file) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 14> kTypes{{
      {".html", "text/html; charset=utf-8"},
      {".htm", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},  // RFC 9239 §6
      {".mjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".map", "application/json"},
      {".svg", "image/svg+xml"},
      {".png", "image/png"},
      {".ico", "image/vnd.microsoft.icon"},
      {".txt", "text/plain; charset=utf-8"},
      {".woff2", "font/woff2"},
      {".webmanifest", "application/manifest+json"},
      {".yaml", "application/yaml"},
  }};
  const auto extension = file.extension().string();
  for (const auto& [ext, type] : kTypes) {
    if (ext == extension) {
      return type;
    }
  }
  return "application/octet-stream";
}

Result<StaticFile> read_static_file(const std::filesystem::path& root, std::string_view path) {
  auto relative = relative_path(path);
  if (!relative) {
    return relative.error();
  }
  std::error_code ec;
  const auto base = std::filesystem::canonical(root, ec);
  const auto file = ec ? std::filesystem::path{} : std::filesystem::weakly_canonical(base / *relative, ec);
  if (ec || !inside(base, file) || !std::filesystem::is_regular_file(file, ec) ||
      std::filesystem::file_size(file, ec) > kMaxFileSize || ec) {
    return Error(Errc::not_found, "no file " + std::string(path));
  }
  std::ifstream in(file, std::ios::binary);
  std::ostringstream body;
  body << in.rdbuf();
  if (!in) {
    return Error(Errc::not_found, "cannot read " + std::string(path));
  }
  return StaticFile{std::string(content_type_for(file)), std::move(body).str()};
}

}  // namespace sf::web
