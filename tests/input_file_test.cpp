// Tests for the reading of input files (rayspace/input_file.h): only regular files, bounded, every
// failure one line naming the file; and the loaders that read through it.
#include <sys/stat.h>

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

}  // TEST_SUITE
