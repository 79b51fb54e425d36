// Hunt and Mark's perspective grids (docs/grids.md): the cube-face mapping and the least distance by
// known answers, the binning's soundness point by point, and grid.trace against brute force.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/grid/tracer.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/light_sample.h"
#include "rayspace/parallel.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_model.h"
#include "tl_util.h"
#include "test_settings.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

SceneBuffers SoupScene(std::vector<layout::Triangle> tris, std::vector<glm::vec3> lights) {
  SceneBuffers b;
  b.triangles = std::move(tris);
  b.lo = glm::vec3(INFINITY);
  b.hi = -b.lo;
  for (const layout::Triangle& t : b.triangles)
    for (const glm::vec4& v : {t.v0, t.v1, t.v2}) {
      b.lo = glm::min(b.lo, Xyz(v));
      b.hi = glm::max(b.hi, Xyz(v));
    }
  std::uint32_t first = 0;
  for (glm::vec3 p : lights) {
    layout::Light l{};
    l.position = glm::vec4(p, 1.0f);
    l.attenuation = glm::vec4(1, 0, 0, 1);
    l.sampling = glm::uvec4(layout::kLightPoint, 1, first++, 1);
    b.lights.push_back(l);
  }
  return b;
}

// A point of triangle t at barycentric (a, b).
glm::dvec3 PointOn(const layout::Triangle& t, double a, double b) {
  const glm::dvec3 v0(Xyz(t.v0)), v1(Xyz(t.v1)), v2(Xyz(t.v2));
  return v0 + (v1 - v0) * a + (v2 - v0) * b;
}

bool Lists(const GridArrays& g, std::uint32_t cell, std::uint32_t tri) {
  for (std::uint32_t i = g.first[cell]; i < g.first[cell + 1]; ++i)
    if (g.triangles[i] == tri) return true;
  return false;
}

}  // namespace

TEST_CASE("grid: a direction's cube face and cell") {
  const grid::FaceUv px = grid::DirectionFace({2, 0.5f, -1});
  CHECK(px.face == 0u);
  CHECK(px.u == 0.25f);   // y / x
  CHECK(px.v == -0.5f);   // z / x
  CHECK(grid::DirectionFace({0, -3, 0}).face == 3u);
  CHECK(grid::DirectionFace({0.1f, 0.2f, -1}).face == 5u);
  CHECK(grid::DirectionFace({1, 1, 0}).face == 0u);  // ties go to the lower axis
  // 4 cells a side: u = 0.25 lies in column 2, v = -0.5 in row 1.
  CHECK(grid::FaceCell(px, 4) == (0u * 4 + 1) * 4 + 2);
  // The face's edges stay in range.
  CHECK(grid::FaceCell(grid::DirectionFace({1, 1, 1}), 4) == 15u);
  CHECK(grid::FaceCell(grid::DirectionFace({1, -1, -1}), 4) == 0u);
}

TEST_CASE("grid: the least distance from a point to a triangle") {
  const glm::dvec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  CHECK(grid::PointTriangleDistance({0.5, 0.5, 3}, a, b, c) == doctest::Approx(3.0));          // above the inside
  CHECK(grid::PointTriangleDistance({-3, -4, 0}, a, b, c) == doctest::Approx(5.0));            // nearest a vertex
  CHECK(grid::PointTriangleDistance({1, -2, 0}, a, b, c) == doctest::Approx(2.0));             // nearest an edge
  CHECK(grid::PointTriangleDistance({2, 2, 0}, a, b, c) == doctest::Approx(std::sqrt(2.0)));  // beyond the long edge
  // Two equal vertices make a segment (conference has such triangles): the distance to it, not 0 / 0,
  // and not a vertex's, which would be more than the least distance.
  const glm::dvec3 d(2, 0, 0);
  CHECK(grid::PointTriangleDistance({1, 1, 0}, a, a, d) == doctest::Approx(1.0));
  CHECK(grid::PointTriangleDistance({1, 1, 0}, a, d, d) == doctest::Approx(1.0));
  CHECK(grid::PointTriangleDistance({1, 1, 0}, d, a, a) == doctest::Approx(1.0));
}

