// Traversal lists (rayspace/emu/tl/tl.h): a hand-worked scene, the lists' invariants, the walk
// against brute force for every list count and order (random soups, the bunny, rays ending or
// starting exactly at a hit), determinism and a degenerate set.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <string>

#include <doctest/doctest.h>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/emu/tl/tracer.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/scene.h"
#include "test_util.h"
#include "tl_util.h"

namespace tl = rayspace::emu::tl;
using rayspace::test::BruteClosest;
using rayspace::test::MakeSegment;
using rayspace::test::MakeTriangle;
using rayspace::emu::HitPrim;
using rayspace::emu::HitT;
using rayspace::emu::kMissPacked;
using rayspace::emu::PackHit;
using rayspace::layout::kNoPrim;
using rayspace::layout::Ray;
using rayspace::layout::Triangle;

namespace {

std::vector<std::uint32_t> Prims(const tl::Lists& l, std::uint32_t k) {
  std::vector<std::uint32_t> p;
  for (std::uint32_t i = l.first[k]; i < l.first[k + 1]; ++i)
    if (tl::IsTriangle(l.escapes[i])) p.push_back(l.words[i].w);
  return p;
}
std::vector<tl::Escape> Escapes(const tl::Lists& l, std::uint32_t k) {
  return {l.escapes.begin() + l.first[k], l.escapes.begin() + l.first[k + 1]};
}

// Three small triangles at three corners of a 10 x 10 square in z = 0:
//   T0 (0,0) (1,0) (0,1), T1 (10,0) (9,0) (10,1), T2 (0,10) (1,10) (0,9).
// With leaf_triangles = 1, the root R is centred at the box centre (5,5,0), radius sqrt(50) ~ 7.07
// (rounded up); each triangle's radius about its centroid is sqrt(5)/3 ~ 0.75 < 0.25 x 7.07, so none
// is big, and the centroids (1/3,1/3), (29/3,1/3), (1/3,29/3) fall in octants 0, 1, 2: children A
// (T0), B (T1), C (T2), each a leaf of radius sqrt(0.5) ~ 0.71 about (0.5,0.5), (9.5,0.5), (0.5,9.5).
// Projections on +x: A [-0.21, 1.21], B [8.79, 10.21], C = A's: earliest first gives A, C, B (A
// before C: the tie keeps octant order). On -x: B [-10.21, -8.79] first, then A, C. On +y: A, B, C;
// on -y: C, A, B; on +-z all equal: A, B, C. Each list is R, X, Tx, Y, Ty, Z, Tz with escapes
//   R: -1 (its subtree is the list), X: 2, Tx: 1, Y: 2, Ty: 1, Z: -1 (no super-sibling), Tz: 0 (last).
std::vector<Triangle> HandScene() {
  return {MakeTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), MakeTriangle({10, 0, 0}, {9, 0, 0}, {10, 1, 0}), MakeTriangle({0, 10, 0}, {1, 10, 0}, {0, 9, 0})};
}
tl::Options HandOptions(std::uint32_t lists) {
  tl::Options o;
  o.lists = lists;
  o.tree.leaf_triangles = 1;
  return o;
}

}  // namespace

TEST_CASE("tl: the hand-worked scene's lists and escapes") {
  const tl::Lists l = tl::Build(HandScene(), HandOptions(6));
  REQUIRE(l.first == std::vector<std::uint32_t>{0, 7, 14, 21, 28, 35, 42});
  const std::vector<tl::Escape> esc{-1, 2, 1, 2, 1, -1, 0};
  const std::vector<std::vector<std::uint32_t>> prims{{0, 2, 1}, {1, 0, 2}, {0, 1, 2}, {2, 0, 1}, {0, 1, 2}, {0, 1, 2}};
  for (std::uint32_t k = 0; k < 6; ++k) {
    CAPTURE(k);
    CHECK(Escapes(l, k) == esc);
    CHECK(Prims(l, k) == prims[k]);
  }
  // The shared vertices: nine distinct, in first-use order; T1's word names 3, 4, 5 and id 1.
  CHECK(l.vertices.size() == 9);
  CHECK(l.words[6] == tl::Word(3, 4, 5, 1));  // list 0's last element: T1
  const glm::vec4 root(std::bit_cast<float>(l.words[0].x), std::bit_cast<float>(l.words[0].y), std::bit_cast<float>(l.words[0].z),
                       std::bit_cast<float>(l.words[0].w));
  CHECK(glm::vec3(root) == glm::vec3(5, 5, 0));
  CHECK(static_cast<double>(root.w) >= std::sqrt(50.0));
  CHECK(root.w < 7.0711f);
  // 42 elements of 20 bytes, 9 vertices of 16, 7 offsets of 4.
  CHECK(l.Bytes() == 42 * 20 + 9 * 16 + 7 * 4);
}

