// The data check on a tiny data root and manifest: no scene data needed.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "rayspace/data_check.h"
#include "rayspace/error.h"

namespace {

namespace fs = std::filesystem;

void Write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

// A data root with d/tri.obj = "abc" and a manifest that lists it for tiny.json.
struct TinyRoot {
  // One directory per process: ctest -j runs these test cases as processes side by side.
  fs::path dir = fs::temp_directory_path() / ("rayspace_data_check_test_" + std::to_string(getpid()));
  // Both files should hold "abc"; d/changed.obj holds "abd".
  std::string manifest = R"({"format": 1, "scenes": {"tiny.json": ["d/tri.obj"], "changed.json": ["d/changed.obj"]},
    "files": [{"path": "d/tri.obj", "size": 3, "source": "d", "url": "https://example.org/tri.obj", "obtained": "copy",
               "sha256": "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"},
              {"path": "d/changed.obj", "size": 3, "source": "d", "url": "https://example.org/tri.obj", "obtained": "copy",
               "sha256": "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"}],
    "sources": {"d": {"url": "https://example.org/tri.obj"}}})";
  TinyRoot() {
    fs::remove_all(dir);
    Write(dir / "root/d/tri.obj", "abc");
    Write(dir / "root/d/changed.obj", "abd");
    Write(dir / "scenes/changed.json", "{}");
    Write(dir / "scenes/tiny.json", R"({"objects": [{"mesh": "d/tri.obj"}]})");
  }
  ~TinyRoot() { fs::remove_all(dir); }
  std::vector<rayspace::data::Problem> Check(const std::string& scene = "tiny.json") const {
    return rayspace::data::CheckSceneData({dir / "scenes" / scene}, dir / "root", manifest);
  }
};

}  // namespace

TEST_CASE("data: SHA-256 of a file through OpenSSL") {
  TinyRoot t;
  CHECK(rayspace::data::Sha256File(t.dir / "root/d/tri.obj") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK_THROWS_AS(rayspace::data::Sha256File(t.dir / "nonesuch"), rayspace::InputError);
}

TEST_CASE("data: a listed file present, truncated, different or missing") {
  TinyRoot t;
  CHECK(t.Check().empty());
  SUBCASE("truncated") {
    Write(t.dir / "root/d/tri.obj", "ab");
    const auto p = t.Check();
    REQUIRE(p.size() == 1);
    CHECK(p[0].scene == "tiny.json");
    CHECK(p[0].file == "d/tri.obj");
    CHECK(p[0].message == "d/tri.obj: 2 bytes, the manifest says 3 (get it from https://example.org/tri.obj)");
  }
  SUBCASE("different bytes, same size") {
    const auto p = t.Check("changed.json");
    REQUIRE(p.size() == 1);
    CHECK(p[0].message.find("d/changed.obj: SHA-256 a52d159f") == 0);
    CHECK(p[0].message.find("the manifest says ba7816bf") != std::string::npos);
  }
  SUBCASE("missing") {
    fs::remove(t.dir / "root/d/tri.obj");
    const auto p = t.Check();
    REQUIRE(p.size() == 1);
    CHECK(p[0].message.find("d/tri.obj: missing under the data root") == 0);
    CHECK(p[0].message.find("get it from https://example.org/tri.obj") != std::string::npos);
  }
}

TEST_CASE("data: a scene not in the manifest is checked by its meshes") {
  TinyRoot t;
  Write(t.dir / "scenes/other.json", R"({"objects": [{"mesh": "d/tri.obj"}, {"mesh": "e/none.obj"}]})");
  const auto p = t.Check("other.json");
  REQUIRE(p.size() == 1);
  CHECK(p[0].file == "e/none.obj");
  CHECK(p[0].message.find("the data manifest does not list it") != std::string::npos);
}

TEST_CASE("data: the embedded manifest lists the bundled scenes") {
  const auto names = rayspace::data::ManifestScenes(rayspace::data::EmbeddedManifest());
  CHECK(std::find(names.begin(), names.end(), "sponza.json") != names.end());
  CHECK(std::find(names.begin(), names.end(), "cornell-mirrors.json") != names.end());
}
