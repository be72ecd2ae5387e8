#include "sf/dds/entity.hpp"

#include <fmt/format.h>

namespace sf::dds {

Error dds_error(dds_return_t rc, std::string_view what) {
  Errc code = Errc::io;
  switch (rc) {
    case DDS_RETCODE_BAD_PARAMETER:
      code = Errc::invalid_argument;
      break;
    case DDS_RETCODE_TIMEOUT:
      code = Errc::timeout;
      break;
    case DDS_RETCODE_OUT_OF_RESOURCES:
      code = Errc::limit_exceeded;
      break;
    case DDS_RETCODE_UNSUPPORTED:
    case DDS_RETCODE_INCONSISTENT_POLICY:
      code = Errc::unsupported;
      break;
    case DDS_RETCODE_PRECONDITION_NOT_MET:
    case DDS_RETCODE_NOT_ENABLED:
    case DDS_RETCODE_ALREADY_DELETED:
    case DDS_RETCODE_ILLEGAL_OPERATION:
    case DDS_RETCODE_IMMUTABLE_POLICY:
      code = Errc::state;
      break;
    default:
      break;
  }
  return Error{code, fmt::format("{}: {}", what, dds_strretcode(rc))};
}

void Entity::reset() {
  if (handle_ > 0) {
    // An already deleted handle (its parent went first) is not an error here.
    (void)dds_delete(handle_);
  }
  handle_ = 0;
}

}  // namespace sf::dds