TEST_CASE("tl: the hand-worked scene's walks") {
  const tl::Lists l = tl::Build(HandScene(), HandOptions(6));
  // Down onto T1 at (9.7, 0.2): list -z (R, A, T0, B, T1, C, T2). R hit, A missed (escape 2 to B), B hit, T1 hit at
  // t = 5, C missed and its escape -1 ends the walk: 4 spheres, 1 triangle.
  tl::Stats s;
  const Ray down = MakeSegment({9.7f, 0.2f, 5.0f}, {0, 0, -1});
  CHECK(tl::ListFor(6, {0, 0, -1}) == 5);
  CHECK(tl::Closest(l, down, &s) == PackHit(5.0f, 1));
  CHECK(s.spheres == 4);
  CHECK(s.triangles == 1);
  CHECK(s.entries == 7);  // T0 skipped by A's escape, T2 by C's: the whole list passed
  // Any hit stops at T1: R, A, B; the entries up to T1 passed (R, A, T0, B, T1), C and T2 not.
  s = {};
  CHECK(tl::Any(l, down, &s));
  CHECK(s.spheres == 3);
  CHECK(s.triangles == 1);
  CHECK(s.entries == 5);
  // Through the middle: R hit, A, B, C missed by escapes, no triangle tested.
  s = {};
  CHECK(tl::Closest(l, MakeSegment({5, 5, 5}, {0, 0, -1}), &s) == kMissPacked);
  CHECK(s.spheres == 4);
  CHECK(s.triangles == 0);
  CHECK(s.entries == 7);
  // Outside the root: its escape -1 ends the walk at once, passing the whole list.
  s = {};
  CHECK_FALSE(tl::Any(l, MakeSegment({20, 20, 5}, {0, 0, -1}), &s));
  CHECK(s.spheres == 1);
  CHECK(s.entries == 7);
  // The interval is open: a hit at exactly tmax or tmin is not one.
  CHECK(tl::Closest(l, MakeSegment({9.7f, 0.2f, 5.0f}, {0, 0, -1}, 0.0f, 5.0f)) == kMissPacked);
  CHECK(tl::Closest(l, MakeSegment({9.7f, 0.2f, 5.0f}, {0, 0, -1}, 5.0f, INFINITY)) == kMissPacked);
  CHECK(tl::Closest(l, MakeSegment({9.7f, 0.2f, 5.0f}, {0, 0, -1}, 0.0f, 5.0f + 1e-5f)) == PackHit(5.0f, 1));
  CHECK_FALSE(tl::Any(l, MakeSegment({9.7f, 0.2f, 5.0f}, {0, 0, -1}, 0.0f, INFINITY, 1)));
}

TEST_CASE("tl: the two orders differ where the projections do") {
  // U0 spans x in [0, 4], U1 x in [1, 2]: earliest first (by lo) U0, U1; latest last (by hi) U1, U0.
  const std::vector<Triangle> tris{MakeTriangle({0, 0, 0}, {4, 0, 0}, {0, 1, 0}), MakeTriangle({1, 0, 1}, {2, 0, 1}, {1, 1, 1})};
  tl::Options o;
  o.lists = 1;
  tl::Lists l = tl::Build(tris, o);
  CHECK(Prims(l, 0) == std::vector<std::uint32_t>{0, 1});
  CHECK(Escapes(l, 0) == std::vector<tl::Escape>{-1, 1, 0});
  o.order = tl::Order::kLatestLast;
  l = tl::Build(tris, o);
  CHECK(Prims(l, 0) == std::vector<std::uint32_t>{1, 0});
}

