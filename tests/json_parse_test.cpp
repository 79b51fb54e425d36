// ParseJson, the one parser of every JSON file rayspace reads: the grammar, plus a nesting bound,
// no key twice in one object and no NUL byte, each refused with a message that says which.
#include <string>

#include <doctest/doctest.h>

#include "rayspace/json_text.h"

using rayspace::JsonError;
using rayspace::kMaxJsonDepth;
using rayspace::ParseJson;

namespace {

std::string Nested(int depth, const char* open, const char* close) {
  std::string s;
  for (int i = 0; i < depth; ++i) s += open;
  s += "1";
  for (int i = 0; i < depth; ++i) s += close;
  return s;
}

std::string ErrorOf(const std::string& text) {
  try {
    ParseJson(text);
  } catch (const JsonError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("ParseJson: nesting up to kMaxJsonDepth parses, one deeper is refused before it is built") {
  CHECK(ParseJson(Nested(kMaxJsonDepth, "[", "]")).is_array());
  CHECK(ErrorOf(Nested(kMaxJsonDepth + 1, "[", "]")).find("nested deeper than 256") != std::string::npos);
  std::string objects;
  for (int i = 0; i < kMaxJsonDepth + 1; ++i) objects += "{\"a\":";
  objects += "1" + std::string(kMaxJsonDepth + 1, '}');
  CHECK(ErrorOf(objects).find("nested deeper than 256") != std::string::npos);
  // 100,000 levels (a 200 KB file): refused, not a stack overflow.
  CHECK(ErrorOf(Nested(100000, "[", "]")).find("nested deeper") != std::string::npos);
}

TEST_CASE("ParseJson: a key given twice in one object is refused, the same key in two objects is not") {
  CHECK(ErrorOf(R"({"a": 1, "b": 2, "a": 3})") == "the key \"a\" is given twice in one object");
  CHECK(ErrorOf(R"({"x": {"a": 1, "a": 1}})") == "the key \"a\" is given twice in one object");
  const auto j = ParseJson(R"({"a": {"a": 1}, "b": [{"a": 2}, {"a": 3}]})");
  CHECK(j["b"][1]["a"] == 3);
}

TEST_CASE("ParseJson: a NUL byte anywhere is refused, naming its byte") {
  CHECK(ErrorOf(std::string("{}\0", 3)) == "byte 3: a NUL byte");
  CHECK(ErrorOf(std::string("{\"a\0\": 1}", 9)) == "byte 4: a NUL byte");
}

TEST_CASE("ParseJson: syntax errors keep their line and column, without the library's prefix") {
  const std::string e = ErrorOf("{\n  \"a\": 1,,\n}");
  CHECK(e.rfind("line 2, column", 0) == 0);
  CHECK(e.find("[json.exception") == std::string::npos);
  CHECK(ErrorOf("{\"a\": 1e400}").find("1e400") != std::string::npos);
}
