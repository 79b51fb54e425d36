// Tests for the reading of input files (rayspace/input_file.h): only regular files, bounded, gzip
// undone while reading, every failure one line naming the file; and the loaders that read through it.
#include <sys/stat.h>
#include <zlib.h>

#include <filesystem>
#include <functional>
#include <string>

#include <doctest/doctest.h>

#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/scene.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using rayspace::InputFile;
using rayspace::ReadInputFile;
using rayspace::test::TempDir;

// The InputError message of `f`, or "<no error>".
std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const rayspace::InputError& e) {
    const std::string message = e.what();
    CHECK(message.find('\n') == std::string::npos);
    return message;
  }
  return "<no error>";
}

bool Contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

fs::path MakeFifo(const TempDir& dir, const std::string& name) {
  const fs::path p = dir.path() / name;
  REQUIRE(::mkfifo(p.c_str(), 0600) == 0);
  return p;
}

// `text` as one gzip member (zlib's deflate with gzip framing).
std::string Gzipped(const std::string& text) {
  z_stream zs{};
  REQUIRE(deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
  std::string out(deflateBound(&zs, text.size()) + 64, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  zs.avail_in = static_cast<uInt>(text.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  REQUIRE(deflate(&zs, Z_FINISH) == Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

const InputFile kGzipMesh{"mesh", rayspace::kMaxDataFileBytes, rayspace::Gzip::kByExtension};
constexpr const char* kTriangleObj = "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

}  // namespace

TEST_SUITE("input_file") {

TEST_CASE("ReadInputFile reads a regular file whole, and an empty one") {
  TempDir dir;
  const std::string text(3 << 20, 'x');  // more than one read chunk
  CHECK(ReadInputFile(dir.Write("big.txt", text), {"test file"}) == text);
  CHECK(ReadInputFile(dir.Write("empty.txt", ""), {"test file"}).empty());
}

TEST_CASE("ReadInputFile refuses anything but a regular file, naming the file and what it is") {
  TempDir dir;
  const fs::path fifo = MakeFifo(dir, "pipe.obj");  // no writer: opening or reading it must not block
  const std::string m = ErrorOf([&] { ReadInputFile(fifo, {"mesh"}); });
  CHECK(Contains(m, fifo.string() + ": mesh is a FIFO (named pipe), not a regular file"));
  const std::string d = ErrorOf([&] { ReadInputFile(dir.path(), {"scene file"}); });
  CHECK(Contains(d, dir.path().string() + ": scene file is a directory, not a regular file"));
  CHECK(Contains(ErrorOf([] { ReadInputFile("/dev/zero", {"material file"}); }),
                 "/dev/zero: material file is a character device, not a regular file"));
  fs::create_symlink("/dev/zero", dir.path() / "zero.mtl");
  CHECK(Contains(ErrorOf([&] { ReadInputFile(dir.path() / "zero.mtl", {"material file"}); }), "is a character device"));
  CHECK(Contains(ErrorOf([&] { ReadInputFile(dir.path() / "missing.json", {"scene file"}); }),
                 "missing.json: cannot open scene file: No such file or directory"));
}

TEST_CASE("ReadInputFile refuses a file over its bound before reading it") {
  TempDir dir;
  const fs::path p = dir.Write("eleven.txt", "hello world");
  CHECK(ReadInputFile(p, {"test file", 11}) == "hello world");
  CHECK(Contains(ErrorOf([&] { ReadInputFile(p, {"test file", 10}); }),
                 "eleven.txt: test file is 11 bytes, more than the 10 bytes rayspace reads"));
  CHECK(Contains(ErrorOf([&] { ReadInputFile(p, {"test file", 0}); }), "more than the 0 bytes"));
}

TEST_CASE("NotRegularFile says what a path is") {
  TempDir dir;
  CHECK(rayspace::NotRegularFile(dir.Write("a.txt", "a")).empty());
  CHECK(rayspace::NotRegularFile(dir.path()) == "is a directory, not a regular file");
  CHECK(rayspace::NotRegularFile(MakeFifo(dir, "p")) == "is a FIFO (named pipe), not a regular file");
  CHECK(rayspace::NotRegularFile(dir.path() / "none") == "does not exist");
}

TEST_CASE("loaders refuse a FIFO, a device or a directory as scene, mesh or MTL file") {
  TempDir dir;
  const fs::path scene_fifo = MakeFifo(dir, "scene.json");
  CHECK(Contains(ErrorOf([&] { rayspace::LoadScene(scene_fifo, {}); }), "scene.json: scene file is a FIFO"));
  CHECK(Contains(ErrorOf([&] { rayspace::LoadMesh(MakeFifo(dir, "m.ply")); }), "m.ply: mesh is a FIFO"));
  CHECK(Contains(ErrorOf([&] { rayspace::LoadMesh(MakeFifo(dir, "m.obj")); }), "m.obj: mesh is a FIFO"));
  MakeFifo(dir, "fifo.mtl");
  const fs::path obj = dir.Write("t.obj", "mtllib fifo.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK(Contains(ErrorOf([&] { rayspace::LoadObj(obj); }), "fifo.mtl: material file (mtllib of t.obj) is a FIFO"));
  const fs::path zero = dir.Write("z.obj", "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK(Contains(ErrorOf([&] { rayspace::LoadObj(zero); }), "/dev/zero: material file (mtllib of z.obj) is a character device"));
  // A missing MTL stays a warning, as before: the mesh loads with the default material.
  const fs::path missing = dir.Write("w.obj", "mtllib none.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK(rayspace::LoadObj(missing).submeshes.at(0).TriangleCount() == 1);
}

TEST_CASE("a mesh path that exists but is not a regular file is refused as such, not reported missing") {
  TempDir dir;
  fs::create_directories(dir.path() / "dir.obj");
  const fs::path scene = dir.Write("s.json", R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov_y_deg": 45},
    "image": {"width": 8, "height": 8}, "objects": [{"mesh": "dir.obj"}]})");
  const std::string m = ErrorOf([&] { rayspace::LoadScene(scene, {}); });
  CHECK(Contains(m, "objects[0]"));
  CHECK(Contains(m, "dir.obj: mesh is a directory, not a regular file"));
}

TEST_CASE("ReadInputFile undoes gzip for a .gz name, members concatenated, and only when asked") {
  TempDir dir;
  const std::string text(3 << 20, 'v');  // decompresses over several chunks
  CHECK(ReadInputFile(dir.Write("a.obj.gz", Gzipped(text)), kGzipMesh) == text);
  CHECK(ReadInputFile(dir.Write("b.OBJ.GZ", Gzipped("ab") + Gzipped("cd")), kGzipMesh) == "abcd");
  CHECK(ReadInputFile(dir.Write("c.obj.gz", Gzipped("")), kGzipMesh).empty());
  const std::string raw = Gzipped("xy");
  CHECK(ReadInputFile(dir.Write("d.obj.gz", raw), {"mesh"}) == raw);  // Gzip::kNo: the bytes as they are
}

TEST_CASE("ReadInputFile refuses corrupt, truncated, empty or non-gzip .gz files naming the file") {
  TempDir dir;
  const std::string good = Gzipped(std::string(kTriangleObj) + std::string(5000, '#'));
  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x55);
  const std::string cases[][3] = {
      {"truncated.obj.gz", good.substr(0, good.size() / 2), "truncated.obj.gz: mesh is truncated gzip data"},
      {"no_trailer.obj.gz", good.substr(0, good.size() - 4), "no_trailer.obj.gz: mesh is truncated gzip data"},
      {"flipped.obj.gz", flipped, "flipped.obj.gz: mesh is not valid gzip data ("},
      {"text.obj.gz", kTriangleObj, "text.obj.gz: mesh is not valid gzip data (incorrect header check)"},
      {"trailing.obj.gz", good + "junk", "trailing.obj.gz: mesh is not valid gzip data ("},
      {"empty.obj.gz", "", "empty.obj.gz: mesh is empty, not gzip data"},
  };
  for (const auto& c : cases) {
    CAPTURE(c[0]);
    const fs::path p = dir.Write(c[0], c[1]);
    const std::string m = ErrorOf([&] { ReadInputFile(p, kGzipMesh); });
    CHECK_MESSAGE(Contains(m, c[2]), m);
  }
}

TEST_CASE("ReadInputFile bounds what gzip data decompresses to") {
  TempDir dir;
  const fs::path bomb = dir.Write("bomb.ply.gz", Gzipped(std::string(8 << 20, '\0')));  // 8 MiB from a few KiB
  CHECK(Contains(ErrorOf([&] { ReadInputFile(bomb, {"mesh", 1 << 20, rayspace::Gzip::kByExtension}); }),
                 "bomb.ply.gz: mesh decompresses to more than the 1 MiB rayspace reads"));
  CHECK(ReadInputFile(bomb, {"mesh", 8 << 20, rayspace::Gzip::kByExtension}).size() == (8u << 20));
  // Exactly at the bound is read; one byte over is refused (the bound counts as it decompresses).
  const fs::path edge = dir.Write("edge.ply.gz", Gzipped(std::string((1 << 20) + 1, 'x')));
  CHECK(Contains(ErrorOf([&] { ReadInputFile(edge, {"mesh", 1 << 20, rayspace::Gzip::kByExtension}); }), "decompresses to more than"));
  CHECK(ReadInputFile(edge, {"mesh", (1 << 20) + 1, rayspace::Gzip::kByExtension}).size() == (1u << 20) + 1);
}

TEST_CASE("ReadInputFile stops a text file's gzip data at its first NUL byte") {
  TempDir dir;
  // 8 MiB of NUL bytes after "v 0": a text format is refused at byte 4, a binary one (PLY) is read.
  const fs::path nul = dir.Write("nul.obj.gz", Gzipped("v 0" + std::string(8 << 20, '\0')));
  CHECK(ErrorOf([&] { ReadInputFile(nul, {"mesh", rayspace::kMaxDataFileBytes, rayspace::Gzip::kByExtension, true}); }) ==
        nul.string() + ": mesh holds a NUL byte at decompressed byte 4, and it is a text file");
  CHECK(ReadInputFile(nul, kGzipMesh).size() == 3 + (8u << 20));
  // The OBJ loader reads its gzip data as text.
  CHECK(Contains(ErrorOf([&] { rayspace::LoadMesh(nul); }), "NUL byte at decompressed byte 4"));
}

TEST_CASE("gzip names: the format and the sub-mesh name come from the name without .gz") {
  CHECK(rayspace::IsGzipName("a/conference.obj.gz"));
  CHECK(rayspace::IsGzipName("x.Gz"));
  CHECK_FALSE(rayspace::IsGzipName("x.gzip"));
  CHECK(rayspace::StemWithoutGz("a/conference.obj.gz") == "conference");
  CHECK(rayspace::StemWithoutGz("bun.ply") == "bun");
  TempDir dir;
  const rayspace::MeshData plain = rayspace::LoadMesh(dir.Write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
  const rayspace::MeshData gz = rayspace::LoadMesh(dir.Write("tri2.obj.gz", Gzipped("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")));
  REQUIRE(gz.submeshes.size() == 1);
  CHECK(gz.submeshes[0].name == "tri2");
  CHECK(gz.submeshes[0].positions == plain.submeshes.at(0).positions);
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const rayspace::MeshData pgz = rayspace::LoadMesh(dir.Write("tri3.PLY.gz", Gzipped(ply)));
  REQUIRE(pgz.submeshes.size() == 1);
  CHECK(pgz.submeshes[0].name == "tri3");
  CHECK(pgz.submeshes[0].positions == plain.submeshes.at(0).positions);
  CHECK(Contains(ErrorOf([&] { rayspace::LoadMesh(dir.Write("m.stl.gz", Gzipped("solid"))); }), "unsupported mesh format '.stl'"));
  // An error inside the decompressed text names the .gz file and the line, as for a plain file.
  CHECK(Contains(ErrorOf([&] { rayspace::LoadMesh(dir.Write("nan.obj.gz", Gzipped("v 0 0 0\nv nan 0 0\n"))); }),
                 "nan.obj.gz:2: non-finite vertex coordinate"));
}

TEST_CASE("the shared conference room loads from its .obj.gz") {
  const fs::path file = fs::path(RAYSPACE_TEST_DATA_ROOT) / "conference" / "conference.obj.gz";
  if (rayspace::test::SkipWithoutData("conference/conference.obj.gz")) return;
  const rayspace::MeshData mesh = rayspace::LoadMesh(file);
  REQUIRE(mesh.submeshes.size() == 1);
  CHECK(mesh.submeshes[0].name == "conference");
  CHECK(mesh.submeshes[0].TriangleCount() == 331179);
}

}  // TEST_SUITE
