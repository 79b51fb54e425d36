// Output files written whole or not at all, and JSON text that never fails on bytes that are not UTF-8.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <doctest/doctest.h>

#include "rayspace/error.h"
#include "rayspace/json_text.h"
#include "rayspace/output_file.h"

namespace fs = std::filesystem;
using rayspace::EscapeInvalidUtf8;

namespace {

fs::path FreshDir(const char* name) {
  const fs::path dir = fs::temp_directory_path() / (std::string("rayspace-output-") + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Read(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::size_t Entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

}  // namespace

TEST_CASE("EscapeInvalidUtf8 keeps valid UTF-8 and writes every other byte as \\xNN") {
  CHECK(EscapeInvalidUtf8("plain.json") == "plain.json");
  CHECK(EscapeInvalidUtf8("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80") == "\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80");
  CHECK(EscapeInvalidUtf8("sc\xffne.json") == "sc\\xffne.json");
  CHECK(EscapeInvalidUtf8("\xc0\xaf") == "\\xc0\\xaf");                  // overlong '/'
  CHECK(EscapeInvalidUtf8("\xed\xa0\x80") == "\\xed\\xa0\\x80");          // a surrogate
  CHECK(EscapeInvalidUtf8("\xf4\x90\x80\x80") == "\\xf4\\x90\\x80\\x80");  // beyond U+10FFFF
  CHECK(EscapeInvalidUtf8("a\xe2\x82") == "a\\xe2\\x82");                  // truncated at the end
  CHECK(EscapeInvalidUtf8("\x80x\xc3\xa9") == "\\x80x\xc3\xa9");
}

TEST_CASE("JsonText writes strings and keys that are not UTF-8 escaped, where dump would throw") {
  const nlohmann::json j = {{"file", "sc\xffne.json"}, {"k\xfe", {"ok", "\xc0"}}};
  CHECK_THROWS(j.dump());
  const nlohmann::json back = nlohmann::json::parse(rayspace::JsonText(j));
  CHECK(back["file"] == "sc\\xffne.json");
  CHECK(back["k\\xfe"][1] == "\\xc0");
  CHECK(rayspace::JsonText({{"a", 1}}) == "{\n  \"a\": 1\n}\n");
}

TEST_CASE("OutputFile lands whole on Commit and leaves nothing when dropped") {
  const fs::path dir = FreshDir("commit");
  {
    rayspace::OutputFile f((dir / "out.json").string(), {"the test file", false, true, {}});
    CHECK(fs::exists(f.temp_path()));
    CHECK(!fs::exists(dir / "out.json"));
    f.Commit("{}\n");
  }
  CHECK(Read(dir / "out.json") == "{}\n");
  CHECK(Entries(dir) == 1);
  {
    rayspace::OutputFile dropped((dir / "out.json").string(), {"the test file", false, true, {}});
    rayspace::OutputFile fresh((dir / "new.json").string(), {"the test file", false, true, {}});
    dropped.Write("half");  // written, never published: the old file stays
  }
  CHECK(Read(dir / "out.json") == "{}\n");
  CHECK(Entries(dir) == 1);
  fs::remove_all(dir);
}

TEST_CASE("OutputFile refuses directories, devices, inputs and paths under a file, naming the path") {
  const fs::path dir = FreshDir("refuse");
  std::ofstream(dir / "input.obj") << "v 0 0 0\n";
  std::ofstream(dir / "file") << "";
  auto open = [&](const fs::path& p) {
    return rayspace::OutputFile(p.string(), {"the test file", false, true, {dir / "input.obj"}});
  };
  CHECK_THROWS_WITH_AS(open(dir), doctest::Contains("is a directory"), rayspace::InputError);
  CHECK_THROWS_WITH_AS(open("/dev/null"), doctest::Contains("/dev/null: cannot write the test file: is not a regular file"),
                       rayspace::InputError);
  CHECK_THROWS_WITH_AS(open(dir / "input.obj"), doctest::Contains("is also an input"), rayspace::InputError);
  CHECK_THROWS_WITH_AS(open(dir / "file" / "x.json"), doctest::Contains("file/x.json: cannot write the test file"),
                       rayspace::InputError);
  fs::create_symlink(dir / "nowhere" / "x.json", dir / "link.json");
  CHECK_THROWS_WITH_AS(open(dir / "link.json"), doctest::Contains("dangling symbolic link"), rayspace::InputError);
  CHECK(Entries(dir) == 3);  // nothing added but the link
  fs::remove_all(dir);
}

TEST_CASE("OutputFile through a symbolic link replaces the file it names and keeps the link") {
  const fs::path dir = FreshDir("link");
  std::ofstream(dir / "real.json") << "old";
  fs::create_symlink("real.json", dir / "link.json");
  rayspace::OutputFile((dir / "link.json").string(), {"the test file", false, true, {}}).Commit("new");
  CHECK(fs::is_symlink(dir / "link.json"));
  CHECK(Read(dir / "real.json") == "new");
  fs::remove_all(dir);
}
