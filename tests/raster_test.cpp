// Known-answer tests of the emulated lavapipe raster (coverage rule, clipping, reconstruction).
#include <doctest/doctest.h>

#include <cfloat>
#include <random>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/raster_detail.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

// Coverage count per pixel of a set of window-space triangles on a W x H framebuffer.
std::vector<int> Coverage(const std::vector<std::array<glm::vec2, 3>>& tris, int w, int h) {
  std::vector<int> count(static_cast<std::size_t>(w) * h, 0);
  for (const auto& t : tris) {
    raster::Setup s;
    if (!raster::SetupTriangle(t[0], t[1], t[2], w, h, s)) continue;
    for (int y = s.y0; y <= s.y1; ++y)
      for (int x = s.x0; x <= s.x1; ++x)
        if (raster::Covers(s, x, y)) ++count[static_cast<std::size_t>(y) * w + x];
  }
  return count;
}

}  // namespace

TEST_CASE("raster: top-left rule on edges through pixel centres") {
  // Rectangle with every edge through pixel centres: x in [2.5, 6.5], y in [1.5, 5.5]. The left and
  // top edges own their pixels, the right and bottom ones do not: columns 2..5, rows 1..4.
  const glm::vec2 a(2.5f, 1.5f), b(6.5f, 1.5f), c(6.5f, 5.5f), d(2.5f, 5.5f);
  for (int winding = 0; winding < 2; ++winding) {
    std::vector<std::array<glm::vec2, 3>> tris;
    if (winding == 0) tris = {{a, b, c}, {a, c, d}};
    else tris = {{a, c, b}, {a, d, c}};  // the other orientation must give the same pixels
    const auto cov = Coverage(tris, 10, 8);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 10; ++x) {
        const int expect = (x >= 2 && x <= 5 && y >= 1 && y <= 4) ? 1 : 0;
        INFO("pixel " << x << "," << y << " winding " << winding);
        CHECK(cov[y * 10 + x] == expect);
      }
  }
}

TEST_CASE("raster: two triangles sharing an edge cover each pixel exactly once") {
  // The shared diagonal passes through pixel centres (x = y): each of those belongs to one side.
  const glm::vec2 a(0.5f, 0.5f), b(16.5f, 0.5f), c(16.5f, 16.5f), d(0.5f, 16.5f);
  const auto cov = Coverage({{a, b, c}, {a, c, d}}, 20, 20);
  int covered = 0;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) {
      INFO("pixel " << x << "," << y);
      CHECK(cov[y * 20 + x] <= 1);
      covered += cov[y * 20 + x];
      if (x < 16 && y < 16) CHECK(cov[y * 20 + x] == 1);
    }
  CHECK(covered == 16 * 16);
}

TEST_CASE("raster: a random fan covers every pixel of its polygon exactly once") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
  for (int trial = 0; trial < 20; ++trial) {
    const glm::vec2 centre(32.0f + jitter(rng) * 10, 32.0f + jitter(rng) * 10);
    std::vector<glm::vec2> ring;
    const int n = 7 + trial % 9;
    for (int k = 0; k < n; ++k) {
      const float ang = 6.2831853f * (k + 0.5f * jitter(rng)) / n;
      const float r = 25.0f + 5.0f * jitter(rng);
      ring.push_back(centre + r * glm::vec2(std::cos(ang), std::sin(ang)));
    }
    std::vector<std::array<glm::vec2, 3>> tris;
    for (int k = 0; k < n; ++k) tris.push_back({centre, ring[k], ring[(k + 1) % n]});
    const auto cov = Coverage(tris, 64, 64);
    // Every pixel at most once; pixels well inside the polygon (radius < 19) exactly once.
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        INFO("trial " << trial << " pixel " << x << "," << y);
        CHECK(cov[y * 64 + x] <= 1);
        if (glm::length(glm::vec2(x + 0.5f, y + 0.5f) - centre) < 19.0f) CHECK(cov[y * 64 + x] == 1);
      }
  }
}

TEST_CASE("raster: zero-area triangles are culled") {
  raster::Setup s;
  CHECK_FALSE(raster::SetupTriangle({1.5f, 1.5f}, {5.5f, 5.5f}, {9.5f, 9.5f}, 16, 16, s));
  CHECK_FALSE(raster::SetupTriangle({1.5f, 1.5f}, {1.5f, 1.5f}, {9.5f, 2.5f}, 16, 16, s));
}

TEST_CASE("raster: snapping is 8 subpixel bits, round to nearest even") {
  // 1/512 of a pixel is half a subpixel step: the tie rounds to even, moving the edge by nothing.
  const auto base = Coverage({{glm::vec2(2.5f, 0.5f), glm::vec2(2.5f, 9.5f), glm::vec2(9.5f, 0.5f)}}, 12, 12);
  const auto tie = Coverage({{glm::vec2(2.5f + 1.0f / 512, 0.5f), glm::vec2(2.5f + 1.0f / 512, 9.5f), glm::vec2(9.5f, 0.5f)}}, 12, 12);
  CHECK(base == tie);
  // Just past the tie the left edge moves right by one subpixel and column 2 is lost.
  const auto moved = Coverage({{glm::vec2(2.5f + 1.0f / 400, 0.5f), glm::vec2(2.5f + 1.0f / 400, 9.5f), glm::vec2(9.5f, 0.5f)}}, 12, 12);
  CHECK(base[1 * 12 + 2] == 1);
  CHECK(moved[1 * 12 + 2] == 0);
}

