// Small text helpers shared by the modules' parsers of names, lists and options (ASCII only:
// what they handle are identifiers, host names, URIs and numbers, never prose).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace sf {

// The fields of `text` between `separator`s, empty fields included ("a,,b" → "a", "", "b");
// no fields at all for empty text. The views point into `text`.
std::vector<std::string_view> split(std::string_view text, char separator);

// `text` with ASCII letters in lower case.
std::string lower(std::string_view text);

// `text` without leading and trailing white space (space, tab, CR, LF, VT, FF).
std::string_view trim(std::string_view text);

// The value of a hexadecimal digit (0-9, a-f, A-F), -1 for any other character.
int hex_value(char c);

// The message of an errno value. strerror() is not thread-safe; the error category's message is.
std::string errno_text(int err);

}  // namespace sf
