// Small builders shared by the tests.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <string_view>

#include <doctest/doctest.h>
#include <fmt/format.h>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/procedural.h"
#include "rayspace/scene.h"
#include "rayspace/scene_buffers.h"
#include "rayspace/workgroup.h"
#include "test_settings.h"

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
  // The bytes of `name` (a path under the directory), or "" when it cannot be read.
  std::string Read(const std::string& name) const {
    std::ifstream in(path_ / name, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

 private:
  std::filesystem::path path_;
};

inline std::filesystem::path SourceDir() { return RAYSPACE_SOURCE_DIR; }
inline std::filesystem::path DataRoot() { return RAYSPACE_TEST_DATA_ROOT; }
inline bool HaveData() { return std::filesystem::is_directory(DataRoot()); }
// A case that needs `file` under the data root: without it, prints "data root not found: ..." on
// standard output, which ctest counts as a skip (SKIP_REGULAR_EXPRESSION in tests/CMakeLists.txt)
// rather than a pass, and returns true so that the case returns.
inline bool SkipWithoutData(const std::filesystem::path& file) {
  if (std::filesystem::is_regular_file(DataRoot() / file)) return false;
  std::printf("data root not found: %s (no %s): skipped\n", DataRoot().string().c_str(), file.string().c_str());
  return true;
}

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

// One floor quad, one material and one light, seen from above on an 8x8 frame: the scene of the
// ray-generation and shading known answers, with a builder for hand-made shading points.
struct ShadingFixture {
  Scene scene;
  SceneBuffers b;
  layout::FrameConstants fc{};
  explicit ShadingFixture(MaterialDesc m, LightDesc light = {}) {
    scene.camera.eye = {0, 3, 3};
    scene.camera.target = {0, 0, 0};
    scene.materials.push_back(m);
    scene.lights.push_back(light);
    AddQuad(scene, "floor", {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1});
    b = FlattenScene(scene);
    fc = MakeFrameConstants(scene, b, 8, 8);
  }
  // The colour one shading point gets through the shade pass, its shadow slots (one per light sample)
  // each cast and occluded as `occluded` says; read back from the fixed-point accumulator.
  glm::vec3 Shade(const layout::Surface& s, const std::vector<std::uint32_t>& occluded) const {
    std::vector<std::uint64_t> accum(3 * 64, 0);
    const std::vector<layout::Surface> surfaces{s};
    const std::vector<std::uint32_t> flags(occluded.size(), 1u);
    std::vector<std::uint32_t> offsets(occluded.size());
    for (std::size_t i = 0; i < offsets.size(); ++i) offsets[i] = static_cast<std::uint32_t>(i);
    emu::PassShade({.frame = fc, .surfaces = surfaces, .shadow_flags = flags, .shadow_offsets = offsets, .occluded = occluded,
                    .accum = &accum, .scene = &b});
    return glm::vec3(accum[0], accum[1], accum[2]) / layout::kAccumScale;
  }
  layout::Surface Surface(glm::vec3 p, glm::vec3 n, glm::vec3 incoming) const {
    layout::Surface s{};
    s.position = glm::vec4(p, 1);
    s.normal = glm::vec4(n, 0);
    s.incoming = glm::vec4(incoming, 0);
    s.weight = glm::vec4(1, 1, 1, 0);
    s.info = glm::uvec4(0, 0, 0, 0);
    return s;
  }
};

// A reflection ray from o along d (not normalised), t in (0, inf), leaving primitive `ignore`.
inline layout::Ray MakeRay(glm::vec3 o, glm::vec3 d, std::uint32_t ignore = layout::kNoPrim) {
  layout::Ray r{};
  r.origin_tmin = glm::vec4(o, 0.0f);
  r.direction_tmax = glm::vec4(d, std::numeric_limits<float>::infinity());
  r.info = glm::uvec4(0, ignore, layout::kRayReflection, 0);
  return r;
}

// A triangle from three points (w = 1, as the scene buffers hold them).
inline layout::Triangle MakeTriangle(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  return {glm::vec4(a, 1.0f), glm::vec4(b, 1.0f), glm::vec4(c, 1.0f)};
}

// A ray from o along d over (tmin, tmax), ignoring primitive `ignore`.
inline layout::Ray MakeSegment(glm::vec3 o, glm::vec3 d, float tmin = 0.0f, float tmax = std::numeric_limits<float>::infinity(),
                               std::uint32_t ignore = layout::kNoPrim) {
  layout::Ray r{};
  r.origin_tmin = glm::vec4(o, tmin);
  r.direction_tmax = glm::vec4(d, tmax);
  r.info = glm::uvec4(0u, ignore, 0u, 0u);
  return r;
}

// A closed unit sphere mesh at the origin as one object.
inline Scene SphereScene(int segments, int rings) {
  Scene s;
  s.camera.eye = {0, 0, 5};
  s.materials.push_back(Diffuse("m", glm::vec3(0.5f)));
  MeshData m = GenerateSphere(1.0f, segments, rings, "sphere");
  Object o;
  o.name = "sphere";
  o.positions = m.submeshes[0].positions;
  o.normals = m.submeshes[0].normals;
  o.material.assign(o.TriangleCount(), 0);
  s.objects.push_back(o);
  return s;
}

// A frame rendered with the hierarchy tracer, and the tracer's statistics.
struct HRun {
  emu::FrameResult frame;
  std::vector<emu::BatchStats> stats;
};

inline HRun RunHierarchy(const Scene& s, int w, int h, emu::HierarchyConfig cfg, std::vector<std::uint64_t>* log = nullptr) {
  const SceneBuffers b = FlattenScene(s);
  cfg.image_width = w;
  cfg.image_height = h;
  cfg.candidate_log = log;
  auto tracer = emu::MakeHierarchyTracer(b, cfg);
  emu::FrameOptions fo;
  fo.width = w;
  fo.height = h;
  HRun r;
  r.frame = emu::RenderFrame(s, b, *tracer, fo);
  r.stats = tracer->Stats();
  return r;
}

}  // namespace rayspace::test
