// Tests for the OBJ and MTL loader beyond scene_loader_test.cpp: line endings (CR, LF, CRLF and
// mixed) checked exactly as the parser splits them.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "rayspace/error.h"
#include "rayspace/scene.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using rayspace::MeshData;
using rayspace::test::TempDir;

// The InputError message of loading `file` with `contents`, or "<no error>"; the message must be
// one line naming the file.
std::string LoadError(const TempDir& dir, const std::string& file, const std::string& contents) {
  const fs::path path = dir.Write(file, contents);
  try {
    rayspace::LoadMesh(path);
  } catch (const rayspace::InputError& e) {
    const std::string message = e.what();
    CHECK(message.find('\n') == std::string::npos);
    CHECK(message.find('\r') == std::string::npos);
    CHECK(message.find(file) != std::string::npos);
    return message;
  }
  return "<no error>";
}

bool Contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// `lf` with every '\n' replaced by `eol`.
std::string WithLineEnds(const std::string& lf, const std::string& eol) {
  std::string out;
  for (char c : lf) out += c == '\n' ? eol : std::string(1, c);
  return out;
}

}  // namespace

TEST_SUITE("obj_mtl") {

TEST_CASE("OBJ with CR-only line ends: every line is checked, bad ones refused as in an LF file") {
  TempDir dir;
  struct Case {
    std::string name, lf_text, expected;
  };
  const std::vector<Case> cases = {
      {"nan", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nf 1 2 3\n", ":4: non-finite vertex coordinate 'nan'"},
      {"garbage", "v 0 0 0\nv 1 0 0\nv 0 1 abc\nf 1 2 3\n", ":3: bad vertex coordinate 'abc'"},
      {"two_vertex_face", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\n", ":4: face needs at least 3 vertices"},
      {"index_range", "v 0 0 0\nv 1 0 0\nf 1 2 3\n", ":3: vertex index 3 out of range (have 2)"},
      {"short_vertex", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", ":2: vertex needs 3 coordinates"},
  };
  for (const Case& c : cases) {
    for (const std::string eol : {"\n", "\r", "\r\n"}) {
      const std::string file = c.name + (eol == "\r" ? "_cr" : eol == "\n" ? "_lf" : "_crlf") + ".obj";
      CAPTURE(file);
      const std::string message = LoadError(dir, file, WithLineEnds(c.lf_text, eol));
      CHECK_MESSAGE(Contains(message, file + c.expected), message);
    }
  }
}

TEST_CASE("OBJ with mixed line ends numbers its lines as the parser does and loads the same mesh") {
  TempDir dir;
  const std::string lf = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
  const MeshData reference = rayspace::LoadMesh(dir.Write("lf.obj", lf));
  const std::string mixed = "v 0 0 0\r\nv 1 0 0\rv 0 1 0\nv 1 1 0\r\rf 1 2 3\r\nf 2 4 3";
  const MeshData m = rayspace::LoadMesh(dir.Write("mixed.obj", mixed));
  REQUIRE(m.submeshes.size() == 1);
  CHECK(m.submeshes[0].positions == reference.submeshes.at(0).positions);
  // "\r\r" is two line ends (an empty line 5), so the face is on line 6.
  const std::string bad = "v 0 0 0\r\nv 1 0 0\rv 0 1 0\nv 1 1 0\r\rf 1 2 5\r\n";
  CHECK(Contains(LoadError(dir, "mixed_bad.obj", bad), "mixed_bad.obj:6: vertex index 5 out of range (have 4)"));
}

TEST_CASE("OBJ and MTL with a NUL byte are refused naming the line") {
  TempDir dir;
  CHECK(Contains(LoadError(dir, "nul.obj", std::string("v 0 0 0\nv 1 0 0\0 junk\nv 0 1 0\nf 1 2 3\n", 38)),
                 "nul.obj:2: NUL byte"));
  dir.Write("nul.mtl", std::string("newmtl a\nKd 1 1 1\0\n", 19));
  const fs::path obj = dir.Write("uses_nul.obj", "mtllib nul.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
  CHECK_THROWS_WITH_AS(rayspace::LoadMesh(obj), doctest::Contains("nul.mtl:2: NUL byte"), rayspace::InputError);
}

TEST_CASE("MTL with CR-only line ends gives the same materials as with LF") {
  TempDir dir;
  const std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
  const std::string mtl = "newmtl red\nKd 0.8 0.1 0.2\nKs 0.3 0.4 0.5\nNs 12\n";
  for (const std::string eol : {"\n", "\r", "\r\n"}) {
    TempDir d;
    d.Write("m.mtl", WithLineEnds(mtl, eol));
    const MeshData m = rayspace::LoadMesh(d.Write("t.obj", WithLineEnds(obj, eol)));
    REQUIRE(m.materials.size() == 1);
    CHECK(m.materials[0].name == "red");
    CHECK(m.materials[0].diffuse == glm::vec3(0.8f, 0.1f, 0.2f));
    CHECK(m.materials[0].specular == glm::vec3(0.3f, 0.4f, 0.5f));
    CHECK(m.materials[0].shininess == 12.0f);
    CHECK(m.submeshes.at(0).material == std::vector<int>{0});
  }
}

}  // TEST_SUITE
