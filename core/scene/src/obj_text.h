// The text of OBJ and MTL files, read line by line as tinyobjloader reads it, for the checks that
// run before tinyobjloader parses the same text.
#pragma once
#include <cstddef>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

namespace rayspace::obj_text {

// Makes every line end in a single '\n': tinyobjloader ends a line at "\r\n", at a lone "\r" and
// at "\n", so without this a CR-only file is one line to a check that splits at '\n' and many to
// the parser. Both then see, and number, the same lines. A NUL byte, which ends a line early for
// tinyobjloader's token parser, is refused naming the file and line: OBJ and MTL are text.
void NormaliseLineEnds(std::string& text, const std::string& file);

// The fields of a line, split at spaces and tabs as tinyobjloader splits them; the line's '#'
// comment is dropped first.
std::vector<std::string_view> Tokens(std::string_view line);

// The whole token as a number (std::from_chars, correctly rounded); false for anything else.
bool ParseFloat(std::string_view s, double& v);
bool ParseInt(std::string_view s, long long& v);

// An istream buffer over text already in memory, without the copy an istringstream makes.
class TextBuf : public std::streambuf {
 public:
  explicit TextBuf(std::string& text) { setg(text.data(), text.data(), text.data() + text.size()); }
};

// Calls f(line_number, line) for every line of normalised text, numbered from 1.
template <typename F>
void ForEachLine(const std::string& text, F&& f) {
  std::size_t line_no = 0, pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    f(++line_no, std::string_view(text.data() + pos, end - pos));
    pos = end + 1;
  }
}

}  // namespace rayspace::obj_text