TEST_CASE("grid: every point of every triangle lies in a cell that lists it, no closer than its least distance") {
  const std::vector<glm::vec3> lights{{0.1f, 0.2f, -0.3f}, {3, 2, 1}};
  const SceneBuffers b = SoupScene(test::TlSoup(300, 11), lights);
  const GridArrays g = grid::Build(b, {16, 8});
  REQUIRE(g.light_grids.size() == 2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t checked = 0;
  for (std::uint32_t t = 0; t < b.triangles.size(); ++t)
    for (int k = 0; k < 20; ++k) {
      double s = u(rng), r = u(rng);
      if (s + r > 1) s = 1 - s, r = 1 - r;
      const glm::dvec3 p = PointOn(b.triangles[t], s, r);
      for (std::uint32_t l = 0; l < lights.size(); ++l) {
        const glm::dvec3 d = p - glm::dvec3(lights[l]);
        const glm::vec3 df = glm::vec3(d / glm::length(d));  // a shadow ray's rounded direction
        const std::uint32_t cell = g.light_grids[l].x + grid::FaceCell(grid::DirectionFace(df), g.light_grids[l].y);
        INFO("triangle " << t << " light " << l << " cell " << cell);
        CHECK(Lists(g, cell, t));
        CHECK(static_cast<double>(g.min_dist[cell]) <= glm::length(d));
        ++checked;
      }
      // The regular grid's cell of the point.
      const glm::uvec4 dims = g.volume_dims[0];
      glm::uvec3 c;
      for (int a = 0; a < 3; ++a)
        c[a] = static_cast<std::uint32_t>(std::clamp(std::floor((p[a] - g.volume[0][a]) / g.volume[1][a]), 0.0, dims[a] - 1.0));
      CHECK(Lists(g, dims.w + (c.z * dims.y + c.y) * dims.x + c.x, t));
    }
  CHECK(checked == 300 * 20 * 2);
}

TEST_CASE("grid: grid.trace gives brute force's closest hits and occlusion, shadow rays from the lights included") {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    const std::vector<glm::vec3> lights{{0.05f, 1.5f, 0.0f}, {-0.4f, 0.3f, 0.2f}};
    const SceneBuffers b = SoupScene(test::TlSoup(400, seed), lights);
    for (const grid::Options o : {grid::Options{200, 54}, grid::Options{3, 2}, grid::Options{32, 1}}) {
      const GridArrays g = grid::Build(b, o);
      std::mt19937 rng(seed * 7);
      std::uniform_real_distribution<float> u(-1.2f, 1.2f);
      std::vector<layout::Ray> closest, shadow;
      for (int i = 0; i < 1500; ++i) {
        const glm::vec3 org(u(rng), u(rng), u(rng)), to(u(rng), u(rng), u(rng));
        layout::Ray r = test::MakeSegment(org, to - org, 0.0f, i % 3 == 0 ? 1.0f : INFINITY, i % 5 == 0 ? static_cast<std::uint32_t>(i % 400) : layout::kNoPrim);
        r.info.z = layout::kRayReflection;
        closest.push_back(r);
        // A shadow ray from a light to a point, as raygen.shadow makes it.
        const std::uint32_t l = static_cast<std::uint32_t>(i % 2);
        const glm::vec3 v = to - lights[l];
        const float dist = Length(v);
        layout::Ray s = test::MakeSegment(lights[l], v / dist, 1e-6f, dist * kShadowTmaxFactor);
        s.info = glm::uvec4(0, layout::kNoPrim, layout::kRayShadow, l);
        shadow.push_back(s);
      }
      const auto call = [&](const std::vector<layout::Ray>& rays, std::uint32_t sh) {
        return PassGridTrace({.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes, .light_grids = g.light_grids,
                              .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims, .triangles = b.triangles,
                              .rays = rays, .shadow = sh});
      };
      const GridWalks wc = call(closest, 0), ws = call(shadow, 1);
      std::size_t hits = 0, occluded = 0, skipped = 0;
      for (std::size_t i = 0; i < closest.size(); ++i) {
        INFO("seed " << seed << " cells " << o.cells << " regular " << o.regular << " ray " << i);
        CHECK(wc.hits[i] == test::BruteClosest(b.triangles, closest[i]));
        CHECK(ws.occluded[i] == (test::BruteClosest(b.triangles, shadow[i]) != kMissPacked ? 1u : 0u));
        CHECK(ws.steps[i] == 1u);  // one perspective cell each
        hits += wc.hits[i] != kMissPacked;
        occluded += ws.occluded[i];
        skipped += ws.tests[i] == 0 && !ws.occluded[i];
      }
      // The rays are not trivial: many hit, many are shadowed, and some unoccluded ones skip every test.
      CHECK(hits > 300);
      CHECK(occluded > 300);
      if (o.cells == 200) CHECK(skipped > 50);
    }
  }
}

