// Tests for the scene JSON loader and the OBJ/MTL loader behind it: parsing of every section,
// transforms (positions and normals), instances, mesh path resolution (beside the scene, data root,
// RAYSPACE_DATA), OBJ polygons, groups and materials, and every class of malformed input, each of
// which must be a one-line InputError naming the file and the field or line.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "rayspace/procedural.h"
#include "rayspace/scene.h"
#include "rayspace/scene_buffers.h"
#include "test_util.h"

namespace {

namespace fs = std::filesystem;
using rayspace::FlattenScene;
using rayspace::InputError;
using rayspace::LightShape;
using rayspace::LoadOptions;
using rayspace::LoadScene;
using rayspace::Scene;
using rayspace::SceneBuffers;
using rayspace::ShadowSlotsPerSurface;
namespace layout = rayspace::layout;

using rayspace::test::TempDir;

// Sets (or unsets) RAYSPACE_DATA for the scope and restores the previous value afterwards.
class ScopedDataEnv {
 public:
  explicit ScopedDataEnv(const std::optional<std::string>& value) {
    if (const char* old = std::getenv("RAYSPACE_DATA")) old_ = old;
    if (value) ::setenv("RAYSPACE_DATA", value->c_str(), 1);
    else ::unsetenv("RAYSPACE_DATA");
  }
  ~ScopedDataEnv() {
    if (old_) ::setenv("RAYSPACE_DATA", old_->c_str(), 1);
    else ::unsetenv("RAYSPACE_DATA");
  }
  ScopedDataEnv(const ScopedDataEnv&) = delete;
  ScopedDataEnv& operator=(const ScopedDataEnv&) = delete;

 private:
  std::optional<std::string> old_;
};

constexpr const char* kCamera =
    R"("camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45})";
constexpr const char* kImage = R"("image": {"width": 64, "height": 48})";

// A scene with the standard camera and image, one light, and the given objects array body.
std::string SceneWith(const std::string& objects, const std::string& materials = "{}") {
  return fmt::format(R"({{
  {},
  {},
  "lights": [{{"position": [0, 4, 4]}}],
  "materials": {},
  "objects": [{}]
}})",
                     kCamera, kImage, materials, objects);
}

// Runs `load`, which must throw InputError; checks the message is one line and contains every
// needle. Returns the message.
std::string ExpectInputError(const std::function<void()>& load, const std::vector<std::string>& needles) {
  std::string message;
  bool threw_input = false;
  try {
    load();
  } catch (const InputError& e) {
    threw_input = true;
    message = e.what();
  } catch (const std::exception& e) {
    FAIL_CHECK("expected rayspace::InputError, got another exception: " << std::string(e.what()));
    return {};
  }
  if (!threw_input) {
    FAIL_CHECK("expected rayspace::InputError, nothing was thrown");
    return {};
  }
  INFO("message: " << std::string(message));
  CHECK(message.find('\n') == std::string::npos);
  CHECK(message.find('\r') == std::string::npos);
  for (const std::string& n : needles) {
    INFO("expected to contain: " << n);
    CHECK(message.find(n) != std::string::npos);
  }
  return message;
}

// Writes `json` as a scene file and expects LoadScene to fail naming the file and the needles.
std::string ExpectSceneError(const std::string& json, std::vector<std::string> needles) {
  TempDir dir;
  const fs::path scene = dir.Write("bad_scene.json", json);
  needles.insert(needles.begin(), scene.string());
  ScopedDataEnv env(std::nullopt);
  return ExpectInputError([&] { LoadScene(scene, LoadOptions{}); }, needles);
}

void CheckVec(glm::vec3 actual, glm::vec3 expected, float tol = 1e-5f) {
  INFO("actual (" << actual.x << ", " << actual.y << ", " << actual.z << "), expected (" << expected.x << ", "
                  << expected.y << ", " << expected.z << ")");
  CHECK(std::fabs(actual.x - expected.x) <= tol);
  CHECK(std::fabs(actual.y - expected.y) <= tol);
  CHECK(std::fabs(actual.z - expected.z) <= tol);
}

const rayspace::Object* FindObject(const Scene& s, const std::string& name) {
  for (const auto& o : s.objects)
    if (o.name == name) return &o;
  return nullptr;
}

// Quad (negative indices), pentagon, and a triangle with negative indices.
constexpr const char* kPolygonsObj = R"(# polygons
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
f -4 -3 -2 -1
v 2 0 0
v 3 0 0
v 3.5 1 0
v 2.5 2 0
v 1.5 1 0
f 5 6 7 8 9
f -5 -4 -3
)";

constexpr const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

}  // namespace

