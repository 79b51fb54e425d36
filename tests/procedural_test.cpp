#include <cmath>
#include <limits>
#include <string>

#include <doctest/doctest.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "rayspace/procedural.h"

using rayspace::Generate;
using rayspace::InputError;
using rayspace::MeshData;
using rayspace::SubMesh;
using nlohmann::json;

namespace {

std::size_t Triangles(const MeshData& m) {
  std::size_t n = 0;
  for (const SubMesh& s : m.submeshes) n += s.TriangleCount();
  return n;
}

// Every generator promises: three normals per triangle, unit length, one material slot per triangle,
// and counter-clockwise winding seen from the side the normals point to.
void CheckWellFormed(const MeshData& m) {
  CHECK(m.materials.empty());
  for (const SubMesh& s : m.submeshes) {
    REQUIRE(s.positions.size() % 3 == 0);
    REQUIRE(s.normals.size() == s.positions.size());
    REQUIRE(s.material.size() == s.TriangleCount());
    for (int mat : s.material) CHECK(mat == -1);
    for (const glm::vec3& n : s.normals) CHECK(std::abs(glm::length(n) - 1.0f) < 1e-5f);
    for (std::size_t t = 0; t < s.TriangleCount(); ++t) {
      glm::vec3 a = s.positions[3 * t], b = s.positions[3 * t + 1], c = s.positions[3 * t + 2];
      glm::vec3 face = glm::cross(b - a, c - a);
      glm::vec3 shading = s.normals[3 * t] + s.normals[3 * t + 1] + s.normals[3 * t + 2];
      REQUIRE(glm::length(face) > 0.0f);
      CHECK(glm::dot(face, shading) > 0.0f);
    }
  }
}

glm::vec3 Centroid(const SubMesh& s, std::size_t t) {
  return (s.positions[3 * t] + s.positions[3 * t + 1] + s.positions[3 * t + 2]) / 3.0f;
}

void Bounds(const MeshData& m, glm::vec3& lo, glm::vec3& hi) {
  lo = glm::vec3(std::numeric_limits<float>::max());
  hi = -lo;
  for (const SubMesh& s : m.submeshes) {
    for (const glm::vec3& p : s.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  }
}

// Expects Generate to throw InputError whose one-line message names `where` and contains `needle`.
void CheckRejects(const std::string& kind, const json& params, const std::string& needle) {
  const std::string where = "scenes/test.json: objects[7]";
  CAPTURE(kind);
  CAPTURE(params.dump());
  try {
    Generate(kind, params, where);
    FAIL("no InputError");
  } catch (const InputError& e) {
    std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find(where) != std::string::npos);
    CHECK(what.find(needle) != std::string::npos);
    CHECK(what.find('\n') == std::string::npos);
  }
}

}  // namespace

TEST_CASE("box: 6 faces of n x n quads, two triangles each") {
  for (int n : {1, 2, 5}) {
    MeshData m = rayspace::GenerateBox({2.0f, 1.0f, 3.0f}, n, false, "b");
    REQUIRE(m.submeshes.size() == 1);
    CHECK(m.submeshes[0].name == "b");
    CHECK(Triangles(m) == static_cast<std::size_t>(6 * n * n * 2));
    CheckWellFormed(m);
    glm::vec3 lo, hi;
    Bounds(m, lo, hi);
    CHECK(lo == glm::vec3(-1.0f, -0.5f, -1.5f));
    CHECK(hi == glm::vec3(1.0f, 0.5f, 1.5f));
  }
}

TEST_CASE("box: normals outward, or inward when asked") {
  for (bool inward : {false, true}) {
    MeshData m = rayspace::GenerateBox({1.0f, 2.0f, 4.0f}, 3, inward, "b");
    const SubMesh& s = m.submeshes[0];
    for (std::size_t t = 0; t < s.TriangleCount(); ++t) {
      float d = glm::dot(s.normals[3 * t], Centroid(s, t));  // centre is the origin
      CHECK((inward ? d < 0.0f : d > 0.0f));
    }
    CheckWellFormed(m);
  }
}

TEST_CASE("sphere: counts, radius and outward normals") {
  // segments 8, rings 5: a fan of 8 at each pole plus 3 bands of 8 quads.
  MeshData m = rayspace::GenerateSphere(2.5f, 8, 5, "s");
  CHECK(Triangles(m) == 8 + 8 + 3 * 8 * 2);
  CheckWellFormed(m);
  const SubMesh& s = m.submeshes[0];
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    CHECK(std::abs(glm::length(s.positions[i]) - 2.5f) < 2.5f * 1e-6f);
    CHECK(glm::length(s.normals[i] - s.positions[i] / 2.5f) < 1e-5f);
  }
  CHECK(Triangles(rayspace::GenerateSphere(1.0f, 3, 2, "s")) == 3 + 3);
}