namespace {
// The unit cube's 12 triangles, wound outwards, as two objects of 6 (the first three faces, the rest).
SceneBuffers Cube() {
  const glm::vec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<layout::Triangle> tris;
  for (const auto& q : quads) {
    tris.push_back(test::MakeTriangle(p[q[0]], p[q[1]], p[q[2]]));
    tris.push_back(test::MakeTriangle(p[q[0]], p[q[2]], p[q[3]]));
  }
  SceneBuffers b = SoupScene(tris, {{0.5f, 3.0f, 0.5f}});
  b.objects = {glm::uvec4(0, 6, 0, 0), glm::uvec4(6, 6, 0, 0)};
  return b;
}
}  // namespace

TEST_CASE("grid: closedness is decided per surface, across objects") {
  SceneBuffers b = Cube();
  std::vector<std::size_t> open;
  CHECK(grid::ClosedObjects(b, &open) == std::vector<bool>{true, true});  // neither half alone is closed
  CHECK(open == std::vector<std::size_t>{0, 0});
  // Without its last triangle the cube has a hole of three edges, and both objects touch it.
  b.triangles.pop_back();
  b.objects[1].y = 5;
  CHECK(grid::ClosedObjects(b, &open) == std::vector<bool>{false, false});
  CHECK(open == std::vector<std::size_t>{3, 3});
  // A lone triangle beside a closed cube: only its object is open.
  SceneBuffers c = Cube();
  c.triangles.push_back(test::MakeTriangle({5, 5, 5}, {6, 5, 5}, {5, 6, 5}));
  c.objects.push_back(glm::uvec4(12, 1, 0, 0));
  CHECK(grid::ClosedObjects(c) == std::vector<bool>{true, true, false});
}