TEST_SUITE("scene_loader") {

TEST_CASE("scene: minimal scene with a generator object parses every section") {
  TempDir dir;
  const fs::path scene = dir.Write("minimal.json", R"({
  "name": "minimal",
  "camera": {"eye": [1, 2, 3], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y_deg": 40},
  "image": {"width": 320, "height": 200},
  "lights": [
    {"position": [0, 10, 0], "color": [1, 0.5, 0.25], "intensity": 2.5, "attenuation": [1, 0.1, 0.01]},
    {"position": [-3, 4, 5]}
  ],
  "materials": {
    "red": {"diffuse": [0.9, 0.1, 0.1], "specular": [0.2, 0.3, 0.4], "shininess": 16,
            "reflectivity": 0.25, "transparency": 0.5, "ior": 1.5},
    "plain": {}
  },
  "objects": [
    {"name": "cube", "generator": "box", "params": {"size": 2, "subdivisions": 2}, "material": "red"}
  ],
  "max_depth": 3
})");
  const Scene s = LoadScene(scene, LoadOptions{});
  CHECK(s.name == "minimal");
  CHECK(s.path == scene);
  CheckVec(s.camera.eye, {1, 2, 3});
  CheckVec(s.camera.target, {0, 0.5f, 0});
  CheckVec(s.camera.up, {0, 1, 0});
  CHECK(s.camera.fov_y_deg == doctest::Approx(40.0));
  CHECK(s.width == 320);
  CHECK(s.height == 200);
  CHECK(s.max_depth == 3);

  REQUIRE(s.lights.size() == 2);
  CheckVec(s.lights[0].position, {0, 10, 0});
  CheckVec(s.lights[0].color, {1, 0.5f, 0.25f});
  CHECK(s.lights[0].intensity == doctest::Approx(2.5));
  CheckVec(s.lights[0].attenuation, {1, 0.1f, 0.01f});
  CheckVec(s.lights[1].position, {-3, 4, 5});
  CheckVec(s.lights[1].color, {1, 1, 1});  // defaults
  CHECK(s.lights[1].intensity == doctest::Approx(1.0));
  CheckVec(s.lights[1].attenuation, {1, 0, 0});

  REQUIRE(s.materials.size() >= 2);
  const rayspace::MaterialDesc* red = nullptr;
  for (const auto& m : s.materials)
    if (m.name == "red") red = &m;
  REQUIRE(red != nullptr);
  CheckVec(red->diffuse, {0.9f, 0.1f, 0.1f});
  CheckVec(red->specular, {0.2f, 0.3f, 0.4f});
  CHECK(red->shininess == 16.0f);
  CHECK(red->reflectivity == doctest::Approx(0.25));
  CHECK(red->transparency == doctest::Approx(0.5));
  CHECK(red->ior == doctest::Approx(1.5));

  REQUIRE(s.objects.size() == 1);
  const rayspace::Object& cube = s.objects[0];
  CHECK(cube.name == "cube");
  CHECK(cube.TriangleCount() == 12u * 2 * 2);  // box: 12 n^2
  CHECK(s.TriangleCount() == 48u);
  CHECK(cube.normals.size() == cube.positions.size());
  REQUIRE(cube.material.size() == cube.TriangleCount());
  for (std::uint32_t m : cube.material) {
    REQUIRE(m < s.materials.size());
    CHECK(s.materials[m].name == "red");
  }
  // Untransformed size-2 box: every coordinate is +-1 or 0.
  for (const glm::vec3& p : cube.positions) {
    CHECK(std::fabs(p.x) <= 1.0f);
    CHECK(std::fabs(p.y) <= 1.0f);
    CHECK(std::fabs(p.z) <= 1.0f);
  }
}

TEST_CASE("scene: defaults for name (file stem), up, max_depth and the default material") {
  TempDir dir;
  const fs::path scene = dir.Write("stem_name.json",
                                   R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov_y_deg": 60},
                                       "image": {"width": 8, "height": 8},
                                       "objects": [{"generator": "box"}]})");
  const Scene s = LoadScene(scene, LoadOptions{});
  CHECK(s.name == "stem_name");
  CheckVec(s.camera.up, {0, 1, 0});
  CHECK(s.max_depth == 1);
  CHECK(s.lights.empty());
  REQUIRE(s.objects.size() == 1);
  CHECK(s.objects[0].TriangleCount() == 12u);
  REQUIRE(s.materials.size() == 1);
  CHECK(s.materials[0].name == "default");
  for (std::uint32_t m : s.objects[0].material) CHECK(m == 0u);
}

TEST_CASE("scene: camera up is judged by its direction, not its length") {
  // A tiny or huge up that is not parallel to the view is valid; the frame is the same as with a
  // unit up (fails before: [0, 1e-7, 0] was refused by an absolute threshold).
  auto scene_with_up = [](const std::string& up) {
    return fmt::format(R"({{"camera": {{"eye": [0, 0, 5], "target": [0, 0, 0], "up": {}, "fov_y_deg": 45}}, {},
                            "objects": [{{"generator": "box"}}]}})",
                       up, kImage);
  };
  TempDir dir;
  ScopedDataEnv env(std::nullopt);
  std::vector<glm::vec3> rights;
  for (const char* up : {"[0, 1, 0]", "[0, 1e-7, 0]", "[0, 1e-30, 0]", "[0, 1e30, 0]", "[1e-38, 1e-38, 0]"}) {
    CAPTURE(up);
    const Scene s = LoadScene(dir.Write("up.json", scene_with_up(up)), LoadOptions{});
    CHECK(glm::length(glm::cross(glm::normalize(glm::dvec3(s.camera.up)), glm::dvec3(0, 1, 0))) < 0.8);
    CHECK(FlattenScene(s).triangles.size() == 12);
  }
  ExpectSceneError(scene_with_up("[0, 0, 0]"), {"camera.up", "zero"});
  ExpectSceneError(scene_with_up("[0, 0, 1e-7]"), {"camera.up", "parallel"});
  ExpectSceneError(scene_with_up("[0, 0, -3e29]"), {"camera.up", "parallel"});
}

TEST_CASE("scene: transform applies scale then rotation then translation to positions and normals") {
  TempDir dir;
  // Scale, then rotate about Z by 90 degrees, then translate.
  const fs::path scene = dir.Write(
      "transform.json",
      SceneWith(R"({"name": "b", "generator": "box",
                    "transform": {"scale": [2, 3, 4], "rotate_deg": [0, 0, 90], "translate": [10, 20, 30]}})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 1);
  const rayspace::Object& o = s.objects[0];
  REQUIRE(o.TriangleCount() == 12u);
  // The generator's first vertex is (0.5, -0.5, -0.5) on the +X face (normal +X).
  // scale -> (1, -1.5, -2); rotate Z 90: (x, y) -> (-y, x) -> (1.5, 1, -2); translate -> (11.5, 21, 28).
  CheckVec(o.positions[0], {11.5f, 21.0f, 28.0f}, 1e-4f);
  // The +X normal goes through the inverse transpose: +X -> rotated to +Y.
  CheckVec(o.normals[0], {0.0f, 1.0f, 0.0f}, 1e-5f);
  // Every vertex of the transformed box lies on the expected bounds.
  for (const glm::vec3& p : o.positions) {
    CHECK(p.x >= 10.0f - 1.5f - 1e-4f);
    CHECK(p.x <= 10.0f + 1.5f + 1e-4f);
    CHECK(p.y >= 20.0f - 1.0f - 1e-4f);
    CHECK(p.y <= 20.0f + 1.0f + 1e-4f);
    CHECK(p.z >= 30.0f - 2.0f - 1e-4f);
    CHECK(p.z <= 30.0f + 2.0f + 1e-4f);
  }
}

