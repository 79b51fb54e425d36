// The text of every JSON file rayspace writes (statistics, reports, saved inputs).
#pragma once
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace rayspace {

// `s` with every byte that is not part of a valid UTF-8 sequence written as the four characters \xNN
// (NN its value in lower-case hex, as Python's backslashreplace writes it); valid UTF-8 comes back
// unchanged.
std::string EscapeInvalidUtf8(std::string_view s);

// `j` as indented JSON text ending in a newline. File names are bytes, not text: a string or key that
// is not valid UTF-8 is written through EscapeInvalidUtf8, so that writing never fails on one.
std::string JsonText(const nlohmann::json& j, int indent = 2);

}  // namespace rayspace