TEST_CASE("grid: --closed-models keeps the faces turned from the light and shadows the surfaces facing away untraced") {
  const SceneBuffers b = Cube();  // light above the cube, at y = 3
  // The top face (y = 1, normal +y) faces the light; the bottom face (normal -y) faces away.
  CHECK_FALSE(grid::FacesAway({0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {0.5f, 3, 0.5f}));
  CHECK(grid::FacesAway({0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0.5f, 3, 0.5f}));  // normal (0, -1, 0): the light is behind
  const GridArrays open = grid::Build(b, {8, 4, false}), closed = grid::Build(b, {8, 4, true});
  CHECK(closed.perspective_refs < open.perspective_refs);
  // The light at (0.5, 3, 0.5) sees the top face from the front; it lies behind the bottom's plane and
  // on the inner side of every side's plane (x = 0, 1 and z = 0, 1 with outward normals): ten of the
  // twelve triangles face away.
  std::size_t away = 0;
  for (const layout::Triangle& t : b.triangles) away += grid::FacesAway(Xyz(t.v0), Xyz(t.v1), Xyz(t.v2), {0.5f, 3, 0.5f});
  CHECK(away == 10);
  // Shadow rays from the light to the middle of the top face (lit) and of the bottom face (facing away).
  std::vector<layout::Ray> rays;
  for (const auto& [point, tri] : {std::pair{glm::vec3(0.4f, 1, 0.6f), 6u}, std::pair{glm::vec3(0.6f, 0, 0.3f), 0u}}) {
    const glm::vec3 v = point - glm::vec3(0.5f, 3, 0.5f);
    layout::Ray r = test::MakeSegment({0.5f, 3, 0.5f}, v / Length(v), 1e-6f, Length(v) * kShadowTmaxFactor);
    r.info = glm::uvec4(0, tri, layout::kRayShadow, 0);
    rays.push_back(r);
  }
  for (const bool c : {false, true}) {
    const GridArrays& g = c ? closed : open;
    const GridWalks w = PassGridTrace({.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes, .light_grids = g.light_grids,
                                       .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims, .triangles = b.triangles,
                                       .rays = rays, .shadow = 1, .closed = c ? 1u : 0u});
    INFO("closed " << c);
    CHECK(w.occluded == std::vector<std::uint32_t>{0u, 1u});  // the same answers
    if (c) CHECK(w.tests[1] == 0u);                          // the bottom is in shadow untraced
    if (c) CHECK(w.tests[0] == 0u);                          // the top's cell holds only faces farther away
  }
}

TEST_CASE("grid: eye rays through the eye's grid give brute force's closest hits") {
  const SceneBuffers b = SoupScene(test::TlSoup(500, 21), {{0, 2, 0}});
  const glm::vec3 eye(0.2f, -0.1f, -2.5f);
  CHECK(grid::EyeCells(512, std::tan(0.5 * 55.0 * 3.14159265358979 / 180.0)) == 10u);  // 983 pixels a face, 100 a cell
  const GridArrays g = grid::Build(b, {200, 54}, &eye, 6);
  REQUIRE(g.eye == 1u);
  CHECK(g.light_grids[1].y == 6u);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<layout::Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    // Eye rays all around the eye, most towards the soup.
    const glm::vec3 d = i % 4 == 0 ? glm::vec3(u(rng), u(rng), u(rng)) : glm::vec3(u(rng), u(rng), 2.5f + u(rng)) * 0.7f;
    layout::Ray r = test::MakeSegment(eye, d, 0.0f, INFINITY);
    r.info = glm::uvec4(static_cast<std::uint32_t>(i), layout::kNoPrim, layout::kRayPrimary, 0);
    rays.push_back(r);
  }
  const GridWalks w = PassGridTrace({.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes,
                                     .light_grids = g.light_grids, .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims,
                                     .triangles = b.triangles, .rays = rays, .shadow = 0, .eye = g.eye});
  std::size_t hits = 0, tests = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    INFO("ray " << i);
    CHECK(w.hits[i] == test::BruteClosest(b.triangles, rays[i]));
    CHECK(w.steps[i] == 1u);
    hits += w.hits[i] != kMissPacked;
    tests += w.tests[i];
  }
  CHECK(hits > 1000);
  // The rectangles of the projections spare most of a cell's triangles.
  CHECK(tests < rays.size() * 40);
}