TEST_CASE("scene: non-uniform scale with rotation keeps normals unit and perpendicular to their faces") {
  TempDir dir;
  const fs::path scene = dir.Write(
      "skew.json", SceneWith(R"({"generator": "sphere", "params": {"segments": 12, "rings": 6},
                                 "transform": {"scale": [1, 5, 0.25], "rotate_deg": [30, 45, 60], "translate": [1, 2, 3]}},
                                {"generator": "box",
                                 "transform": {"scale": [1, 5, 0.25], "rotate_deg": [30, 45, 60]}})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 2);
  for (const auto& o : s.objects) {
    REQUIRE(o.normals.size() == o.positions.size());
    for (const glm::vec3& n : o.normals) CHECK(glm::length(n) == doctest::Approx(1.0).epsilon(1e-5));
  }
  // Box: vertex normals equal the face normals, so after the inverse transpose they must be
  // perpendicular to the transformed faces' edges and point the same way as the geometric normal.
  const rayspace::Object& box = s.objects[1];
  for (std::size_t t = 0; t < box.TriangleCount(); ++t) {
    const glm::vec3 a = box.positions[3 * t], b = box.positions[3 * t + 1], c = box.positions[3 * t + 2];
    const glm::vec3 geo = glm::normalize(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = box.normals[3 * t + k];
      CHECK(std::fabs(glm::dot(n, glm::normalize(b - a))) < 1e-4f);
      CHECK(std::fabs(glm::dot(n, glm::normalize(c - a))) < 1e-4f);
      CHECK(glm::dot(n, geo) > 0.999f);
    }
  }
}

// A box's normals are the scale's axes, which the matrix and its inverse transpose map alike; a
// slanted normal under a non-uniform scale tells them apart.
TEST_CASE("scene: a slanted OBJ normal under scale (2, 1, 1) goes through the inverse transpose") {
  TempDir dir;
  dir.Write("slant.obj", "v 0 0 0\nv 1 -1 0\nv 0 0 1\nvn 0.70710678 0.70710678 0\nf 1//1 2//1 3//1\n");
  const fs::path scene =
      dir.Write("slant.json", SceneWith(R"({"name": "s", "mesh": "slant.obj", "transform": {"scale": [2, 1, 1]}})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 1);
  REQUIRE(s.objects[0].TriangleCount() == 1u);
  // inverse transpose diag(1/2, 1, 1): (1, 1, 0) -> (0.5, 1, 0); the matrix would give (2, 1, 0).
  const glm::vec3 expected = glm::normalize(glm::vec3(0.5f, 1.0f, 0.0f));
  for (int k = 0; k < 3; ++k) CheckVec(s.objects[0].normals[k], expected, 1e-5f);
  // The plane x + y = 0 stays perpendicular to its normal: scaled, it is x/2 + y = 0.
  const glm::vec3 edge = s.objects[0].positions[1] - s.objects[0].positions[0];
  CHECK(std::fabs(glm::dot(s.objects[0].normals[0], edge)) < 1e-5f);
}

// A sphere of radius r scaled by (a, b, c) is the ellipsoid (x/ar)^2 + (y/br)^2 + (z/cr)^2 = 1, whose
// normal at p is the gradient's direction (x/a^2, y/b^2, z/c^2): the sphere's radial vertex normals
// must land on it.
TEST_CASE("scene: an ellipsoid's vertex normals are its analytic gradient") {
  TempDir dir;
  const fs::path scene = dir.Write(
      "ellipsoid.json", SceneWith(R"({"generator": "sphere", "params": {"radius": 1.5, "segments": 16, "rings": 8},
                                       "transform": {"scale": [3, 1, 0.5], "translate": [4, -2, 7]}})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 1);
  const rayspace::Object& o = s.objects[0];
  REQUIRE(o.normals.size() == o.positions.size());
  for (std::size_t i = 0; i < o.positions.size(); ++i) {
    const glm::vec3 p = o.positions[i] - glm::vec3(4, -2, 7);
    const glm::vec3 gradient = glm::normalize(glm::vec3(p.x / 9.0f, p.y, p.z / 0.25f));
    INFO("vertex " << i);
    CheckVec(o.normals[i], gradient, 1e-4f);
  }
}

TEST_CASE("scene: instances make one object per instance named name#k") {
  TempDir dir;
  const fs::path scene = dir.Write(
      "instances.json", SceneWith(R"({"name": "crate", "generator": "box", "instances": [
                                        {"translate": [0, 0, 0]},
                                        {"translate": [5, 0, 0]},
                                        {"translate": [0, 7, 0], "scale": 2}]})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 3);
  CHECK(s.objects[0].name == "crate#0");
  CHECK(s.objects[1].name == "crate#1");
  CHECK(s.objects[2].name == "crate#2");
  CHECK(s.TriangleCount() == 36u);
  CheckVec(s.objects[0].positions[0], {0.5f, -0.5f, -0.5f});
  CheckVec(s.objects[1].positions[0], {5.5f, -0.5f, -0.5f});
  CheckVec(s.objects[2].positions[0], {1.0f, 6.0f, -1.0f});
}