TEST_CASE("cylinder: side quads and optional cap fans") {
  MeshData capped = rayspace::GenerateCylinder(0.5f, 2.0f, 10, true, "c");
  MeshData open = rayspace::GenerateCylinder(0.5f, 2.0f, 10, false, "c");
  CHECK(Triangles(capped) == 10 * 2 + 10 + 10);
  CHECK(Triangles(open) == 10 * 2);
  CheckWellFormed(capped);
  CheckWellFormed(open);
  glm::vec3 lo, hi;
  Bounds(capped, lo, hi);
  CHECK(lo.y == 0.0f);
  CHECK(hi.y == 2.0f);
  for (const glm::vec3& p : open.submeshes[0].positions) {
    CHECK(std::abs(std::hypot(p.x, p.z) - 0.5f) < 1e-6f);
  }
}

TEST_CASE("wavy: height field with upward normals") {
  MeshData m = rayspace::GenerateWavy(2.0f, 0.1f, 3.0f, 3, "w");
  CHECK(Triangles(m) == 3 * 3 * 2);
  CheckWellFormed(m);
  const SubMesh& s = m.submeshes[0];
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const glm::vec3& p = s.positions[i];
    CHECK(std::abs(p.y - 0.1f * std::cos(3.0f * p.x) * std::cos(3.0f * p.z)) < 1e-6f);
    CHECK(s.normals[i].y > 0.0f);
  }
}

TEST_CASE("cornell room: published measurements, inward walls") {
  MeshData m = rayspace::GenerateCornellRoom(3, true);
  REQUIRE(m.submeshes.size() == 6);
  const char* names[] = {"floor", "ceiling", "back", "front", "left", "right"};
  for (int i = 0; i < 6; ++i) {
    CHECK(m.submeshes[i].name == names[i]);
    CHECK(m.submeshes[i].TriangleCount() == 3 * 3 * 2);
  }
  CheckWellFormed(m);
  glm::vec3 lo, hi;
  Bounds(m, lo, hi);
  CHECK(lo == glm::vec3(0.0f));
  CHECK(hi == glm::vec3(556.0f, 548.8f, 559.2f));
  const glm::vec3 centre(278.0f, 274.4f, 279.6f);
  for (const SubMesh& s : m.submeshes) {
    for (std::size_t t = 0; t < s.TriangleCount(); ++t) {
      CHECK(glm::dot(s.normals[3 * t], centre - Centroid(s, t)) > 0.0f);
    }
  }
  MeshData open = rayspace::GenerateCornellRoom(2, false);
  REQUIRE(open.submeshes.size() == 5);
  for (const SubMesh& s : open.submeshes) CHECK(s.name != "front");
  CHECK(Triangles(open) == 5 * 2 * 2 * 2);
}

TEST_CASE("furniture: 12 d^2 per box plus 32 d per capped cylinder, standing on the floor") {
  struct Piece {
    const char* kind;
    MeshData (*make)(int, const std::string&);
    int boxes, cylinders;
    float max_height;
  };
  const Piece pieces[] = {
      {"desk", &rayspace::GenerateDesk, 3, 4, 0.75f},
      {"chair", &rayspace::GenerateChair, 8, 6, 1.07f},
      {"shelf", &rayspace::GenerateShelf, 28, 0, 1.90f},
      {"monitor", &rayspace::GenerateMonitor, 2, 1, 0.44f},
      {"lamp", &rayspace::GenerateLamp, 1, 3, 0.44f},
  };
  for (const Piece& p : pieces) {
    CAPTURE(p.kind);
    for (int d : {1, 3}) {
      MeshData m = p.make(d, p.kind);
      REQUIRE(m.submeshes.size() == 1);
      CHECK(m.submeshes[0].name == p.kind);
      CHECK(Triangles(m) == static_cast<std::size_t>(12 * d * d * p.boxes + 32 * d * p.cylinders));
      CheckWellFormed(m);
      glm::vec3 lo, hi;
      Bounds(m, lo, hi);
      CHECK(std::abs(lo.y) < 1e-6f);
      CHECK(std::abs(hi.y - p.max_height) < 1e-5f);
      CHECK(hi.x - lo.x < 1.5f);
      CHECK(hi.z - lo.z < 1.0f);
    }
    CHECK(Triangles(Generate(p.kind, json::object(), "w")) == Triangles(p.make(2, p.kind)));
  }
}