namespace {
// A soup with a sphere light and a rect light among its triangles.
SceneBuffers AreaSoup(std::uint32_t seed) {
  SceneBuffers b = SoupScene(test::TlSoup(400, seed), {});
  layout::Light sphere{};
  sphere.position = glm::vec4(0.05f, 1.1f, 0.0f, 0.08f);  // w: the radius
  sphere.attenuation = glm::vec4(1, 0, 0, 0.125f);
  sphere.sampling = glm::uvec4(layout::kLightSphere, 8, 0, 4);
  layout::Light rect{};
  rect.position = glm::vec4(-0.4f, 0.3f, 0.2f, 1.0f);
  rect.axis_u = glm::vec4(0.06f, 0.0f, 0.0f, 4.0f);
  rect.axis_v = glm::vec4(0.0f, 0.01f, 0.05f, 2.0f);
  rect.attenuation = glm::vec4(1, 0, 0, 0.125f);
  rect.sampling = glm::uvec4(layout::kLightRect, 8, 8, 4);
  b.lights = {sphere, rect};
  return b;
}

// `count` shadow rays of the soup's two area lights, alternately, each from a point of its light's box
// (a sample) to a point of the soup; with `own_surfaces` every seventh leaves a triangle of the soup.
std::vector<layout::Ray> AreaShadowRays(const SceneBuffers& b, int count, std::uint32_t seed, bool own_surfaces) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.2f, 1.2f), s(-1.0f, 1.0f);
  std::vector<layout::Ray> rays;
  for (int i = 0; i < count; ++i) {
    const std::uint32_t l = static_cast<std::uint32_t>(i % 2);
    glm::vec3 lo, hi;
    LightCorners(b.lights[l], lo, hi);
    const glm::vec3 from = (lo + hi) * 0.5f + (hi - lo) * 0.5f * glm::vec3(s(rng), s(rng), s(rng));
    const glm::vec3 v = glm::vec3(u(rng), u(rng), u(rng)) - from;
    const float dist = Length(v);
    layout::Ray r = test::MakeSegment(from, v / dist, 1e-6f, dist * kShadowTmaxFactor);
    const bool own = own_surfaces && i % 7 == 0;
    r.info = glm::uvec4(0, own ? static_cast<std::uint32_t>(i % 400) : layout::kNoPrim, layout::kRayShadow, l);
    rays.push_back(r);
  }
  return rays;
}

GridWalks Trace(const GridArrays& g, const SceneBuffers& b, const std::vector<layout::Ray>& rays, std::uint32_t shadow) {
  return PassGridTrace({.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes, .light_grids = g.light_grids,
                        .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims, .slices = g.slices, .triangles = b.triangles,
                        .rays = rays, .shadow = shadow, .secondary = g.secondary});
}
}  // namespace

TEST_CASE("grid: every point of every triangle beyond an area light's core lies in a 3D cell that lists it") {
  const SceneBuffers b = AreaSoup(4);
  grid::Options o;
  o.area_cells = 12;
  o.area_depth = 5;
  o.area_near = 2;
  const GridArrays g = grid::Build(b, o);
  REQUIRE(g.light_grids.size() == 2);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t checked = 0;
  for (std::uint32_t l = 0; l < 2; ++l) {
    const glm::uvec4 e = g.light_grids[l];
    REQUIRE(e.z == 5u);
    const glm::dvec3 c(Xyz(g.origins[l]));
    const double near = static_cast<double>(g.origins[l].w * layout::kGridNearShrink);
    for (std::uint32_t t = 0; t < b.triangles.size(); ++t)
      for (int k = 0; k < 10; ++k) {
        double s = u(rng), r = u(rng);
        if (s + r > 1) s = 1 - s, r = 1 - r;
        const glm::dvec3 q = PointOn(b.triangles[t], s, r) - c;
        for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
          const int major = static_cast<int>(f / 2), a = (major + 1) % 3, bb = (major + 2) % 3;
          const double m = (f % 2 == 0 ? 1.0 : -1.0) * q[major];
          if (!(m >= near) || std::abs(q[a]) > m || std::abs(q[bb]) > m) continue;
          // The cell in exact arithmetic: columns of (u + 1) n / 2, the slice of 1 / m among the face's bounds.
          const std::uint32_t i = std::min(static_cast<std::uint32_t>((q[a] / m + 1.0) * 6.0), 11u);
          const std::uint32_t j = std::min(static_cast<std::uint32_t>((q[bb] / m + 1.0) * 6.0), 11u);
          std::uint32_t slice = 0;
          for (std::uint32_t x = 1; x < 5; ++x) slice += 1.0 / m <= static_cast<double>(g.slices[e.w + f * 6 + x]) ? 1u : 0u;
          const std::uint32_t cell = e.x + f * 12 * 12 * 5 + (slice * 12 + j) * 12 + i;
          INFO("light " << l << " triangle " << t << " face " << f << " cell " << cell);
          CHECK(Lists(g, cell, t));
          ++checked;
        }
      }
  }
  CHECK(checked > 2000);
}

