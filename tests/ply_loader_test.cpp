// Tests for the PLY loader: the three encodings, skipping of unknown data, normals, every class of
// malformed input, a small built-in fuzz pass, and the real Stanford bunny when the data is present.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <doctest/doctest.h>

#include "rayspace/error.h"
#include "rayspace/scene.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using rayspace::LoadPly;
using rayspace::MeshData;

using rayspace::test::TempDir;

// Binary body builder writing each value in the chosen byte order.
class Bytes {
 public:
  explicit Bytes(bool big_endian) : big_(big_endian) {}
  template <typename T>
  Bytes& operator<<(T value) {
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    if (big_ != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
    data_.append(b, sizeof(T));
    return *this;
  }
  const std::string& str() const { return data_; }

 private:
  bool big_;
  std::string data_;
};

// The shared test mesh: five vertices, a triangle and a quad.
const glm::vec3 kVertices[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0.5f}, {2, 1, -0.25f}};
// The quad (1,3,4,2) fans into (1,3,4) and (1,4,2).
const int kTriangleCorners[] = {0, 1, 2, 1, 3, 4, 1, 4, 2};

// Checks the mesh against the test mesh in detail; returns its triangle count for the caller to assert.
std::size_t CheckTestMesh(const MeshData& mesh, const std::string& name) {
  REQUIRE(mesh.submeshes.size() == 1);
  const rayspace::SubMesh& sub = mesh.submeshes[0];
  CHECK(sub.name == name);
  REQUIRE(sub.TriangleCount() == 3);
  REQUIRE(sub.positions.size() == 9);
  for (std::size_t i = 0; i < 9; ++i) {
    CAPTURE(i);
    CHECK(sub.positions[i] == kVertices[kTriangleCorners[i]]);
  }
  CHECK(sub.normals.empty());
  CHECK(sub.material == std::vector<int>{-1, -1, -1});
  CHECK(mesh.materials.empty());
  return sub.TriangleCount();
}

const char* const kAsciiTestMesh =
    "ply\n"
    "format ascii 1.0\n"
    "comment made by hand\n"
    "element vertex 5\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element face 2\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "0 0 0\n"
    "1 0 0\n"
    "0 1 0\n"
    "2 0 0.5\n"
    "2 1 -0.25\n"
    "3 0 1 2\n"
    "4 1 3 4 2\n";

// The test mesh in binary, with an unknown double after the coordinates.
std::string BinaryTestMesh(bool big_endian) {
  std::string header = "ply\n";
  header += big_endian ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
  header +=
      "element vertex 5\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "property double confidence\n"
      "element face 2\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  Bytes body(big_endian);
  for (const glm::vec3& v : kVertices) body << v.x << v.y << v.z << 0.75;
  body << std::uint8_t{3} << std::int32_t{0} << std::int32_t{1} << std::int32_t{2};
  body << std::uint8_t{4} << std::int32_t{1} << std::int32_t{3} << std::int32_t{4} << std::int32_t{2};
  return header + body.str();
}

// The message of the InputError that loading `path` throws, or "<no error>". Any other exception
// escapes and fails the test.
std::string LoadError(const fs::path& path) {
  try {
    LoadPly(path);
  } catch (const rayspace::InputError& e) {
    return e.what();
  }
  return "<no error>";
}

bool Contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("LoadPly reads an ascii triangle and fan-triangulates a quad") {
  TempDir dir;
  CHECK(CheckTestMesh(LoadPly(dir.Write("ascii_mesh.ply", kAsciiTestMesh)), "ascii_mesh") == 3);
}

TEST_CASE("LoadPly tolerates CRLF line endings, blank lines and '+' signs in ascii") {
  TempDir dir;
  std::string text = kAsciiTestMesh;
  std::string crlf;
  for (char c : text) {
    if (c == '\n') crlf += '\r';
    crlf += c;
  }
  crlf.insert(crlf.find("2 0 0.5"), "\r\n");
  const std::size_t plus = crlf.find("2 0 0.5");
  crlf.replace(plus, 7, "+2 0 +0.5");
  CHECK(CheckTestMesh(LoadPly(dir.Write("crlf.ply", crlf)), "crlf") == 3);
}

