// Tests for the OBJ and MTL loader beyond scene_loader_test.cpp: line endings (CR, LF, CRLF and
// mixed) checked exactly as the parser splits them, and MTL values checked against their ranges.
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
  // Each case under LF, CR and CRLF line ends alike; the normal and texture cases are also the
  // check of vn and vt values, which tinyobjloader would read as 0.
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
      {"nan_normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 1\nf 1//1 2//2 3//1\n",
       ":5: non-finite normal coordinate 'nan'"},
      {"garbage_normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 x 1\nf 1//1 2//1 3//1\n", ":4: bad normal coordinate 'x'"},
      {"short_normal", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 1\nf 1//1 2//1 3//1\n", ":4: normal needs 3 coordinates"},
      {"huge_texcoord", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 1e39\nf 1/1 2/1 3/1\n", ":4: non-finite texture coordinate '1e39'"},
      {"empty_texcoord", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt\nf 1 2 3\n", ":4: texture needs 1 coordinate"},
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

TEST_CASE("MTL values: NaN, infinite, negative, out of range or malformed are refused naming file, line and key") {
  struct Case {
    std::string line, expected;
  };
  const std::vector<Case> cases = {
      {"Kd nan 0.5 0.5", ":3: Kd: 'nan' is not finite"},
      {"Kd 0.5 inf 0.5", ":3: Kd: 'inf' is not finite"},
      {"Kd 0.5 0.5 -0.1", ":3: Kd: -0.1 out of range [0, 1000000]"},
      {"Kd 0.5 0.5 1e7", ":3: Kd: 1e7 out of range"},
      {"Kd 1e400 0 0", ":3: Kd: '1e400' is not a number"},
      {"Kd 0.5", ":3: Kd needs 3 numbers (r g b), got 1"},
      {"Kd 0.5 0.5 0.5 0.5", ":3: Kd needs 3 numbers (r g b), got 4"},
      {"Kd 0.5 abc 0.5", ":3: Kd: 'abc' is not a number"},
      {"Kd spectral file.rfl", ":3: Kd needs 3 numbers"},
      {"Ks -1 0 0", ":3: Ks: -1 out of range"},
      {"Ks nan nan nan", ":3: Ks: 'nan' is not finite"},
      {"Ns -5", ":3: Ns: -5 out of range [0, 4096]"},
      {"Ns 5000", ":3: Ns: 5000 out of range [0, 4096]"},
      {"Ns nan", ":3: Ns: 'nan' is not finite"},
      {"Ns", ":3: Ns needs 1 number, got 0"},
      {"Ka 0 -1 0", ":3: Ka: -1 out of range"},
      {"Ke inf 0 0", ":3: Ke: 'inf' is not finite"},
      {"Tf 1 1 nan", ":3: Tf: 'nan' is not finite"},
      {"Ni -1", ":3: Ni: -1 out of range [0, 100]"},
      {"Ni 1e9", ":3: Ni: 1e9 out of range"},
      {"d 1.5", ":3: d: 1.5 out of range [0, 1]"},
      {"Tr -0.5", ":3: Tr: -0.5 out of range [0, 1]"},
      {"illum 2.5", ":3: illum: 2.5 is not an integer"},
      {"illum 11", ":3: illum: 11 out of range [0, 10]"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.line);
    TempDir dir;
    dir.Write("bad.mtl", "newmtl a\nKa 0 0 0\n" + c.line + "\nKd 0.5 0.5 0.5\n");
    const fs::path obj = dir.Write("t.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
    std::string message = "<no error>";
    try {
      rayspace::LoadMesh(obj);
    } catch (const rayspace::InputError& e) {
      message = e.what();
    }
    CHECK_MESSAGE(Contains(message, "bad.mtl" + c.expected), message);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("MTL values at the ends of their ranges and as exporters write them load") {
  TempDir dir;
  dir.Write("ok.mtl",
            "# exported\nnewmtl a\nNs 96.078431\nKa 0.000000 0.000000 0.000000\nKd +0.640000 0.64 0.64\n"
            "Ks 0.5 0.5 0.5\nKe 0 0 0\nNi 0\nd 1.000000\nTr 0\nillum 2\nmap_Kd wood.png\n"
            "newmtl b\nKd 0 0 1000000\nKs 1000000 0 0\nNs 4096\nNi 100\nd 0\nTf 1 1 1\nillum 0\n");
  const fs::path obj =
      dir.Write("t.obj", "mtllib ok.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 3 2\n");
  const MeshData m = rayspace::LoadMesh(obj);
  REQUIRE(m.materials.size() == 2);
  CHECK(m.materials[0].diffuse == glm::vec3(0.64f));
  CHECK(m.materials[0].shininess == 96.0f);
  CHECK(m.materials[1].diffuse == glm::vec3(0, 0, 1e6f));
  CHECK(m.materials[1].specular == glm::vec3(1e6f, 0, 0));
  CHECK(m.materials[1].shininess == 4096.0f);
}

}  // TEST_SUITE