TEST_CASE("grid: area lights' shadow rays through their 3D grids give brute force's occlusion") {
  for (std::uint32_t seed : {1u, 2u}) {
    const SceneBuffers b = AreaSoup(seed);
    grid::Options fine, coarse;
    coarse.area_cells = 3;
    coarse.area_depth = 2;
    coarse.area_near = 1;
    fine.area_near = 2;
    grid::Options mid = fine;
    mid.area_cells = 16;
    mid.area_depth = 8;
    for (const grid::Options& o : {fine, coarse, mid}) {
      const GridArrays g = grid::Build(b, o);
      const std::vector<layout::Ray> rays = AreaShadowRays(b, 2000, seed * 13, true);
      const GridWalks w = Trace(g, b, rays, 1);
      std::size_t occluded = 0, walked = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        INFO("seed " << seed << " cells " << o.area_cells << "x" << o.area_depth << " ray " << i);
        CHECK(grid::VolumeGridOf(rays[i], true, g.light_grids, g.secondary) == rays[i].info.w);
        CHECK(w.occluded[i] == (test::BruteClosest(b.triangles, rays[i]) != kMissPacked ? 1u : 0u));
        occluded += w.occluded[i];
        walked += w.steps[i] > 3;
      }
      CHECK(occluded > 400);
      CHECK(occluded < 1600);
      CHECK(walked > 200);  // the walks cross cells
    }
  }
}

TEST_CASE("grid: an area light's shadow ray counts its core cube's cells apart, and only those") {
  const SceneBuffers b = AreaSoup(3);
  const std::vector<layout::Ray> rays = AreaShadowRays(b, 2000, 29, true);
  grid::Options faces;
  faces.area_near = 2;
  grid::Options all_core = faces;
  all_core.area_near = 1u << 20;  // a core cube wider than the scene: every step is the regular grid's
  grid::Options regular = faces;
  regular.area_perspective = false;
  const GridArrays gf = grid::Build(b, faces), gc = grid::Build(b, all_core), gr = grid::Build(b, regular);
  const GridWalks wf = Trace(gf, b, rays, 1), wc = Trace(gc, b, rays, 1), wr = Trace(gr, b, rays, 1);
  REQUIRE(wf.core_steps.size() == rays.size());
  std::size_t split = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    INFO("ray " << i);
    CHECK(wf.core_steps[i] <= wf.steps[i]);
    // The ray starts on the light, inside its core cube: a walk that steps at all starts there.
    if (wf.steps[i]) CHECK(wf.core_steps[i] >= 1u);
    split += wf.core_steps[i] > 0 && wf.core_steps[i] < wf.steps[i];
    // All in the core: the same cells as the regular grid's walk of the same ray.
    CHECK(wc.core_steps[i] == wc.steps[i]);
    CHECK(wc.steps[i] == wr.steps[i]);
    CHECK(wr.core_steps[i] == 0u);
  }
  CHECK(split > 200);  // walks that leave the core and cross faces' cells
}