TEST_CASE("scene: mesh path resolution beside the scene or via LoadOptions.data_root or RAYSPACE_DATA") {
  TempDir scenes, data;
  data.Write("meshes/tri.obj", kTriangleObj);
  const std::string objects = R"({"name": "t", "mesh": "meshes/tri.obj"})";
  const fs::path scene = scenes.Write("scene.json", SceneWith(objects));

  SUBCASE("absent everywhere: error names the path and suggests --data") {
    ScopedDataEnv env(std::nullopt);
    ExpectInputError([&] { LoadScene(scene, LoadOptions{}); },
                     {scene.string(), "objects[0].mesh", "meshes/tri.obj", "--data"});
  }
  SUBCASE("via LoadOptions.data_root") {
    ScopedDataEnv env(std::nullopt);
    LoadOptions lo;
    lo.data_root = data.path();
    const Scene s = LoadScene(scene, lo);
    REQUIRE(s.objects.size() == 1);
    CHECK(s.objects[0].name == "t");
    CHECK(s.objects[0].TriangleCount() == 1u);
  }
  SUBCASE("via RAYSPACE_DATA") {
    ScopedDataEnv env(data.path().string());
    const Scene s = LoadScene(scene, LoadOptions{});
    REQUIRE(s.objects.size() == 1);
    CHECK(s.objects[0].TriangleCount() == 1u);
  }
  SUBCASE("data_root given but the mesh is not there either: error lists both places") {
    ScopedDataEnv env(std::nullopt);
    TempDir empty;
    LoadOptions lo;
    lo.data_root = empty.path();
    ExpectInputError([&] { LoadScene(scene, lo); },
                     {scene.string(), "objects[0].mesh", (scenes.path() / "meshes/tri.obj").string(),
                      (empty.path() / "meshes/tri.obj").string()});
  }
  SUBCASE("beside the scene wins over the data root") {
    ScopedDataEnv env(std::nullopt);
    scenes.Write("meshes/tri.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 2 2 0\nf 1 2 4 3\n");
    LoadOptions lo;
    lo.data_root = data.path();
    const Scene s = LoadScene(scene, lo);
    REQUIRE(s.objects.size() == 1);
    CHECK(s.objects[0].TriangleCount() == 2u);  // the quad beside the scene, not the data root's triangle
  }
}

TEST_CASE("scene: OBJ negative indices and quad and pentagon fan-triangulated as (0 k k+1)") {
  TempDir dir;
  dir.Write("poly.obj", kPolygonsObj);
  const fs::path scene = dir.Write("poly.json", SceneWith(R"({"name": "p", "mesh": "poly.obj"})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 1);
  const rayspace::Object& o = s.objects[0];
  CHECK(o.name == "p");
  REQUIRE(o.TriangleCount() == 2u + 3u + 1u);
  const std::vector<glm::vec3> v = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0},
                                    {3, 0, 0}, {3.5f, 1, 0}, {2.5f, 2, 0}, {1.5f, 1, 0}};
  const int expected[6][3] = {{0, 1, 2}, {0, 2, 3},              // quad
                              {4, 5, 6}, {4, 6, 7}, {4, 7, 8},   // pentagon
                              {4, 5, 6}};                        // f -5 -4 -3
  for (int t = 0; t < 6; ++t) {
    for (int k = 0; k < 3; ++k) {
      INFO("triangle " << t << " corner " << k);
      const glm::vec3 p = o.positions[3 * t + k];
      const glm::vec3 e = v[expected[t][k]];
      CHECK(p.x == e.x);
      CHECK(p.y == e.y);
      CHECK(p.z == e.z);
    }
  }
  // No vertex normals in the file: the face normal (+Z for these counter-clockwise faces) is used.
  for (const glm::vec3& n : o.normals) CheckVec(n, {0, 0, 1});
}

TEST_CASE("scene: OBJ o and g groups become separate objects") {
  TempDir dir;
  dir.Write("groups.obj", R"(v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
o first
f 1 2 3
g second
f 2 4 3
f 1 2 4
)");
  SUBCASE("named scene object: name/group") {
    const fs::path scene = dir.Write("groups.json", SceneWith(R"({"name": "m", "mesh": "groups.obj"})"));
    const Scene s = LoadScene(scene, LoadOptions{});
    REQUIRE(s.objects.size() == 2);
    const rayspace::Object* first = FindObject(s, "m/first");
    const rayspace::Object* second = FindObject(s, "m/second");
    REQUIRE(first != nullptr);
    REQUIRE(second != nullptr);
    CHECK(first->TriangleCount() == 1u);
    CHECK(second->TriangleCount() == 2u);
    CheckVec(first->positions[1], {1, 0, 0});
    CheckVec(second->positions[1], {1, 1, 0});
  }
  SUBCASE("unnamed scene object: group names") {
    const fs::path scene = dir.Write("groups2.json", SceneWith(R"({"mesh": "groups.obj"})"));
    const Scene s = LoadScene(scene, LoadOptions{});
    REQUIRE(s.objects.size() == 2);
    CHECK(FindObject(s, "first") != nullptr);
    CHECK(FindObject(s, "second") != nullptr);
  }
}