TEST_CASE("tl: a ray's list") {
  CHECK(tl::ListFor(1, {-1, -2, -3}) == 0);
  CHECK(tl::ListFor(2, {0.5f, -9, 0}) == 0);
  CHECK(tl::ListFor(2, {-0.5f, 9, 0}) == 1);
  CHECK(tl::ListFor(6, {0.1f, -0.2f, 0.15f}) == 3);
  CHECK(tl::ListFor(6, {-1, 1, 1}) == 1);  // a tie goes to the lower axis
  CHECK(tl::ListFor(6, {0, 0, 2}) == 4);
  CHECK(tl::ListFor(8, {1, -1, 1}) == 2);
  CHECK(tl::ListFor(8, {-1, -1, -1}) == 7);
  CHECK(tl::ListFor(8, {0, 0, 0}) == 0);
}

namespace {

// A soup of small and large triangles in [-1, 1]^3 (the large ones are kept high as big triangles).
std::vector<Triangle> Soup(std::uint32_t n, std::uint32_t seed) { return rayspace::test::TlSoup(n, seed); }

// Rays at random triangles' interiors (so that many hit), random rays, axis-aligned ones (zero
// components, ties between axes) and, for each hit, the rays that end or start exactly at it or
// ignore its triangle.
std::vector<Ray> Rays(const std::vector<Triangle>& tris, std::uint32_t n, std::uint32_t seed, float extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  std::vector<Ray> rays;
  const glm::vec3 axes[] = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {-1, 0, 1}};
  for (std::uint32_t i = 0; i < n; ++i) {
    const glm::vec3 o = extent * 2.0f * glm::vec3(u(rng), u(rng), u(rng));
    const Triangle& t = tris[rng() % tris.size()];
    const float a = w(rng), b = w(rng) * (1.0f - a);
    const glm::vec3 p = glm::vec3(t.v0) + a * (glm::vec3(t.v1) - glm::vec3(t.v0)) + b * (glm::vec3(t.v2) - glm::vec3(t.v0));
    glm::vec3 d = i % 4 == 3 ? glm::vec3(u(rng), u(rng), u(rng)) : (p - o) * (0.5f + w(rng));
    if (i % 16 == 5) d = axes[(i / 16) % 5];
    rays.push_back(MakeSegment(o, d, i % 8 == 1 ? 0.3f : 0.0f, i % 8 == 2 ? 0.7f : INFINITY));
    const std::uint64_t h = BruteClosest(tris, rays.back());
    if (h == kMissPacked) continue;
    rays.push_back(MakeSegment(o, d, 0.0f, HitT(h)));
    rays.push_back(MakeSegment(o, d, HitT(h), INFINITY));
    rays.push_back(MakeSegment(o, d, 0.0f, INFINITY, HitPrim(h)));
  }
  return rays;
}

// Every list count and order against brute force; returns the elements visited per ray (K = 6).
double CheckAgainstBrute(const std::vector<Triangle>& tris, const std::vector<Ray>& rays) {
  std::vector<std::uint64_t> brute;
  for (const Ray& r : rays) brute.push_back(BruteClosest(tris, r));
  // A quarter of the rays at least must hit, or agreeing on misses would prove little.
  CHECK(std::count(brute.begin(), brute.end(), kMissPacked) < static_cast<std::ptrdiff_t>(rays.size() * 3 / 4));
  double visited = 0.0;
  for (const std::uint32_t k : {1u, 2u, 6u, 8u})
    for (const tl::Order order : {tl::Order::kEarliestFirst, tl::Order::kLatestLast}) {
      tl::Options o;
      o.lists = k;
      o.order = order;
      const tl::Lists l = tl::Build(tris, o);
      std::size_t closest_bad = 0, any_bad = 0;
      tl::Stats s;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        closest_bad += tl::Closest(l, rays[i], &s) != brute[i];
        any_bad += tl::Any(l, rays[i]) != (brute[i] != kMissPacked);
      }
      CAPTURE(k);
      CAPTURE(static_cast<int>(order));
      CHECK(closest_bad == 0);
      CHECK(any_bad == 0);
      if (k == 6 && order == tl::Order::kEarliestFirst) visited = static_cast<double>(s.spheres + s.triangles) / rays.size();
    }
  return visited;
}

