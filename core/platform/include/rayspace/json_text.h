// The text of every JSON file rayspace writes (statistics, reports, saved inputs), and the one parser
// of every JSON file it reads (scenes, saved calls, reports, survivors files, data manifests).
#pragma once
#include <stdexcept>
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

// JSON rayspace reads may not nest deeper than this many arrays and objects (docs/scene-format.md,
// "Limits"): a deeper value is refused before it is built, since every walk over it (printing a
// piece of it in an error, destroying it) would recurse that deep.
inline constexpr int kMaxJsonDepth = 256;

// A JSON text that breaks the grammar or rayspace's rules; what() is "line L, column C: reason" or
// "reason" (without nlohmann's "[json.exception...]" prefix).
class JsonError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses `text` as one JSON value. Beyond the grammar it refuses nesting deeper than kMaxJsonDepth, a
// key given twice in one object (the parser would keep the last silently) and a NUL byte anywhere
// (one after the closing bracket would otherwise pass).
nlohmann::json ParseJson(std::string_view text);

}  // namespace rayspace