TEST_CASE("scene: OBJ MTL Kd Ks Ns mapped and the object material overrides them") {
  TempDir dir;
  dir.Write("mats.mtl", R"(newmtl red
Kd 0.8 0.1 0.2
Ks 0.3 0.4 0.5
Ns 37.6

newmtl blue
Kd 0.1 0.2 0.9
Ks 0 0 0
Ns 10.2
)");
  dir.Write("mats.obj", R"(mtllib mats.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
usemtl red
f 1 2 3
usemtl blue
f 2 4 3
)");
  SUBCASE("MTL materials join the scene as object/material") {
    const fs::path scene = dir.Write("mats.json", SceneWith(R"({"name": "thing", "mesh": "mats.obj"})"));
    const Scene s = LoadScene(scene, LoadOptions{});
    REQUIRE(s.objects.size() == 1);
    const rayspace::Object& o = s.objects[0];
    REQUIRE(o.TriangleCount() == 2u);
    REQUIRE(o.material[0] < s.materials.size());
    REQUIRE(o.material[1] < s.materials.size());
    const rayspace::MaterialDesc& red = s.materials[o.material[0]];
    const rayspace::MaterialDesc& blue = s.materials[o.material[1]];
    CHECK(red.name == "thing/red");
    CHECK(blue.name == "thing/blue");
    CheckVec(red.diffuse, {0.8f, 0.1f, 0.2f});
    CheckVec(red.specular, {0.3f, 0.4f, 0.5f});
    CHECK(red.shininess == 38.0f);  // rounded to an integer exponent
    CheckVec(blue.diffuse, {0.1f, 0.2f, 0.9f});
    CHECK(blue.shininess == 10.0f);
  }
  SUBCASE("the object's material overrides the MTL") {
    const fs::path scene = dir.Write(
        "mats2.json", SceneWith(R"({"name": "thing", "mesh": "mats.obj", "material": "gold"})",
                                R"({"gold": {"diffuse": [1, 0.8, 0], "shininess": 64}})"));
    const Scene s = LoadScene(scene, LoadOptions{});
    REQUIRE(s.objects.size() == 1);
    const rayspace::Object& o = s.objects[0];
    REQUIRE(o.TriangleCount() == 2u);
    for (std::uint32_t m : o.material) {
      REQUIRE(m < s.materials.size());
      CHECK(s.materials[m].name == "gold");
    }
    for (const auto& m : s.materials) CHECK(m.name.find("thing/") == std::string::npos);
  }
}

// ---------------------------------------------------------------------------------------------
// Malformed scenes.