// tinyobjloader ends a line at a lone CR; the PLY reader does not, so a CR-only file or a lone CR
// inside an ascii body must be refused, never read as other lines than those written.
TEST_CASE("LoadPly refuses CR-only line ends and a lone CR in an ascii body") {
  TempDir dir;
  std::string cr;
  for (char c : std::string(kAsciiTestMesh)) cr += c == '\n' ? '\r' : c;
  CHECK(Contains(LoadError(dir.Write("cr.ply", cr)), "line 1: not a PLY file"));
  std::string lone = kAsciiTestMesh;
  lone.replace(lone.find("1 0 0\n0 1 0\n"), 12, "1 0 0\r0 1 0\n");
  CHECK(Contains(LoadError(dir.Write("lone_cr.ply", lone)), "line 12: vertex 1: more values on the line"));
  std::string header = kAsciiTestMesh;
  header.replace(header.find("element vertex 5\n"), 17, "element vertex 5\r");
  CHECK(Contains(LoadError(dir.Write("header_cr.ply", header)), "line 4: element line must be"));
}

TEST_CASE("LoadPly reads little and big endian binary identically") {
  TempDir dir;
  const MeshData little = LoadPly(dir.Write("little.ply", BinaryTestMesh(false)));
  const MeshData big = LoadPly(dir.Write("big.ply", BinaryTestMesh(true)));
  CHECK(CheckTestMesh(little, "little") == 3);
  CHECK(CheckTestMesh(big, "big") == 3);
  CHECK(little.submeshes[0].positions == big.submeshes[0].positions);
  const MeshData ascii = LoadPly(dir.Write("ascii.ply", kAsciiTestMesh));
  CHECK(ascii.submeshes[0].positions == little.submeshes[0].positions);
}

TEST_CASE("LoadPly reads every scalar type by either name") {
  TempDir dir;
  for (bool big : {false, true}) {
    CAPTURE(big);
    std::string text = "ply\n";
    text += big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
    text +=
        "element vertex 3\n"
        "property float64 x\n"
        "property int16 y\n"
        "property char z\n"
        "property uint8 a\n"
        "property ushort b\n"
        "property int32 c\n"
        "property uint d\n"
        "property float32 e\n"
        "element face 1\n"
        "property list uint32 uint16 vertex_indices\n"
        "end_header\n";
    Bytes body(big);
    body << 1.5 << std::int16_t{-2} << std::int8_t{-3} << std::uint8_t{200} << std::uint16_t{60000}
         << std::int32_t{-70000} << std::uint32_t{4000000000u} << 1.0f;
    body << 0.0 << std::int16_t{300} << std::int8_t{4} << std::uint8_t{0} << std::uint16_t{0} << std::int32_t{0}
         << std::uint32_t{0} << 0.0f;
    body << -8.25 << std::int16_t{0} << std::int8_t{0} << std::uint8_t{0} << std::uint16_t{0} << std::int32_t{0}
         << std::uint32_t{0} << 0.0f;
    body << std::uint32_t{3} << std::uint16_t{2} << std::uint16_t{1} << std::uint16_t{0};
    const MeshData mesh = LoadPly(dir.Write("types.ply", text + body.str()));
    const std::vector<glm::vec3> expected = {{-8.25f, 0, 0}, {0, 300, 4}, {1.5f, -2, -3}};
    CHECK(mesh.submeshes.at(0).positions == expected);
  }
}

