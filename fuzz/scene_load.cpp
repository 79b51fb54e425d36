// Bytes as a scene file: the first byte picks the format, the rest is the file. 0: scene JSON,
// 1: OBJ, 2: PLY, 3: MTL (the material file of a fixed OBJ triangle that uses it), 4: gzip data
// named .obj.gz, 5: gzip data named .ply.gz. Every outcome must be a loaded scene or mesh or a
// one-line InputError; anything else aborts.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "rayspace/error.h"
#include "rayspace/scene.h"

namespace {

// The scratch directory; removed at exit, since on tmpfs it holds memory.
std::string& ScratchDir() {
  static std::string dir;
  return dir;
}

void RemoveScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(ScratchDir(), ec);
}

void WriteFile(const std::string& path, const char* data, std::size_t size) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(data, static_cast<std::streamsize>(size));
}

// Loads the file the format byte names; returns nothing, throws what the loaders throw.
void Load(const std::string& dir, unsigned format, const char* data, std::size_t size) {
  using namespace rayspace;
  static const char* const kNames[6] = {"input.json", "input.obj", "input.ply", "input.mtl", "input.obj.gz",
                                        "input.ply.gz"};
  const std::string path = dir + "/" + kNames[format];
  WriteFile(path, data, size);
  if (format == 0) {
    LoadOptions lo;
    lo.data_root = dir;
    (void)LoadScene(path, lo);
  } else if (format == 3) {
    static const char kObj[] = "mtllib input.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    WriteFile(dir + "/uses_mtl.obj", kObj, sizeof kObj - 1);
    (void)LoadMesh(dir + "/uses_mtl.obj");
  } else {
    (void)LoadMesh(path);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  // Every input is written to a file and read back, so the files go to tmpfs when there is one: on
  // a disk-backed /tmp each rewrite of a truncated file waited for the disk (300-600 exec/s, against
  // 9,000-10,000 on /dev/shm, same machine and load).
  static const std::string dir = [] {
    std::error_code ec;
    const std::filesystem::path base =
        std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm") : std::filesystem::temp_directory_path();
    const auto d = base / ("rayspace-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    ScratchDir() = d.string();
    std::atexit(RemoveScratchDir);
    return d.string();
  }();
  try {
    Load(dir, data[0] % 6u, reinterpret_cast<const char*>(data + 1), size - 1);
  } catch (const rayspace::InputError& e) {
    const std::string msg = e.what();
    if (msg.empty() || msg.find('\n') != std::string::npos) {
      std::fprintf(stderr, "error message: '%s'\n", msg.c_str());
      std::fprintf(stderr, "FINDING: scene_load: the error is not one line\n");
      std::abort();
    }
  }
  return 0;
}