TEST_CASE("scene: malformed scene JSON") {
  SUBCASE("missing file") {
    TempDir dir;
    const fs::path missing = dir.path() / "nope.json";
    ExpectInputError([&] { LoadScene(missing, LoadOptions{}); }, {missing.string()});
  }
  SUBCASE("invalid JSON reports line and column") {
    const std::string msg = ExpectSceneError("{\n  \"camera\": {\n    \"eye\": [0, 0, 5],,\n  }\n}\n", {"line", "column"});
    CHECK(msg.find("line 3") != std::string::npos);
  }
  SUBCASE("truncated JSON") { ExpectSceneError("{\"camera\": {", {"line", "column"}); }
  SUBCASE("top level not an object") { ExpectSceneError("[1, 2, 3]", {"scene"}); }
  SUBCASE("missing camera") {
    ExpectSceneError(fmt::format(R"({{{}, "objects": [{{"generator": "box"}}]}})", kImage), {"camera", "missing"});
  }
  SUBCASE("missing image") {
    ExpectSceneError(fmt::format(R"({{{}, "objects": [{{"generator": "box"}}]}})", kCamera), {"image", "missing"});
  }
  SUBCASE("missing objects") { ExpectSceneError(fmt::format(R"({{{}, {}}})", kCamera, kImage), {"objects"}); }
  SUBCASE("empty objects") { ExpectSceneError(fmt::format(R"({{{}, {}, "objects": []}})", kCamera, kImage), {"objects"}); }
  SUBCASE("unknown key: typo fov_deg") {
    ExpectSceneError(R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov_deg": 45},
                        "image": {"width": 8, "height": 8}, "objects": [{"generator": "box"}]})",
                     {"camera.fov_deg", "unknown key"});
  }
  SUBCASE("unknown top-level key") {
    ExpectSceneError(fmt::format(R"({{{}, {}, "objcts": [], "objects": [{{"generator": "box"}}]}})", kCamera, kImage),
                     {"objcts", "unknown key"});
  }
  SUBCASE("wrong type: width as a string") {
    ExpectSceneError(fmt::format(R"({{{}, "image": {{"width": "64", "height": 48}}, "objects": [{{"generator": "box"}}]}})",
                                 kCamera),
                     {"image.width"});
  }
  SUBCASE("wrong type: eye not an array of 3") {
    ExpectSceneError(R"({"camera": {"eye": [0, 5], "target": [0, 0, 0], "fov_y_deg": 45},
                        "image": {"width": 8, "height": 8}, "objects": [{"generator": "box"}]})",
                     {"camera.eye"});
  }
  SUBCASE("wrong type: transform scale as a string") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "transform": {"scale": "big"}})"),
                     {"objects[0].transform.scale"});
  }
  SUBCASE("image width 0") {
    ExpectSceneError(fmt::format(R"({{{}, "image": {{"width": 0, "height": 48}}, "objects": [{{"generator": "box"}}]}})",
                                 kCamera),
                     {"image.width", "out of range"});
  }
  SUBCASE("image width 100000") {
    ExpectSceneError(fmt::format(R"({{{}, "image": {{"width": 100000, "height": 48}}, "objects": [{{"generator": "box"}}]}})",
                                 kCamera),
                     {"image.width", "out of range"});
  }
  SUBCASE("image width 64.5 is not an integer") {
    ExpectSceneError(fmt::format(R"({{{}, "image": {{"width": 64.5, "height": 48}}, "objects": [{{"generator": "box"}}]}})",
                                 kCamera),
                     {"image.width"});
  }
  SUBCASE("a number too large for a double (1e400) is reported") {
    // JSON cannot spell NaN or infinity, but 1e400 overflows a double while parsing.
    // Either a JSON error quoting the number or a field error naming camera.eye is fine.
    const std::string msg =
        ExpectSceneError(R"({"camera": {"eye": [0, 0, 1e400], "target": [0, 0, 0], "fov_y_deg": 45},
                            "image": {"width": 8, "height": 8}, "objects": [{"generator": "box"}]})",
                         {});
    if (!msg.empty()) {
      INFO("message: " << msg);
      CHECK((msg.find("1e400") != std::string::npos || msg.find("camera.eye") != std::string::npos));
    }
  }
  SUBCASE("a number too large for a float (1e35 > 1e30 limit)") {
    ExpectSceneError(R"({"camera": {"eye": [0, 0, 1e35], "target": [0, 0, 0], "fov_y_deg": 45},
                        "image": {"width": 8, "height": 8}, "objects": [{"generator": "box"}]})",
                     {"camera.eye[2]", "out of range"});
  }
  SUBCASE("camera target equals eye") {
    ExpectSceneError(R"({"camera": {"eye": [1, 1, 1], "target": [1, 1, 1], "fov_y_deg": 45},
                        "image": {"width": 8, "height": 8}, "objects": [{"generator": "box"}]})",
                     {"camera.target"});
  }
  SUBCASE("fov out of range") {
    ExpectSceneError(R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov_y_deg": 180},
                        "image": {"width": 8, "height": 8}, "objects": [{"generator": "box"}]})",
                     {"camera.fov_y_deg", "out of range"});
  }
  SUBCASE("max_depth too large") {
    ExpectSceneError(fmt::format(R"({{{}, {}, "max_depth": 17, "objects": [{{"generator": "box"}}]}})", kCamera, kImage),
                     {"max_depth", "out of range"});
  }
  SUBCASE("reflectivity 1.5") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "material": "m"})", R"({"m": {"reflectivity": 1.5}})"),
                     {"materials.m.reflectivity", "out of range"});
  }
  SUBCASE("reflectivity + transparency > 1") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "material": "m"})",
                               R"({"m": {"reflectivity": 0.6, "transparency": 0.5}})"),
                     {"materials.m", "reflectivity + transparency"});
  }
  SUBCASE("shininess 2.5 is not an integer") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "material": "m"})", R"({"m": {"shininess": 2.5}})"),
                     {"materials.m.shininess", "integer"});
  }
  SUBCASE("unknown material key") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "material": "m"})", R"({"m": {"difuse": [1, 1, 1]}})"),
                     {"materials.m.difuse", "unknown key"});
  }
  SUBCASE("unknown material name") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "material": "gold"})", R"({"m": {}})"),
                     {"objects[0].material", "gold"});
  }
  SUBCASE("both mesh and generator") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "mesh": "x.obj"})"), {"objects[0]", "exactly one"});
  }
  SUBCASE("neither mesh nor generator") { ExpectSceneError(SceneWith(R"({"name": "x"})"), {"objects[0]"}); }
  SUBCASE("unknown generator") {
    ExpectSceneError(SceneWith(R"({"generator": "teapot"})"), {"objects[0]", "teapot"});
  }
  SUBCASE("bad generator parameter") {
    ExpectSceneError(SceneWith(R"({"generator": "sphere", "params": {"segments": 2}})"), {"objects[0]", "segments"});
  }
  SUBCASE("transform and instances together") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "transform": {}, "instances": [{}]})"), {"objects[0]"});
  }
  SUBCASE("unknown transform key") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "transform": {"rotate": [0, 0, 0]}})"),
                     {"objects[0].transform.rotate", "unknown key"});
  }
  SUBCASE("scale 0 in an instance") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "instances": [{}, {"scale": 0}]})"),
                     {"objects[0].instances[1].scale", "out of range"});
  }
  SUBCASE("scale 1e30 is out of range") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "transform": {"scale": 1e30}})"),
                     {"objects[0].transform.scale", "out of range"});
  }
  SUBCASE("lights with all-zero attenuation") {
    ExpectSceneError(fmt::format(R"({{{}, {}, "lights": [{{"position": [0, 1, 0], "attenuation": [0, 0, 0]}}],
                                     "objects": [{{"generator": "box"}}]}})",
                                 kCamera, kImage),
                     {"lights[0].attenuation", "zero"});
  }
  SUBCASE("light without a position") {
    ExpectSceneError(fmt::format(R"({{{}, {}, "lights": [{{"position": [0, 1, 0]}}, {{"intensity": 2}}],
                                     "objects": [{{"generator": "box"}}]}})",
                                 kCamera, kImage),
                     {"lights[1].position", "missing"});
  }
  SUBCASE("negative light intensity") {
    ExpectSceneError(fmt::format(R"({{{}, {}, "lights": [{{"position": [0, 1, 0], "intensity": -1}}],
                                     "objects": [{{"generator": "box"}}]}})",
                                 kCamera, kImage),
                     {"lights[0].intensity", "out of range"});
  }
}

// ---------------------------------------------------------------------------------------------
// Malformed meshes, reached through a scene.

namespace {
// Writes `obj` as bad.obj beside a scene that uses it; expects an error naming bad.obj and `needles`.
std::string ExpectObjError(const std::string& obj, std::vector<std::string> needles,
                           const std::string& object_extra = "") {
  TempDir dir;
  const fs::path mesh = dir.Write("bad.obj", obj);
  const fs::path scene = dir.Write("scene.json", SceneWith(R"({"name": "bad", "mesh": "bad.obj")" + object_extra + "}"));
  needles.insert(needles.begin(), mesh.string());
  ScopedDataEnv env(std::nullopt);
  return ExpectInputError([&] { LoadScene(scene, LoadOptions{}); }, needles);
}
}  // namespace