TEST_CASE("LoadPly skips unknown elements and properties, lists included") {
  TempDir dir;
  const std::string header_tail =
      "element material 2\n"
      "property list uchar float tags\n"
      "property uchar red\n"
      "element vertex 5\n"
      "property uchar flags\n"
      "property float x\n"
      "property list ushort double weights\n"
      "property float y\n"
      "property float z\n"
      "property float confidence\n"
      "element face 2\n"
      "property int material_index\n"
      "property list uchar float texcoord\n"
      "property list uchar uint vertex_indices\n"
      "property list uchar uint vertex_index\n"
      "element edge 1\n"
      "property int vertex1\n"
      "property list int short stuff\n"
      "end_header\n";

  SUBCASE("ascii") {
    const std::string text = "ply\nformat ascii 1.0\n" + header_tail +
                             "3 0.5 1.5 2.5 7\n"
                             "0 200\n"
                             "1 0 0 0 0 0.1\n"
                             "2 1 2 0.25 0.5 0 0 0.2\n"
                             "3 0 0 1 0 0.3\n"
                             "4 2 3 4 5 6 0 0.5 0.4\n"
                             "5 2 0 1 -0.25 0.5\n"
                             "0 0 3 0 1 2 3 4 4 4\n"
                             "1 6 1 2 3 4 5 6 4 1 3 4 2 0\n"
                             "0 2 -1 1\n";
    CHECK(CheckTestMesh(LoadPly(dir.Write("unknown_ascii.ply", text)), "unknown_ascii") == 3);
  }
  SUBCASE("binary") {
    for (bool big : {false, true}) {
      CAPTURE(big);
      std::string text = "ply\n";
      text += big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
      text += header_tail;
      Bytes body(big);
      body << std::uint8_t{3} << 0.5f << 1.5f << 2.5f << std::uint8_t{7};
      body << std::uint8_t{0} << std::uint8_t{200};
      for (std::size_t i = 0; i < 5; ++i) {
        const glm::vec3& v = kVertices[i];
        body << std::uint8_t{1} << v.x << std::uint16_t(i);
        for (std::size_t k = 0; k < i; ++k) body << double(k);
        body << v.y << v.z << 0.5f;
      }
      body << std::int32_t{0} << std::uint8_t{2} << 0.0f << 1.0f;
      body << std::uint8_t{3} << std::uint32_t{0} << std::uint32_t{1} << std::uint32_t{2};
      body << std::uint8_t{0};
      body << std::int32_t{1} << std::uint8_t{0};
      body << std::uint8_t{4} << std::uint32_t{1} << std::uint32_t{3} << std::uint32_t{4} << std::uint32_t{2};
      body << std::uint8_t{1} << std::uint32_t{9};
      body << std::int32_t{5} << std::int32_t{2} << std::int16_t{-1} << std::int16_t{1};
      CHECK(CheckTestMesh(LoadPly(dir.Write("unknown_binary.ply", text + body.str())), "unknown_binary") == 3);
    }
  }
}

TEST_CASE("LoadPly accepts vertex_index and a face element declared before the vertices") {
  TempDir dir;
  const std::string text =
      "ply\n"
      "format ascii 1.0\n"
      "element face 2\n"
      "property list uchar int vertex_index\n"
      "element vertex 5\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "end_header\n"
      "3 0 1 2\n"
      "4 1 3 4 2\n"
      "0 0 0\n"
      "1 0 0\n"
      "0 1 0\n"
      "2 0 0.5\n"
      "2 1 -0.25\n";
  CHECK(CheckTestMesh(LoadPly(dir.Write("face_first.ply", text)), "face_first") == 3);
}

TEST_CASE("LoadPly reads vertex normals") {
  TempDir dir;
  const std::string text =
      "ply\n"
      "format ascii 1.0\n"
      "element vertex 4\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "property float nx\n"
      "property float ny\n"
      "property float nz\n"
      "element face 1\n"
      "property list uchar int vertex_indices\n"
      "end_header\n"
      "0 0 0 0 0 1\n"
      "1 0 0 0 1 0\n"
      "1 1 0 1 0 0\n"
      "0 1 0 0 0 -1\n"
      "4 0 1 2 3\n";
  const MeshData mesh = LoadPly(dir.Write("normals.ply", text));
  const rayspace::SubMesh& sub = mesh.submeshes.at(0);
  REQUIRE(sub.TriangleCount() == 2);
  const std::vector<glm::vec3> normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 0, -1}};
  CHECK(sub.normals == normals);

  // Without all three components there are no normals; the partial one is just skipped.
  std::string partial = text;
  partial.erase(partial.find("property float nz\n"), 18);
  for (const char* row : {"0 0 0 0 0 1\n", "1 0 0 0 1 0\n", "1 1 0 1 0 0\n", "0 1 0 0 0 -1\n"}) {
    const std::size_t at = partial.find(row);
    partial.replace(at, std::strlen(row), std::string(row, std::strlen(row) - 3) + "\n");
  }
  const MeshData no_normals = LoadPly(dir.Write("partial_normals.ply", partial));
  CHECK(no_normals.submeshes.at(0).TriangleCount() == 2);
  CHECK(no_normals.submeshes.at(0).normals.empty());
}