// The relaxed model of a walk through a 3D grid (verify/src/spec_grid_walk.cpp) on the area
// lights' shadow rays: a device that stops a cell earlier or tests one triangle fewer after its hit
// is within the spec; one that reports an occluded ray lit is beyond it wherever a triangle surely
// hit lies in a cell every walk crosses.
TEST_CASE("relaxed model: an area light's shadow ray may stop its 3D walk anywhere after a hit, not miss a sure one") {
  const SceneBuffers b = AreaSoup(1);
  grid::Options o;
  o.area_near = 2;
  const GridArrays g = grid::Build(b, o);
  const std::vector<layout::Ray> rays = AreaShadowRays(b, 600, 26, false);
  const call::GridTrace c{.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes,
                          .light_grids = g.light_grids, .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims,
                          .slices = g.slices, .triangles = b.triangles, .rays = rays, .shadow = 1, .secondary = g.secondary};
  const GridWalks e = PassGridTrace(c);
  const auto verdict = [&](const GridWalks& device) {
    return verify::ClassifyWithinSpec("grid.trace", verify::EncodeCall(c), verify::EncodeOutputs(c, &e), verify::EncodeOutputs(c, &device));
  };
  GridWalks earlier = e, lit = e;
  std::size_t stopped = 0, flipped = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (e.occluded[i] == 0 || e.steps[i] < 2 || e.tests[i] < 2) continue;
    --earlier.steps[i], --earlier.tests[i];
    ++stopped;
    lit.occluded[i] = 0;
    ++flipped;
  }
  REQUIRE(stopped > 50);
  const verify::SpecVerdict within = verdict(earlier);
  CHECK(within.modelled);
  CHECK(within.within == stopped);
  CHECK(within.beyond == 0);
  const verify::SpecVerdict beyond = verdict(lit);
  CHECK(beyond.within + beyond.beyond == flipped);
  CHECK(beyond.beyond * 10 >= flipped * 9);  // all but rays whose every hit may flip or lies in a cell a walk may skip
}

TEST_CASE("grid: reflection rays through the 3D grid about the eye give brute force's closest hits") {
  const SceneBuffers b = SoupScene(test::TlSoup(500, 31), {{0, 2, 0}});
  const glm::vec3 eye(0.3f, -0.2f, -2.5f);
  for (const std::uint32_t cells : {200u, 5u}) {
    grid::Options o;
    o.secondary_perspective = true;
    o.area_cells = cells;
    o.area_depth = cells == 5u ? 3u : 4u;
    const GridArrays g = grid::Build(b, o, nullptr, 0, &eye);
    REQUIRE(g.secondary == 1u);
    std::mt19937 rng(cells);
    std::uniform_real_distribution<float> u(-1.3f, 1.3f);
    std::vector<layout::Ray> rays;
    for (int i = 0; i < 2500; ++i) {
      const glm::vec3 org(u(rng), u(rng), u(rng)), to(u(rng), u(rng), u(rng));
      layout::Ray r = test::MakeSegment(org, to - org, 0.0f, i % 3 == 0 ? 1.0f : INFINITY, i % 5 == 0 ? static_cast<std::uint32_t>(i % 500) : layout::kNoPrim);
      r.info.z = i % 2 ? layout::kRayReflection : layout::kRayRefraction;
      rays.push_back(r);
    }
    const GridWalks w = Trace(g, b, rays, 0);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      INFO("cells " << cells << " ray " << i);
      CHECK(grid::VolumeGridOf(rays[i], false, g.light_grids, g.secondary) == 1u);
      CHECK(w.hits[i] == test::BruteClosest(b.triangles, rays[i]));
      hits += w.hits[i] != kMissPacked;
    }
    CHECK(hits > 800);
  }
}