TEST_CASE("scene: a bad generator parameter names the file, object, generator, parameter and value") {
  // Generator params go through the loader's checked readers: one line, field path and value.
  SUBCASE("wrong type") {
    const std::string msg = ExpectSceneError(SceneWith(R"({"generator": "sphere", "params": {"segments": "many"}})"),
                                             {"objects[0]: generator 'sphere': params.segments: expected an integer, got \"many\""});
    CHECK(msg.find("InputError") == std::string::npos);
  }
  SUBCASE("negative count") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "params": {"subdivisions": -3}})"),
                     {"objects[0]: generator 'box': params.subdivisions: -3 out of range [1, 1024]"});
  }
  SUBCASE("count out of range") {
    ExpectSceneError(SceneWith(R"({"generator": "wavy", "params": {"resolution": 5000}})"),
                     {"objects[0]: generator 'wavy': params.resolution: 5000 out of range [1, 4096]"});
  }
  SUBCASE("count too large for any integer") {
    ExpectSceneError(SceneWith(R"({"generator": "sphere", "params": {"rings": 18446744073709551615}})"),
                     {"params.rings: 18446744073709551615 out of range [2, 4096]"});
  }
  SUBCASE("fractional count") {
    ExpectSceneError(SceneWith(R"({"generator": "lamp", "params": {"detail": 2.5}})"),
                     {"objects[0]: generator 'lamp': params.detail: expected an integer, got 2.5"});
  }
  SUBCASE("zero length") {
    ExpectSceneError(SceneWith(R"({"generator": "cylinder", "params": {"height": 0}})"),
                     {"params.height: 0 out of range (0, 1000000]"});
  }
  SUBCASE("size component of the wrong type") {
    ExpectSceneError(SceneWith(R"({"generator": "box", "params": {"size": [1, "2", 3]}})"),
                     {"params.size[1]: expected a number, got \"2\""});
  }
  SUBCASE("flag of the wrong type") {
    ExpectSceneError(SceneWith(R"({"generator": "cornell_room", "params": {"closed": "yes"}})"),
                     {"params.closed: expected true or false, got \"yes\""});
  }
  SUBCASE("unknown parameter lists the known ones") {
    ExpectSceneError(SceneWith(R"({"generator": "desk", "params": {"segments": 8}})"),
                     {"params.segments: unknown key (known: detail)"});
  }
  SUBCASE("the second object is named") {
    ExpectSceneError(SceneWith(R"({"generator": "box"}, {"generator": "sphere", "params": {"radius": -1}})"),
                     {"objects[1]: generator 'sphere': params.radius: -1 out of range (0, 1000000]"});
  }
  SUBCASE("NaN (not writable in JSON text, so through Generate)") {
    const nlohmann::json params = {{"radius", std::numeric_limits<double>::quiet_NaN()}};
    ExpectInputError([&] { rayspace::Generate("sphere", params, "scene.json: objects[2]"); },
                     {"scene.json: objects[2]: generator 'sphere': params.radius: nan is not finite"});
  }
  SUBCASE("infinity") {
    const nlohmann::json params = {{"amplitude", std::numeric_limits<double>::infinity()}};
    ExpectInputError([&] { rayspace::Generate("wavy", params, "scene.json: objects[0]"); },
                     {"params.amplitude: inf is not finite"});
  }
}