TEST_CASE("LoadPly reports malformed files with the file name and location") {
  TempDir dir;
  const std::string vertex_header =
      "element vertex 5\n"
      "property float x\n"
      "property float y\n"
      "property float z\n";
  const std::string face_header =
      "element face 2\n"
      "property list uchar int vertex_indices\n";
  const std::string ascii_start = "ply\nformat ascii 1.0\n" + vertex_header + face_header + "end_header\n";
  // Header lines 1-9; vertices on body lines 10-14, faces on 15-16.
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n2 0 0.5\n2 1 -0.25\n";
  const std::string faces = "3 0 1 2\n4 1 3 4 2\n";
  const std::string ascii_good = ascii_start + vertices + faces;
  // The valid ascii file with one value edited, so the body is still large enough to pass the
  // count-versus-size check and the error is the one under test.
  auto edit = [&](std::string_view from, std::string_view to) {
    std::string text = ascii_good;
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
  };
  auto binary_start = [&](bool big) {
    return std::string("ply\n") + (big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n") +
           vertex_header + face_header + "end_header\n";
  };

  struct Case {
    std::string file;      // also what the message must name
    std::string contents;
    std::string expected;  // a fragment the message must contain
  };
  const std::vector<Case> cases = {
      {"not_ply.ply", "hello world\n", "line 1: not a PLY file"},
      {"empty.ply", "", "not a PLY file"},
      {"magic_prefix.ply", "plyx\nformat ascii 1.0\n", "not a PLY file"},
      {"bad_version.ply", "ply\nformat ascii 2.0\n", "line 2: unsupported PLY version '2.0'"},
      {"bad_format.ply", "ply\nformat binary_middle_endian 1.0\n", "line 2: unsupported format"},
      {"format_fields.ply", "ply\nformat ascii\n", "line 2: format line"},
      {"no_format.ply", "ply\n" + vertex_header, "line 2: element before the format line"},
      {"no_format_end.ply", "ply\nend_header\n", "line 2: header has no format line"},
      {"unknown_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\n",
       "line 4: unknown property type 'float128'"},
      {"unknown_list_type.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int128 vertex_indices\n",
       "line 4: unknown property type 'int128'"},
      {"float_count.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\n",
       "line 4: list count type must be an integer type"},
      {"unknown_keyword.ply", "ply\nformat ascii 1.0\nelemnt vertex 1\n", "line 3: unknown header keyword 'elemnt'"},
      {"property_first.ply", "ply\nformat ascii 1.0\nproperty float x\n", "line 3: property before any element"},
      {"duplicate_property.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float x\n",
       "line 5: duplicate property 'x'"},
      {"negative_count.ply", "ply\nformat ascii 1.0\nelement vertex -3\n", "line 3: bad count '-3'"},
      {"huge_count.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n", "line 3: bad count"},
      {"no_end_header.ply", "ply\nformat ascii 1.0\n" + vertex_header, "line 6: header has no end_header line"},
      {"missing_z.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n" + face_header +
           "end_header\n0 0\n",
       "line 3: vertex element has no 'z' property"},
      {"list_x.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n" + face_header +
                         "end_header\n",
       "line 3: vertex property 'x' must not be a list"},
      {"no_face.ply", "ply\nformat ascii 1.0\n" + vertex_header + "end_header\n" + vertices, "no face element"},
      {"no_vertex.ply", "ply\nformat ascii 1.0\n" + face_header + "end_header\n", "no vertex element"},
      {"duplicate_vertex.ply", "ply\nformat ascii 1.0\n" + vertex_header + vertex_header + face_header + "end_header\n",
       "line 7: second 'vertex' element"},
      {"no_indices.ply", "ply\nformat ascii 1.0\n" + vertex_header + "element face 1\nproperty int foo\nend_header\n",
       "line 7: face element has no 'vertex_indices'"},
      {"float_indices.ply",
       "ply\nformat ascii 1.0\n" + vertex_header + "element face 1\nproperty list uchar float vertex_indices\n" +
           "end_header\n",
       "line 7: face property 'vertex_indices' must have an integer item type"},
      {"ascii_truncated.ply", ascii_good.substr(0, ascii_good.size() - 5), "line 16: face 1: unexpected end of file"},
      {"ascii_short_line.ply", edit("3 0 1 2\n", "3 0 1\n"), "line 15: face 0: fewer values on the line"},
      {"ascii_long_line.ply", edit("0 0 0\n", "0 0 0 0\n"), "line 10: vertex 0: more values on the line"},
      {"ascii_trailing.ply", ascii_good + "1 2 3\n", "line 17: unexpected data after the last element"},
      {"ascii_token.ply", edit("0 1 0\n", "0 0.5abc 0\n"), "line 12: vertex 2: '0.5abc' is not a valid float"},
      {"ascii_int_token.ply", edit("3 0 1 2\n", "3 0 1 2.0\n"), "line 15: face 0: '2.0' is not a valid int"},
      {"ascii_count_range.ply", edit("3 0 1 2\n", "300 0 1 2\n"), "line 15: face 0: value 300 out of range for uchar"},
      {"out_of_range.ply", edit("4 1 3 4 2\n", "4 1 3 5 2\n"), "line 16: face 1: vertex index 5 out of range (0..4)"},
      {"negative_index.ply", edit("3 0 1 2\n", "3 0 -1 2\n"), "line 15: face 0: negative vertex index -1"},
      {"two_indices.ply", edit("3 0 1 2\n", "2 0 1\n"), "line 15: face 0: 2 vertex indices, a face needs at least 3"},
      {"nan.ply", edit("2 0 0.5\n", "nan 0 0.5\n"), "line 13: vertex 3: non-finite coordinate"},
      {"inf.ply", edit("2 0 0.5\n", "2 -inf 0.5\n"), "line 13: vertex 3: non-finite coordinate"},
      {"float_overflow.ply", edit("0 1 0\n", "0 1e39 0\n"), "line 12: vertex 2: non-finite coordinate"},
      {"absurd_ascii.ply",
       "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
       "property float z\n" + face_header + "end_header\n0 0 0\n",
       "line 3: element 'vertex' count 1000000000000 is too large"},
      {"absurd_faces.ply",
       "ply\nformat ascii 1.0\n" + vertex_header + "element face 4294967295\n" +
           "property list uchar int vertex_indices\nend_header\n" + vertices,
       "line 7: element 'face' count 4294967295 is too large"},
      {"absurd_unknown.ply",
       "ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\nproperty list uint uint a\n" +
           vertex_header + face_header + "end_header\n",
       "line 3: element 'junk' count 18446744073709551615 is too large"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.file);
    const std::string message = LoadError(dir.Write(c.file, c.contents));
    CHECK_MESSAGE(Contains(message, c.file), message);
    CHECK_MESSAGE(Contains(message, c.expected), message);
    CHECK(!Contains(message, "\n"));
  }

  // The same classes of error in binary bodies, where the location is the element and index.
  for (bool big : {false, true}) {
    CAPTURE(big);
    const std::string prefix = big ? "big_" : "little_";
    const std::string good = BinaryTestMesh(big);
    auto check = [&](const std::string& name, const std::string& contents, std::string_view expected) {
      const std::string file = prefix + name;
      CAPTURE(file);
      const std::string message = LoadError(dir.Write(file, contents));
      CHECK(Contains(message, file));
      CHECK_MESSAGE(Contains(message, expected), message);
    };
    Bytes v(big);
    for (const glm::vec3& p : kVertices) v << p.x << p.y << p.z;

    check("truncated.ply", good.substr(0, good.size() - 2), "face 1: unexpected end of file");
    check("truncated_vertices.ply", good.substr(0, good.find("end_header\n") + 11 + 30),
          "is too large");  // the counts no longer fit in what is left
    {
      Bytes f(big);
      f << std::uint8_t{3} << std::int32_t{0} << std::int32_t{1} << std::int32_t{2};
      f << std::uint8_t{255} << std::int32_t{1} << std::int32_t{3} << std::int32_t{4};
      check("long_list.ply", binary_start(big) + v.str() + f.str(), "face 1: unexpected end of file");
    }
    {
      Bytes f(big);
      f << std::uint8_t{3} << std::int32_t{0} << std::int32_t{1} << std::int32_t{2};
      f << std::uint8_t{3} << std::int32_t{1} << std::int32_t{99} << std::int32_t{2};
      check("out_of_range.ply", binary_start(big) + v.str() + f.str(), "face 1: vertex index 99 out of range (0..4)");
    }
    {
      Bytes f(big);
      f << std::uint8_t{3} << std::int32_t{0} << std::int32_t{-7} << std::int32_t{2};
      f << std::uint8_t{3} << std::int32_t{1} << std::int32_t{3} << std::int32_t{2};
      check("negative_index.ply", binary_start(big) + v.str() + f.str(), "face 0: negative vertex index -7");
    }
    {
      Bytes f(big);
      f << std::uint8_t{1} << std::int32_t{0};
      f << std::uint8_t{3} << std::int32_t{1} << std::int32_t{3} << std::int32_t{2};
      check("short_face.ply", binary_start(big) + v.str() + f.str() + std::string(8, '\0'),
            "face 0: 1 vertex indices, a face needs at least 3");
    }
    {
      Bytes nan(big);
      for (int i = 0; i < 5; ++i) {
        nan << (i == 3 ? std::numeric_limits<float>::quiet_NaN() : 0.0f) << 0.0f
            << (i == 4 ? std::numeric_limits<float>::infinity() : 0.0f);
      }
      check("nan.ply", binary_start(big) + nan.str() + std::string(40, '\0'), "vertex 3: non-finite coordinate");
    }
    {
      std::string text = "ply\n";
      text += big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
      text += "element vertex 1\nproperty double x\nproperty double y\nproperty double z\n" + face_header +
              "end_header\n";
      Bytes b(big);
      b << 0.0 << 1e300 << 0.0;
      check("double_range.ply", text + b.str() + std::string(26, '\0'), "vertex 0: coordinate 1e+300 does not fit");
    }
    {
      std::string text = "ply\n";
      text += big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
      text += vertex_header + "element face 2\nproperty list char int vertex_indices\nend_header\n";
      Bytes f(big);
      f << std::int8_t{-1} << std::int32_t{0} << std::int32_t{0} << std::int32_t{0};
      f << std::uint8_t{0} << std::int32_t{0} << std::int32_t{0} << std::int32_t{0};
      check("negative_length.ply", text + v.str() + f.str(), "face 0: negative list length -1");
    }
  }

  const std::string message = LoadError(dir.path() / "does_not_exist.ply");
  CHECK(Contains(message, "does_not_exist.ply"));
  CHECK(Contains(message, "cannot open"));
  CHECK(Contains(LoadError(dir.path()), "is a directory, not a regular file"));
}

// A small deterministic fuzz pass: every truncation and many random byte edits of valid ascii and
// binary files must either load or throw InputError; anything else (a crash, another exception)
// fails the test.
TEST_CASE("LoadPly survives truncated and corrupted files") {
  TempDir dir;
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement extra 1\nproperty list uchar int stuff\n"
      "element vertex 5\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n"
      "property float ny\nproperty float nz\nelement face 2\nproperty list uchar int vertex_indices\n"
      "end_header\n2 1 2\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n2 0 0.5 0 0 1\n2 1 -0.25 0 0 1\n"
      "3 0 1 2\n4 1 3 4 2\n";
  std::string binary = BinaryTestMesh(false);
  binary.insert(binary.find("element vertex"), "element extra 1\nproperty list uint short stuff\n");
  {
    Bytes extra(false);
    extra << std::uint32_t{2} << std::int16_t{1} << std::int16_t{2};
    binary.insert(binary.find("end_header\n") + 11, extra.str());
  }
  REQUIRE(LoadPly(dir.Write("fuzz_seed_ascii.ply", ascii)).submeshes.at(0).TriangleCount() == 3);
  REQUIRE(LoadPly(dir.Write("fuzz_seed_binary.ply", binary)).submeshes.at(0).TriangleCount() == 3);

  const fs::path file = dir.path() / "fuzz.ply";
  auto load = [&](const std::string& contents) {
    dir.Write("fuzz.ply", contents);
    try {
      const MeshData mesh = LoadPly(file);
      const rayspace::SubMesh& sub = mesh.submeshes.at(0);
      CHECK(sub.positions.size() == sub.material.size() * 3);
      CHECK((sub.normals.empty() || sub.normals.size() == sub.positions.size()));
    } catch (const rayspace::InputError& e) {
      CHECK(Contains(e.what(), "fuzz.ply"));
    }
  };
  std::mt19937 random(12345);
  for (const std::string& seed : {ascii, binary}) {
    for (std::size_t n = 0; n < seed.size(); ++n) load(seed.substr(0, n));
    const char interesting[] = {'\0', '\n', ' ', '-', '9', '\x7f', '\xff', 'e', '.'};
    for (int round = 0; round < 1000; ++round) {
      std::string contents = seed;
      const int edits = 1 + static_cast<int>(random() % 4);
      for (int e = 0; e < edits; ++e) {
        const std::size_t at = random() % contents.size();
        contents[at] = (random() % 2) ? interesting[random() % sizeof(interesting)] : static_cast<char>(random());
      }
      CAPTURE(round);
      load(contents);
    }
  }
}

TEST_CASE("LoadPly loads the Stanford bunny") {
#ifndef RAYSPACE_TEST_DATA_ROOT
  MESSAGE("RAYSPACE_TEST_DATA_ROOT is not defined; skipping the bunny");
#else
  const fs::path root = RAYSPACE_TEST_DATA_ROOT;
  if (rayspace::test::SkipWithoutData("bunny/bun_zipper.ply")) return;
  const auto start = std::chrono::steady_clock::now();
  const MeshData mesh = LoadPly(root / "bunny" / "bun_zipper.ply");
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  MESSAGE("bun_zipper.ply loaded in ", elapsed.count(), " s");

  REQUIRE(mesh.submeshes.size() == 1);
  const rayspace::SubMesh& sub = mesh.submeshes[0];
  CHECK(sub.name == "bun_zipper");
  REQUIRE(sub.TriangleCount() == 69451);
  CHECK(sub.normals.empty());
  CHECK(sub.material.size() == 69451);
  // The first face is "3 21216 21215 20399".
  CHECK(sub.positions[0] == glm::vec3(-0.0923144f, 0.132364f, 0.0182222f));
  CHECK(sub.positions[1] == glm::vec3(-0.0921802f, 0.132348f, 0.0172238f));
  CHECK(sub.positions[2] == glm::vec3(-0.0927674f, 0.130992f, 0.0172311f));
  glm::vec3 lo(std::numeric_limits<float>::max());
  glm::vec3 hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& p : sub.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  CHECK(lo == glm::vec3(-0.0946899f, 0.0329874f, -0.0618736f));
  CHECK(hi == glm::vec3(0.0610091f, 0.187321f, 0.0587997f));
#endif
}