TEST_CASE("Generate: dispatch and defaults") {
  CHECK(Triangles(Generate("box", json(nullptr), "w")) == 12);
  CHECK(Triangles(Generate("box", json{{"size", {1, 2, 3}}, {"subdivisions", 4}}, "w")) == 12 * 16);
  CHECK(Triangles(Generate("box", json{{"size", 2.0}, {"subdivisions", 3.0}}, "w")) == 12 * 9);
  CHECK(Triangles(Generate("sphere", json::object(), "w")) == 2 * 32 * 15);
  CHECK(Triangles(Generate("sphere", json{{"radius", 3}, {"segments", 6}, {"rings", 4}}, "w")) == 2 * 6 * 3);
  CHECK(Triangles(Generate("cylinder", json::object(), "w")) == 4 * 32);
  CHECK(Triangles(Generate("cylinder", json{{"caps", false}, {"segments", 5}}, "w")) == 2 * 5);
  CHECK(Triangles(Generate("wavy", json::object(), "w")) == 2 * 32 * 32);
  CHECK(Triangles(Generate("wavy", json{{"resolution", 7}, {"amplitude", 0}}, "w")) == 2 * 49);
  CHECK(Triangles(Generate("cornell_room", json::object(), "w")) == 6 * 2);
  CHECK(Triangles(Generate("cornell_room", json{{"subdivisions", 4}, {"closed", false}}, "w")) == 5 * 32);
  MeshData inward = Generate("box", json{{"inward", true}}, "w");
  CHECK(glm::dot(inward.submeshes[0].normals[0], Centroid(inward.submeshes[0], 0)) < 0.0f);
}

TEST_CASE("Generate: rejects bad input with InputError naming the place") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  CheckRejects("teapot", json::object(), "teapot");
  CheckRejects("Sphere", json::object(), "Sphere");
  CheckRejects("sphere", json{{"radius", 1}, {"colour", 2}}, "params.colour");
  CheckRejects("desk", json{{"segments", 8}}, "params.segments");
  CheckRejects("sphere", json::array({1, 2}), "params");
  CheckRejects("sphere", json{{"segments", "many"}}, "params.segments");
  CheckRejects("sphere", json{{"segments", 2}}, "params.segments");
  CheckRejects("sphere", json{{"segments", 4097}}, "params.segments");
  CheckRejects("sphere", json{{"segments", 8.5}}, "params.segments");
  CheckRejects("sphere", json{{"segments", -1}}, "params.segments");
  CheckRejects("sphere", json{{"segments", 18446744073709551615ull}}, "params.segments");
  CheckRejects("sphere", json{{"rings", 1}}, "params.rings");
  CheckRejects("sphere", json{{"radius", 0}}, "params.radius");
  CheckRejects("sphere", json{{"radius", -2.0}}, "params.radius");
  CheckRejects("sphere", json{{"radius", nan}}, "params.radius");
  CheckRejects("sphere", json{{"radius", inf}}, "params.radius");
  CheckRejects("sphere", json{{"radius", 1e30}}, "params.radius");
  CheckRejects("sphere", json{{"radius", true}}, "params.radius");
  CheckRejects("sphere", json{{"segments", 4096}, {"rings", 4096}}, "triangles");
  CheckRejects("cylinder", json{{"height", 0}}, "params.height");
  CheckRejects("cylinder", json{{"caps", 1}}, "params.caps");
  CheckRejects("box", json{{"size", {1, 2}}}, "params.size");
  CheckRejects("box", json{{"size", {1, 0, 2}}}, "params.size");
  CheckRejects("box", json{{"size", {1, "2", 3}}}, "params.size");
  CheckRejects("box", json{{"subdivisions", 0}}, "params.subdivisions");
  CheckRejects("box", json{{"subdivisions", 1025}}, "params.subdivisions");
  CheckRejects("box", json{{"subdivisions", 600}}, "triangles");
  CheckRejects("box", json{{"inward", "yes"}}, "params.inward");
  CheckRejects("wavy", json{{"amplitude", -0.1}}, "params.amplitude");
  CheckRejects("wavy", json{{"resolution", 2000}}, "triangles");
  CheckRejects("cornell_room", json{{"subdivisions", 1024}}, "triangles");
  CheckRejects("cornell_room", json{{"closed", nullptr}}, "params.closed");
  CheckRejects("lamp", json{{"detail", 0}}, "params.detail");
  CheckRejects("shelf", json{{"detail", 65}}, "params.detail");
}
