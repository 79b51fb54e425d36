// Small builders shared by the tests.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <string_view>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "rayspace/scene.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::test {

// A scratch directory, unique per test case, removed when the test case ends.
class TempDir {
 public:
  TempDir() {
    std::random_device random;
    const std::uint64_t id = (std::uint64_t{random()} << 32) ^ random() ^
                             static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count());
    path_ = std::filesystem::temp_directory_path() / fmt::format("rayspace_test_{:016x}", id);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  // Writes `bytes` to `name` (sub-folders created) and returns the file's path.
  std::filesystem::path Write(const std::string& name, std::string_view bytes) const {
    const std::filesystem::path file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    REQUIRE(out.good());
    return file;
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::filesystem::path SourceDir() { return RAYSPACE_SOURCE_DIR; }
inline std::filesystem::path DataRoot() { return RAYSPACE_TEST_DATA_ROOT; }
inline bool HaveData() { return std::filesystem::is_directory(DataRoot()); }

inline MaterialDesc Diffuse(const std::string& name, glm::vec3 kd) {
  MaterialDesc m;
  m.name = name;
  m.diffuse = kd;
  return m;
}

// Adds a quad (two triangles: (a,b,c) and (a,c,d)) as its own object.
inline void AddQuad(Scene& s, const std::string& name, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d,
                    std::uint32_t material = 0) {
  Object o;
  o.name = name;
  o.positions = {a, b, c, a, c, d};
  const glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
  o.normals.assign(6, n);
  o.material.assign(2, material);
  s.objects.push_back(o);
}

inline Scene LoadBundled(const std::string& file) {
  LoadOptions lo;
  lo.data_root = DataRoot();
  return LoadScene(SourceDir() / "scenes" / file, lo);
}

}  // namespace rayspace::test