// Each list holds every triangle once; a triangle's escape is 1 (0 at the end), a sphere's reaches
// past its subtree, which is exactly what its sphere must hold (checked in double).
void CheckInvariants(const std::vector<Triangle>& tris, const tl::Lists& l) {
  for (std::uint32_t k = 0; k < l.count; ++k) {
    const std::int64_t b = l.first[k], e = l.first[k + 1];
    std::vector<std::uint32_t> p = Prims(l, k);
    std::sort(p.begin(), p.end());
    for (std::uint32_t i = 0; i < p.size(); ++i) REQUIRE(p[i] == i);
    REQUIRE(p.size() == tris.size());
    CHECK(l.escapes[static_cast<std::size_t>(e - 1)] == tl::kEscapeLast);
    for (std::int64_t i = b; i < e; ++i) {
      const tl::Escape x = l.escapes[static_cast<std::size_t>(i)];
      if (tl::IsTriangle(x)) continue;
      const std::int64_t end = x == tl::kEscapeNone ? e : i + x;
      REQUIRE((x >= 2 || x == tl::kEscapeNone));
      REQUIRE(end <= e);
      const tl::Word& w = l.words[static_cast<std::size_t>(i)];
      const glm::dvec3 c(std::bit_cast<float>(w.x), std::bit_cast<float>(w.y), std::bit_cast<float>(w.z));
      for (std::int64_t j = i + 1; j < end; ++j) {
        const tl::Word& t = l.words[static_cast<std::size_t>(j)];
        if (!tl::IsTriangle(l.escapes[static_cast<std::size_t>(j)])) continue;
        for (const std::uint32_t v : {t.x, t.y, t.z})
          REQUIRE(glm::length(glm::dvec3(glm::vec3(l.vertices[v])) - c) <= static_cast<double>(std::bit_cast<float>(w.w)));
      }
    }
  }
}

}  // namespace

TEST_CASE("tl: every list count and order gives brute force's hits on a random soup") {
  const std::vector<Triangle> tris = Soup(400, 7);
  for (const std::uint32_t k : {1u, 2u, 6u, 8u}) {
    tl::Options o;
    o.lists = k;
    CheckInvariants(tris, tl::Build(tris, o));
  }
  const std::vector<Ray> rays = Rays(tris, 600, 11, 1.0f);
  const double visited = CheckAgainstBrute(tris, rays);
  MESSAGE("soup: " << rays.size() << " rays, " << visited << " elements visited per ray (K = 6) of " << tris.size());
  CHECK(visited < 0.5 * static_cast<double>(tris.size()));  // the escapes do skip
}

TEST_CASE("tl: every list count and order gives brute force's hits on the bunny") {
  if (rayspace::test::SkipWithoutData("bunny/bun_zipper_res4.ply")) return;
  const rayspace::MeshData mesh = rayspace::LoadPly(rayspace::test::DataRoot() / "bunny/bun_zipper_res4.ply");
  std::vector<Triangle> tris;
  for (const rayspace::SubMesh& m : mesh.submeshes)
    for (std::size_t i = 0; i + 2 < m.positions.size(); i += 3) tris.push_back(MakeTriangle(m.positions[i], m.positions[i + 1], m.positions[i + 2]));
  REQUIRE(tris.size() > 500);
  tl::Options o;
  CheckInvariants(tris, tl::Build(tris, o));
  const std::vector<Ray> rays = Rays(tris, 500, 13, 0.12f);
  const double visited = CheckAgainstBrute(tris, rays);
  MESSAGE("bunny: " << tris.size() << " triangles, " << rays.size() << " rays, " << visited << " elements visited per ray (K = 6)");
  CHECK(visited < 0.25 * static_cast<double>(tris.size()));
}

