// The users file of a running server, re-read when it changes.
#include <sys/stat.h>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/opcua/security/users.hpp"

namespace sf::opcua::security {

Result<std::shared_ptr<UsersFile>> UsersFile::open(std::filesystem::path file) {
  std::shared_ptr<UsersFile> users(new UsersFile(std::move(file)));
  users->stamp_ = users->stamp();
  auto loaded = UserDatabase::load(users->file_);
  if (!loaded) {
    return loaded.error();
  }
  users->users_ = std::make_shared<const UserDatabase>(std::move(*loaded));
  return users;
}

// Inode, size and modification time: a replaced or rewritten file has another stamp.
std::string UsersFile::stamp() const {
  struct stat st {};
  if (::stat(file_.c_str(), &st) != 0) {
    return {};
  }
  return fmt::format("{}|{}|{}.{}", st.st_ino, st.st_size, st.st_mtim.tv_sec, st.st_mtim.tv_nsec);
}

std::shared_ptr<const UserDatabase> UsersFile::current() {
  const std::string now = stamp();
  std::lock_guard lock(mutex_);
  if (now == stamp_) {
    return users_;
  }
  stamp_ = now;
  auto loaded = UserDatabase::load(file_);
  if (!loaded) {
    log::get("opcua")->warn("users file {} changed but cannot be used, keeping its {} users: {}",
                            file_.string(), users_->users().size(), loaded.error().message);
    return users_;
  }
  log::get("opcua")->info("users file {} reloaded: {} users", file_.string(), loaded->users().size());
  users_ = std::make_shared<const UserDatabase>(std::move(*loaded));
  return users_;
}

}  // namespace sf::opcua::security