TEST_CASE("grid: the binning's margins keep shadow rays aimed at vertices and edges; without them some are lost") {
  const std::vector<glm::vec3> lights{{0.05f, 1.5f, 0.0f}, {-0.4f, 0.3f, 0.2f}};
  std::size_t lost_without = 0;
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    const SceneBuffers b = SoupScene(test::TlSoup(400, seed), lights);
    std::vector<layout::Ray> rays;
    // To every vertex and edge midpoint: points on the rim of a triangle's projection, where a ray's
    // rounded (u, v) falls on a cell's or a rectangle's edge.
    for (std::uint32_t t = 0; t < b.triangles.size(); ++t)
      for (int k = 0; k < 6; ++k) {
        const layout::Triangle& tr = b.triangles[t];
        const glm::vec3 v[3] = {Xyz(tr.v0), Xyz(tr.v1), Xyz(tr.v2)};
        const glm::vec3 to = k < 3 ? v[k] : (v[k - 3] + v[(k - 2) % 3]) * 0.5f;
        const std::uint32_t l = static_cast<std::uint32_t>((t + k) % 2);
        const glm::vec3 d = to - lights[l];
        const float dist = Length(d);
        layout::Ray r = test::MakeSegment(lights[l], d / dist, 1e-6f, dist * 1.001f);
        r.info = glm::uvec4(0, layout::kNoPrim, layout::kRayShadow, l);
        rays.push_back(r);
      }
    for (const bool margins : {true, false}) {
      grid::Options o{64, 8};
      o.margins = margins;
      const GridArrays g = grid::Build(b, o);
      const GridWalks w = PassGridTrace({.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes,
                                         .light_grids = g.light_grids, .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims,
                                         .triangles = b.triangles, .rays = rays, .shadow = 1});
      std::size_t lost = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) lost += w.occluded[i] != (test::BruteClosest(b.triangles, rays[i]) != kMissPacked ? 1u : 0u);
      INFO("seed " << seed << " margins " << margins);
      if (margins) CHECK(lost == 0u);
      else lost_without += lost;
    }
  }
  MESSAGE("rays lost without the margins: " << lost_without);
  CHECK(lost_without > 0u);
}

TEST_CASE("grid: the build's arrays are the same for every thread count and schedule, each cell's list ascending") {
  rayspace::test::TestSettings settings;
  // Over 2,048 triangles: the build bins them in several runs of 1,024.
  SceneBuffers with_point = SoupScene(test::TlSoup(2600, 31), {});
  with_point.lights = AreaSoup(31).lights;
  with_point.lights.push_back(SoupScene({}, {{0.3f, 0.9f, -0.2f}}).lights[0]);
  with_point.lights.back().sampling.z = 16;  // its shadow slots after the area lights'
  const glm::vec3 eye(0.1f, 0.2f, -2.0f);
  grid::Options o;
  o.cells = 40;
  o.area_cells = 24;
  o.secondary_perspective = true;
  const auto build = [&](int threads, std::size_t chunk) {
    settings->threads = threads;
    settings->chunk = chunk;
    GridArrays g = grid::Build(with_point, o, &eye, 5, &eye);
    return g;
  };
  const GridArrays a = build(1, 0);
  REQUIRE(a.perspective_refs > 0);
  REQUIRE(a.volume_refs > 0);
  std::size_t descending = 0;
  for (std::size_t c = 0; c + 1 < a.first.size(); ++c)
    for (std::uint32_t i = a.first[c] + 1; i < a.first[c + 1]; ++i) descending += a.triangles[i] <= a.triangles[i - 1];
  CHECK(descending == 0);
  for (const auto& [threads, chunk] : std::vector<std::pair<int, std::size_t>>{{2, 0}, {2, 1}, {2, 7}}) {
    CAPTURE(threads);
    CAPTURE(chunk);
    const GridArrays x = build(threads, chunk);
    CHECK(x.first == a.first);
    CHECK(x.triangles == a.triangles);
    CHECK(x.min_dist == a.min_dist);
    CHECK(x.boxes == a.boxes);
    CHECK(x.slices == a.slices);
  }
}