TEST_CASE("tl: the build is deterministic") {
  const std::vector<Triangle> tris = Soup(300, 3);
  for (const std::uint32_t k : {1u, 2u, 6u, 8u}) {
    tl::Options o;
    o.lists = k;
    o.order = k == 2 ? tl::Order::kLatestLast : tl::Order::kEarliestFirst;
    const tl::Lists a = tl::Build(tris, o), b = tl::Build(tris, o);
    CHECK(a.first == b.first);
    REQUIRE(a.escapes.size() == b.escapes.size());
    REQUIRE(a.words.size() == b.words.size());
    REQUIRE(a.vertices.size() == b.vertices.size());
    CHECK(std::memcmp(a.escapes.data(), b.escapes.data(), a.escapes.size() * sizeof(tl::Escape)) == 0);
    CHECK(std::memcmp(a.words.data(), b.words.data(), a.words.size() * sizeof(tl::Word)) == 0);
    CHECK(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(tl::Vertex)) == 0);
  }
}

TEST_CASE("tl: coincident centroids end the build, and an empty scene is an empty walk") {
  std::vector<Triangle> tris(40, MakeTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  const std::vector<Triangle> more = Soup(40, 5);
  tris.insert(tris.end(), more.begin(), more.end());
  const tl::Lists l = tl::Build(tris, {});
  CheckInvariants(tris, l);
  CheckAgainstBrute(tris, Rays(tris, 100, 17, 1.0f));
  const tl::Lists empty = tl::Build(std::vector<Triangle>{}, {});
  CHECK(empty.escapes.empty());
  CHECK(tl::Closest(empty, MakeSegment({0, 0, 1}, {0, 0, -1})) == kMissPacked);
  CHECK_FALSE(tl::Any(empty, MakeSegment({0, 0, 1}, {0, 0, -1})));
}

TEST_CASE("tl: the sphere test keeps every sphere the ray's part truly meets") {
  // Rays whose point at t = 1 (exactly, in double) lies in the sphere, near its surface, at scales
  // from 2^-20 to 2^20 and with the sphere far from the origin: the test, with t ending or starting
  // at 1, must keep them all.
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int tested = 0;
  for (int i = 0; i < 20000; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(rng() % 41) - 20);
    const glm::dvec3 c = scale * glm::dvec3(u(rng), u(rng), u(rng)) * (i % 2 ? 1000.0 : 1.0);
    const glm::vec4 s(glm::vec3(c), static_cast<float>(scale * (0.01 + std::abs(u(rng)))));
    const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::dvec3 p = glm::dvec3(glm::vec3(s)) + dir * static_cast<double>(s.w) * (1.0 - 1e-12);
    const glm::vec3 o = glm::vec3(p + scale * 3.0 * glm::dvec3(u(rng), u(rng), u(rng)));
    const glm::vec3 d = glm::vec3(p) - o;
    const glm::dvec3 q = glm::dvec3(o) + glm::dvec3(d);
    if (glm::length(q - glm::dvec3(glm::vec3(s))) > static_cast<double>(s.w)) continue;
    ++tested;
    CAPTURE(i);
    REQUIRE(tl::SphereMayHit(o, d, 0.0f, 1.0f, s));
    REQUIRE(tl::SphereMayHit(o, d, 1.0f, INFINITY, s));
  }
  CHECK(tested > 10000);
  // And it does prune: a sphere behind the part, beside the line, or beyond the limit.
  const glm::vec4 s(0, 0, 10, 1);
  CHECK_FALSE(tl::SphereMayHit({0, 0, 0}, {0, 0, 1}, 0.0f, 8.9f, s));
  CHECK_FALSE(tl::SphereMayHit({0, 0, 0}, {0, 0, 1}, 11.1f, INFINITY, s));
  CHECK_FALSE(tl::SphereMayHit({1.01f, 0, 0}, {0, 0, 1}, 0.0f, INFINITY, s));
  CHECK(tl::SphereMayHit({0, 0, 0}, {0, 0, 2}, 0.0f, 4.5f, s));
}