TEST_CASE("raster: clipping keeps geometry that crosses the near plane") {
  // A ground plane reaching far behind the camera: every pixel whose centre ray points down must be
  // covered, and the reconstructed position must lie on the plane.
  Scene s;
  s.camera.eye = {0, 1, 0};
  s.camera.target = {0, 0.8f, -1};
  s.camera.up = {0, 1, 0};
  s.camera.fov_y_deg = 60;
  s.materials.push_back(test::Diffuse("ground", glm::vec3(0.5f)));
  test::AddQuad(s, "ground", {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, {-50, 0, -50});
  const SceneBuffers b = FlattenScene(s);
  const int w = 64, h = 48;
  const layout::FrameConstants fc = MakeFrameConstants(s, b, w, h);
  const GBuffer g = PassRaster({.frame = fc, .scene = &b});
  int checked = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 d = PixelDirection(fc, x, y);
      const float dy = d.y / glm::length(d);
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      // Where the ray meets y = 0 inside the quad (|x|,|z| < 50) the pixel must be covered.
      const float t = -1.0f / d.y;
      const glm::vec3 p = glm::vec3(0, 1, 0) + t * d;
      if (dy < -0.05f && std::fabs(p.x) < 49 && std::fabs(p.z) < 49) {
        INFO("pixel " << x << "," << y);
        CHECK(g.prim[i] != layout::kNoPrim);
        CHECK(std::fabs(g.position[i].y) < 1e-4f);
        ++checked;
      }
      if (dy > 0.01f) CHECK(g.prim[i] == layout::kNoPrim);
    }
  CHECK(checked > w * h / 4);
}

TEST_CASE("raster: the nearer triangle wins the depth test, whatever the draw order") {
  Scene s;
  s.camera.eye = {0, 0, 5};
  s.camera.target = {0, 0, 0};
  s.camera.fov_y_deg = 40;
  s.materials.push_back(test::Diffuse("a", glm::vec3(0.2f)));
  s.materials.push_back(test::Diffuse("b", glm::vec3(0.9f)));
  for (int order = 0; order < 2; ++order) {
    s.objects.clear();
    const float zs[2] = {order == 0 ? 0.0f : 1.0f, order == 0 ? 1.0f : 0.0f};
    for (int k = 0; k < 2; ++k)
      test::AddQuad(s, "q", {-1, -1, zs[k]}, {1, -1, zs[k]}, {1, 1, zs[k]}, {-1, 1, zs[k]}, zs[k] == 1.0f ? 1 : 0);
    const SceneBuffers b = FlattenScene(s);
    const layout::FrameConstants fc = MakeFrameConstants(s, b, 32, 32);
    const GBuffer g = PassRaster({.frame = fc, .scene = &b});
    const std::size_t centre = 16 * 32 + 16;
    REQUIRE(g.prim[centre] != layout::kNoPrim);
    CHECK(g.diffuse[centre].x == doctest::Approx(0.9f));  // the quad at z = 1 is nearer the eye
    CHECK(g.position[centre].z == doctest::Approx(1.0f).epsilon(1e-5));
  }
}

TEST_CASE("raster: the draw path runs with flush-to-zero and denormals-are-zero") {
  volatile float tiny = FLT_MIN / 4.0f;  // a denormal
  volatile float one = 1.0f;
  float inside, outside = tiny * one;
  {
    ScopedFtzDaz ftz;
    inside = tiny * one;
  }
  CHECK(outside != 0.0f);
  CHECK(inside == 0.0f);
}

TEST_CASE("raster: a wall far wider than the view covers every pixel, clipped on all four side planes") {
  // A 200 x 200 quad one unit in front of the camera reaches past every side of the view frustum, so
  // each triangle is clipped against the left, right, top and bottom planes; every pixel, the four
  // corners included, must be covered and lie on the wall. A wrong side plane cuts off a corner.
  Scene s;
  s.camera.eye = {0, 0, 1};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 1, 0};
  s.camera.fov_y_deg = 60;
  s.materials.push_back(test::Diffuse("wall", glm::vec3(0.5f)));
  test::AddQuad(s, "wall", {-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0});
  const SceneBuffers b = FlattenScene(s);
  const int w = 32, h = 24;
  const GBuffer g = PassRaster({.frame = MakeFrameConstants(s, b, w, h), .scene = &b});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      INFO("pixel " << x << "," << y);
      CHECK(g.prim[i] != layout::kNoPrim);
      CHECK(std::fabs(g.position[i].z) < 1e-5f);
    }
}
