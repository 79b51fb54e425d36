// Bytes as a scene file: the first byte picks the format (0 scene JSON, 1 OBJ, 2 PLY), the rest is
// the file. Every outcome must be a loaded scene or a one-line InputError; anything else aborts.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "rayspace/error.h"
#include "rayspace/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayspace;
  if (size < 1) return 0;
  static const std::string dir = [] {
    const auto d = std::filesystem::temp_directory_path() / ("rayspace-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  const char* ext[3] = {".json", ".obj", ".ply"};
  const std::string path = dir + "/input" + ext[data[0] % 3];
  {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    if (data[0] % 3 == 0) {
      LoadOptions lo;
      lo.data_root = dir;
      (void)LoadScene(path, lo);
    } else {
      (void)LoadMesh(path);
    }
  } catch (const InputError& e) {
    const std::string msg = e.what();
    if (msg.empty() || msg.find('\n') != std::string::npos) {
      std::fprintf(stderr, "error message: '%s'\n", msg.c_str());
      std::fprintf(stderr, "FINDING: scene_load: the error is not one line\n");
      std::abort();
    }
  }
  return 0;
}