namespace {

// tl.lists at a given schedule: threads and the ParallelFor chunk size.
rayspace::emu::TlListArrays ListsOn(const tl::Tree& tree, std::uint32_t k, int threads, std::size_t chunk) {
  rayspace::test::TestSettings settings;
  settings->threads = threads;
  settings->chunk = chunk;
  const std::vector<glm::vec4> dirs = tl::Directions(k);
  rayspace::emu::TlListArrays a = rayspace::emu::PassTlLists({.tree = tree.View(), .directions = dirs, .order = 0});
  return a;
}

}  // namespace

using rayspace::test::InputErrorOf;

TEST_CASE("tl.lists: the same bits on every schedule (threads, chunk sizes)") {
  const std::vector<Triangle> tris = Soup(500, 11);
  const tl::Tree tree = tl::PrepareTree(tris);
  for (const std::uint32_t k : {2u, 8u}) {
    const rayspace::emu::TlListArrays ref = ListsOn(tree, k, 1, 0);
    for (const auto& [threads, chunk] : {std::pair{2, std::size_t{1}}, {3, std::size_t{7}}, {2, std::size_t{1000}}}) {
      const rayspace::emu::TlListArrays a = ListsOn(tree, k, threads, chunk);
      CAPTURE(threads);
      CAPTURE(chunk);
      CHECK(a.escapes == ref.escapes);
      CHECK(std::memcmp(a.words.data(), ref.words.data(), a.words.size() * sizeof(tl::Word)) == 0);
    }
  }
}

TEST_CASE("tl.trace: per ray brute force's hit, and the walk's sphere and triangle counts") {
  const std::vector<Triangle> tris = Soup(300, 13);
  const std::vector<Ray> rays = Rays(tris, 300, 5, 1.0f);
  const tl::Lists l = tl::Build(tris, {});
  for (const std::uint32_t shadow : {0u, 1u}) {
    const rayspace::emu::TlWalks w = rayspace::emu::PassTlTrace(
        {.first = l.first, .escapes = l.escapes, .words = l.words, .vertices = l.vertices, .rays = rays, .shadow = shadow});
    REQUIRE(w.spheres.size() == rays.size());
    CHECK((shadow ? w.hits.empty() : w.occluded.empty()));
    std::size_t bad = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      tl::Stats s;
      shadow ? static_cast<void>(tl::Any(l, rays[i], &s)) : static_cast<void>(tl::Closest(l, rays[i], &s));
      const std::uint64_t brute = BruteClosest(tris, rays[i]);
      const std::uint64_t want = shadow ? (brute != kMissPacked ? 1u : 0u) : brute;
      bad += (shadow ? w.occluded[i] : w.hits[i]) != want || w.spheres[i] != s.spheres || w.triangles[i] != s.triangles;
    }
    CHECK(bad == 0);
  }
}

TEST_CASE("tl: warp steps charge each ray its 32-ray warp's longest walk") {
  // 40 rays: the first warp's longest walk is ray 5's 7 + 3 = 10 elements, the second's (8 rays) ray
  // 33's 2 + 2 = 4: 32 x 10 + 8 x 4 = 352.
  std::vector<std::uint32_t> spheres(40, 1), triangles(40, 0);
  spheres[5] = 7, triangles[5] = 3;
  spheres[33] = 2, triangles[33] = 2;
  CHECK(rayspace::emu::WarpSteps(spheres, triangles) == 352u);
  CHECK(rayspace::emu::WarpSteps({}, {}) == 0u);
}

