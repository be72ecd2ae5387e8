// Working-counter increments, ET1100 datasheet section I §3.4 "Working
// Counter" (ETG.1000.4 §5.4.2): read +1, write +1, read-write +1/+2/+3,
// ARMW/FRMW +1 at the reading slave and +1 at each writing slave.
#include "sf/ethercat/wkc.hpp"

namespace sf::ethercat {
namespace {

enum class WkcRule { none, read, write, read_write, read_multiple_write };

WkcRule rule_of(Command c) {
  switch (c) {
    case Command::APRD:
    case Command::FPRD:
    case Command::BRD:
    case Command::LRD:
      return WkcRule::read;
    case Command::APWR:
    case Command::FPWR:
    case Command::BWR:
    case Command::LWR:
      return WkcRule::write;
    case Command::APRW:
    case Command::FPRW:
    case Command::BRW:
    case Command::LRW:
      return WkcRule::read_write;
    case Command::ARMW:
    case Command::FRMW:
      return WkcRule::read_multiple_write;
    case Command::NOP:
      break;
  }
  return WkcRule::none;
}

// The WKC field is 16 bits and the ESCs' adders wrap; so does the expectation.
std::uint16_t wrap(std::size_t n) {
  return static_cast<std::uint16_t>(n & 0xFFFFU);
}

}  // namespace

std::uint16_t wkc_increment(Command command, WkcAccess access) {
  const unsigned r = access.read ? 1U : 0U;
  const unsigned w = access.write ? 1U : 0U;
  switch (rule_of(command)) {
    case WkcRule::read:
      return static_cast<std::uint16_t>(r);
    case WkcRule::write:
      return static_cast<std::uint16_t>(w);
    case WkcRule::read_write:
      return static_cast<std::uint16_t>(r + 2U * w);
    case WkcRule::read_multiple_write:
      // One ESC either reads (it is the addressed one) or writes, never both;
      // a caller that reports both still gets the sum.
      return static_cast<std::uint16_t>(r + w);
    case WkcRule::none:
      break;
  }
  return 0;
}

std::uint16_t expected_wkc(Command command, std::size_t reading_slaves, std::size_t writing_slaves) {
  switch (rule_of(command)) {
    case WkcRule::read:
      return wrap(reading_slaves);
    case WkcRule::write:
      return wrap(writing_slaves);
    case WkcRule::read_write:
      return wrap(reading_slaves + 2 * writing_slaves);
    case WkcRule::read_multiple_write:
      return wrap(reading_slaves + writing_slaves);
    case WkcRule::none:
      break;
  }
  return 0;
}

}  // namespace sf::ethercat
