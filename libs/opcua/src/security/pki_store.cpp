// The PKI folder: own credentials, trusted/issuers/rejected certificates and CRLs.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "openssl.hpp"
#include "sf/core/log.hpp"
#include "sf/core/text.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua::security {
namespace fs = std::filesystem;
namespace {

constexpr std::size_t kMinThumbprintPrefix = 8;

Status make_dir(const fs::path& dir, fs::perms perms) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    return make_error(Errc::io, fmt::format("cannot create {}: {}", dir.string(), ec.message()));
  }
  fs::permissions(dir, perms, ec);
  return {};
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file(ec) && it->path().extension() != ".tmp") {
      out.push_back(it->path());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::string_view PkiStore::folder_name(Folder folder) {
  switch (folder) {
    case Folder::Own:
      return "own";
    case Folder::Trusted:
      return "trusted";
    case Folder::Issuers:
      return "issuers";
    case Folder::Rejected:
      return "rejected";
  }
  return "?";
}

fs::path PkiStore::folder_path(Folder folder) const {
  switch (folder) {
    case Folder::Own:
      return own_certificate().parent_path();
    case Folder::Trusted:
      return trusted_certs();
    case Folder::Issuers:
      return issuer_certs();
    case Folder::Rejected:
      return rejected_certs();
  }
  return {};
}

Status PkiStore::create_folders() const {
  constexpr auto kOpen = fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                         fs::perms::others_read | fs::perms::others_exec;
  for (const auto& dir : {own_certificate().parent_path(), trusted_certs(), trusted_crls(), issuer_certs(),
                          issuer_crls(), rejected_certs()}) {
    SF_TRY(make_dir(dir, kOpen));
  }
  return make_dir(own_private_key().parent_path(), fs::perms::owner_all);
}

bool PkiStore::has_own() const {
  std::error_code ec;
  return fs::exists(own_certificate(), ec) && fs::exists(own_private_key(), ec);
}

Result<SecurityCredentials> PkiStore::load_own() const {
  auto certificate = read_certificate_file(own_certificate());
  if (!certificate) {
    return certificate.error();
  }
  auto key = read_private_key_file(own_private_key());
  if (!key) {
    return key.error();
  }
  return SecurityCredentials{std::move(*certificate), std::move(*key)};
}

Result<SecurityCredentials> PkiStore::create_own(const CertificateRequest& request) const {
  SF_TRY(create_folders());
  auto created = create_certificate(request);
  if (!created) {
    return created.error();
  }
  SF_TRY(write_private_key_file(own_private_key(), created->private_key));
  SF_TRY(write_file(own_certificate(), created->certificate.span()));
  auto trusted = add(Folder::Trusted, created->certificate);
  if (!trusted) {
    return trusted.error();
  }
  log::get("opcua")->info("created the application instance certificate {} for {} in {}",
                          own_certificate().string(), request.application_uri, root_.string());
  return created;
}

Result<SecurityCredentials> PkiStore::ensure_own(const CertificateRequest& request) const {
  SF_TRY(create_folders());
  // A server and a client of one installation may start together on a fresh folder: one makes
  // the certificate, the other waits and loads it (certificate and key must stay a pair).
  const fs::path lock_file = root_ / ".lock";
  const int fd = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0) {
    return make_error(Errc::io, fmt::format("cannot open {}: {}", lock_file.string(), std::strerror(errno)));
  }
  while (::flock(fd, LOCK_EX) != 0 && errno == EINTR) {
  }
  auto own = has_own() ? load_own() : create_own(request);
  ::close(fd);  // releases the lock
  return own;
}

std::string PkiStore::file_name(const CertificateInfo& info) {
  std::string name;
  for (const char c : info.common_name) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_';
    name.push_back(plain ? c : '_');
  }
  if (name.empty()) {
    name = "certificate";
  }
  return name.substr(0, 64) + "_" + info.thumbprint + ".der";
}

std::vector<PkiStore::Entry> PkiStore::certificates() const {
  std::vector<Entry> out;
  for (const Folder folder : {Folder::Own, Folder::Trusted, Folder::Issuers, Folder::Rejected}) {
    for (const auto& file : files_in(folder_path(folder))) {
      auto der = read_certificate_file(file);
      auto info = der ? inspect_certificate(der->span()) : Result<CertificateInfo>(der.error());
      if (!info) {
        log::get("opcua")->warn("PKI: skipping {}: {}", file.string(), info.error().message);
        continue;
      }
      out.push_back(Entry{folder, file, std::move(*info)});
    }
  }
  return out;
}

std::vector<fs::path> PkiStore::crls() const {
  std::vector<fs::path> out = files_in(trusted_crls());
  const auto issuers = files_in(issuer_crls());
  out.insert(out.end(), issuers.begin(), issuers.end());
  return out;
}

Result<fs::path> PkiStore::add(Folder folder, const ByteString& certificate) const {
  auto leaf = leaf_certificate(certificate.span());
  if (!leaf) {
    return leaf.error();
  }
  auto info = inspect_certificate(leaf->span());
  if (!info) {
    return info.error();
  }
  SF_TRY(create_folders());
  const fs::path file = folder_path(folder) / file_name(*info);
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    SF_TRY(write_file(file, leaf->span()));
  }
  return file;
}

Result<fs::path> PkiStore::move(std::string_view thumbprint, Folder from, Folder to) const {
  const std::string wanted = lower(thumbprint);
  if (wanted.size() < kMinThumbprintPrefix) {
    return make_error(Errc::invalid_argument,
                      fmt::format("give at least {} hex digits of the thumbprint", kMinThumbprintPrefix));
  }
  std::vector<Entry> matches;
  for (auto& entry : certificates()) {
    if (entry.folder == from && entry.info.thumbprint.compare(0, wanted.size(), wanted) == 0) {
      matches.push_back(std::move(entry));
    }
  }
  if (matches.size() != 1) {
    return make_error(matches.empty() ? Errc::not_found : Errc::invalid_argument,
                      fmt::format("{} certificates in {}/ have a thumbprint starting with {}", matches.size(),
                                  folder_name(from), wanted));
  }
  SF_TRY(create_folders());
  const fs::path target = folder_path(to) / file_name(matches[0].info);
  std::error_code ec;
  fs::rename(matches[0].file, target, ec);
  if (ec) {
    return make_error(Errc::io, fmt::format("cannot move {} to {}: {}", matches[0].file.string(),
                                            target.string(), ec.message()));
  }
  return target;
}

}  // namespace sf::opcua::security
