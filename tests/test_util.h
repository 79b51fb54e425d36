// Small builders shared by the tests.
#pragma once
#include <cstdlib>
#include <filesystem>
#include <string>

#include "rayspace/scene.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::test {

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