TEST_CASE("tl: keys order like their floats, -0 before +0 and a NaN last") {
  const glm::vec3 x(1, 0, 0);
  const std::uint32_t neg = tl::SphereKey({-2, 0, 0, 1}, x, 0), zero_neg = tl::SphereKey({-0.0f, -0.0f, -0.0f, 0}, x, 0),
                      zero = tl::SphereKey({0, 0, 0, 0}, x, 0), pos = tl::SphereKey({3, 0, 0, 1}, x, 0),
                      nan = tl::SphereKey({INFINITY, 0, 0, INFINITY}, x, 0);  // inf - inf
  CHECK(neg < zero_neg);
  CHECK(zero_neg < zero);
  CHECK(zero < pos);
  CHECK(pos < nan);
  CHECK(tl::SphereKey({3, 0, 0, 1}, x, 1) > pos);  // latest-last: the high end, 4 against 2
  CHECK(tl::TriangleKey({5, 0, 0}, {1, 0, 0}, {3, 0, 0}, x, 0) == tl::SphereKey({1, 0, 0, 0}, x, 0));
  CHECK(tl::TriangleKey({5, 0, 0}, {1, 0, 0}, {3, 0, 0}, x, 1) == tl::SphereKey({5, 0, 0, 0}, x, 0));
}

TEST_CASE("tl: calls whose inputs break the contract are refused, naming the call") {
  const std::vector<Triangle> tris = Soup(200, 3);
  tl::Tree tree = tl::PrepareTree(tris);
  const std::vector<glm::vec4> dirs = tl::Directions(6);
  auto lists_error = [&](const tl::Tree& t, std::span<const glm::vec4> d) {
    return InputErrorOf([&] { rayspace::emu::CheckInputs(rayspace::emu::call::TlLists{.tree = t.View(), .directions = d}); });
  };
  CHECK(lists_error(tree, dirs).empty());
  CHECK(lists_error(tree, std::span<const glm::vec4>(dirs).first(5)).find("5 directions") != std::string::npos);
  tl::Tree bad = tree;
  bad.sizes[0] += 1;
  CHECK(lists_error(bad, dirs).find("tl.lists: input 'tl_sizes' element 0") != std::string::npos);
  bad = tree;
  REQUIRE(bad.links.size() > 2);
  bad.links[1].x = 0, bad.links[1].y = 1;  // a child before its parent: a cycle
  CHECK(lists_error(bad, dirs).find("'tl_links' element 1 is out of range") != std::string::npos);
  bad = tree;
  bad.parents.back() = 0;
  CHECK_FALSE(lists_error(bad, dirs).empty());
  bad = tree;
  bad.tri_words[0].y = static_cast<std::uint32_t>(bad.vertices.size());
  CHECK(lists_error(bad, dirs).find("'tl_tri_words' element 0") != std::string::npos);
  bad = tree;
  bad.tri_words[3].w = static_cast<std::uint32_t>(bad.tri_words.size());
  CHECK(lists_error(bad, dirs).find("'tl_tri_words' element 3 names triangle") != std::string::npos);
  // An empty node would be a sphere whose escape, 1, reads as a triangle's.
  bad = tree;
  const auto leaf = std::find_if(bad.links.begin(), bad.links.end(), [](const glm::uvec4& l) { return l.y == 0; });
  REQUIRE(leaf != bad.links.end());
  leaf->w = 0;
  CHECK(lists_error(bad, dirs).find("no children and no triangles") != std::string::npos);

  const tl::Lists l = tl::Build(tris, {});
  const std::vector<Ray> rays{MakeSegment({0, 0, 2}, {0, 0, -1})};
  auto trace_error = [&](std::vector<std::uint32_t> escapes, std::vector<std::uint32_t> first) {
    return InputErrorOf([&] {
      rayspace::emu::CheckInputs(
          rayspace::emu::call::TlTrace{.first = first, .escapes = escapes, .words = l.words, .vertices = l.vertices, .rays = rays});
    });
  };
  CHECK(trace_error(l.escapes, l.first).empty());
  std::vector<std::uint32_t> e = l.escapes;
  e[l.first[1] - 1] = 1;  // the last triangle of list 0 does not end the walk
  CHECK(trace_error(e, l.first).find("tl.trace: the lists: element") != std::string::npos);
  e = l.escapes;
  e[0] = static_cast<std::uint32_t>(l.first[1]);  // list 0's root escapes out of its list
  CHECK(trace_error(e, l.first).find("outside its list") != std::string::npos);
  std::vector<std::uint32_t> f = l.first;
  f.pop_back();
  CHECK(trace_error(l.escapes, f).find("5 lists") != std::string::npos);
}