TEST_CASE("scene: malformed OBJ meshes") {
  SUBCASE("bad vertex coordinate 'abc'") {
    CHECK_FALSE(ExpectObjError("# header\nv 0 0 0\nv 1 2 abc\nv 0 1 0\nf 1 2 3\n", {":3:", "abc"}).empty());
  }
  SUBCASE("vertex with two coordinates") { CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", {":2:"}).empty()); }
  SUBCASE("face index out of range") {
    CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n", {":5:", "out of range"}).empty());
  }
  SUBCASE("negative face index out of range") {
    CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", {":4:", "out of range"}).empty());
  }
  SUBCASE("face index 0") { CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", {":4:"}).empty()); }
  SUBCASE("face of 2 vertices") { CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", {":4:", "3 vertices"}).empty()); }
  SUBCASE("vertex 1e39 is not finite as a float") {
    CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n", {":2:", "1e39"}).empty());
  }
  SUBCASE("vertex nan") { CHECK_FALSE(ExpectObjError("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", {":2:"}).empty()); }
  SUBCASE("normal index out of range") {
    CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n", {":5:", "normal"}).empty());
  }
  SUBCASE("no faces") { CHECK_FALSE(ExpectObjError("v 0 0 0\nv 1 0 0\nv 0 1 0\n", {"no faces"}).empty()); }
  SUBCASE("unsupported mesh extension") {
    TempDir dir;
    dir.Write("mesh.stl", "solid x\n");
    const fs::path scene = dir.Write("scene.json", SceneWith(R"({"mesh": "mesh.stl"})"));
    CHECK_FALSE(ExpectInputError([&] { LoadScene(scene, LoadOptions{}); }, {"mesh.stl", ".stl"}).empty());
  }
}

TEST_CASE("scene: a transform that leaves the coordinate domain is an error naming the object") {
  // The vertex is finite as a float in the file but not after the transform: scale 1e12 on the
  // coordinate 1e30 gives 1e42 > FLT_MAX. (A scale of 1e30 itself is rejected as out of range.)
  TempDir dir;
  dir.Write("far.obj", "v 1e30 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
  const fs::path scene = dir.Write(
      "far.json", SceneWith(R"({"generator": "box"}, {"name": "far", "mesh": "far.obj", "transform": {"scale": 1e12}})"));
  ScopedDataEnv env(std::nullopt);
  CHECK_FALSE(ExpectInputError([&] { LoadScene(scene, LoadOptions{}); }, {scene.string(), "objects[1]", "coordinate domain"}).empty());
}

TEST_CASE("scene: a placement inside 2^62 loads, one beyond it is an error") {
  // Radius 1e6 (the generators' limit) scaled by 1e12 and moved by 1e18 stays below 2^62 (4.6e18).
  TempDir dir;
  const fs::path scene = dir.Write(
      "big.json", SceneWith(R"({"generator": "sphere", "params": {"radius": 1e6, "segments": 4, "rings": 2},
                                "transform": {"scale": 1e12, "translate": [1e18, 0, 0]}})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.objects.size() == 1);
  for (const glm::vec3& p : s.objects[0].positions) CHECK(std::isfinite(p.x));
  const fs::path far = dir.Write(
      "far.json", SceneWith(R"({"generator": "sphere", "params": {"radius": 1e6, "segments": 4, "rings": 2},
                                "transform": {"scale": 1e12, "translate": [1e30, 0, 0]}})"));
  CHECK_FALSE(ExpectInputError([&] { LoadScene(far, LoadOptions{}); }, {far.string(), "objects[0]", "2^62"}).empty());
}

}  // TEST_SUITE

// ---------------------------------------------------------------------------------------------
// Area lights (docs/scene-format.md, "lights").

namespace {
glm::vec3 Xyz4(glm::vec4 v) { return {v.x, v.y, v.z}; }
std::string SceneWithLights(const std::string& lights) {
  return fmt::format(R"({{{}, {}, "lights": [{}], "objects": [{{"generator": "box"}}]}})", kCamera, kImage, lights);
}
}  // namespace

TEST_CASE("scene: area lights: shapes, sizes, normals and the default of 8 samples") {
  TempDir dir;
  const fs::path scene = dir.Write("area.json", SceneWithLights(R"({"position": [0, 4, 0], "shape": "rect", "size": [2, 1]},
    {"position": [1, 4, 0], "shape": "disk", "radius": 0.5, "normal": [0, -2, 0], "samples": 16},
    {"position": [2, 4, 0], "shape": "sphere", "radius": 0.25, "samples": 1},
    {"position": [3, 4, 0], "shape": "point"})"));
  const Scene s = LoadScene(scene, LoadOptions{});
  REQUIRE(s.lights.size() == 4);
  CHECK(s.lights[0].shape == LightShape::kRect);
  CHECK(s.lights[0].samples == 8);
  CheckVec({s.lights[0].size, 0}, {2, 1, 0});
  CheckVec(s.lights[0].normal, {0, -1, 0});  // the default: facing down
  CHECK(s.lights[1].shape == LightShape::kDisk);
  CHECK(s.lights[1].samples == 16);
  CheckVec(s.lights[1].normal, {0, -1, 0});  // normalised
  CHECK(s.lights[2].shape == LightShape::kSphere);
  CHECK(s.lights[2].samples == 1);
  CHECK(s.lights[3].shape == LightShape::kPoint);
  CHECK(s.lights[3].samples == 1);
  CHECK(s.HasAreaLight());
  CHECK(ShadowSlotsPerSurface(s.lights) == 8 + 16 + 1 + 1);
  // The kernels' lights: half-axes of the rect's size, strata, the first slot of each light.
  const SceneBuffers b = FlattenScene(s);
  CHECK(glm::length(Xyz4(b.lights[0].axis_u)) == doctest::Approx(1.0));
  CHECK(glm::length(Xyz4(b.lights[0].axis_v)) == doctest::Approx(0.5));
  CHECK(glm::dot(Xyz4(b.lights[0].axis_u), Xyz4(b.lights[0].axis_v)) == doctest::Approx(0.0));
  CHECK(b.lights[0].sampling == glm::uvec4(layout::kLightRect, 8, 0, 4));
  CHECK(b.lights[1].sampling == glm::uvec4(layout::kLightDisk, 16, 8, 4));
  CHECK(b.lights[2].sampling == glm::uvec4(layout::kLightSphere, 1, 24, 1));
  CHECK(b.lights[3].sampling == glm::uvec4(layout::kLightPoint, 1, 25, 1));
  CHECK(b.lights[2].position.w == 0.25f);
  CHECK(b.lights[0].attenuation.w == 0.125f);
}

TEST_CASE("scene: a scene of point lights has no area light") {
  TempDir dir;
  const Scene s = LoadScene(dir.Write("points.json", SceneWithLights(R"({"position": [0, 4, 0]})")), LoadOptions{});
  CHECK_FALSE(s.HasAreaLight());
  CHECK(ShadowSlotsPerSurface(s.lights) == 1);
}

TEST_CASE("scene: bad area lights are refused naming the field") {
  SUBCASE("unknown shape") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "tube"})"), {"lights[0].shape", "unknown shape 'tube'"});
  }
  SUBCASE("rect without a size") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "rect"})"), {"lights[0].size", "missing"});
  }
  SUBCASE("rect of zero width") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "rect", "size": [0, 1]})"), {"lights[0].size[0]", "out of range"});
  }
  SUBCASE("size of three numbers") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "rect", "size": [1, 1, 1]})"), {"lights[0].size", "[width, height]"});
  }
  SUBCASE("disk without a radius") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "disk"})"), {"lights[0].radius", "missing"});
  }
  SUBCASE("negative radius") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "sphere", "radius": -1})"), {"lights[0].radius", "out of range"});
  }
  SUBCASE("zero normal") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "disk", "radius": 1, "normal": [0, 0, 0]})"), {"lights[0].normal", "zero"});
  }
  SUBCASE("a point light's samples") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "samples": 8})"), {"lights[0].samples", "only a rect, disk or sphere light"});
  }
  SUBCASE("a sphere's normal") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "sphere", "radius": 1, "normal": [0, 1, 0]})"),
                     {"lights[0].normal", "only a rect or disk light"});
  }
  SUBCASE("a point light's radius") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "radius": 1})"), {"lights[0].radius", "only a disk or sphere light"});
  }
  SUBCASE("zero samples") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "sphere", "radius": 1, "samples": 0})"), {"lights[0].samples", "out of range"});
  }
  SUBCASE("more than 256 samples") {
    ExpectSceneError(SceneWithLights(R"({"position": [0, 4, 0], "shape": "sphere", "radius": 1, "samples": 257})"), {"lights[0].samples", "out of range"});
  }
  SUBCASE("more than 1024 samples in all") {
    std::string lights;
    for (int i = 0; i < 5; ++i) lights += std::string(i ? ", " : "") + R"({"position": [0, 4, 0], "shape": "sphere", "radius": 1, "samples": 256})";
    ExpectSceneError(SceneWithLights(lights), {"lights", "1280 samples in all", "at most 1024"});
  }
}
