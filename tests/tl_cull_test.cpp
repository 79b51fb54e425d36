// Back-face culling in the traversal lists (`--backface-cull on`): the side convention, the culled
// fractions against their analytic values, that a dropped triangle is one every ray of its list meets
// from behind, that culling changes no walk's answer, the one-sided rule of the Embree oracle and the
// exact judge, and tl.lists' bits on every schedule with culling.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include <doctest/doctest.h>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/parallel.h"
#include "rayspace/refs/embree_tracer.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/oracle.h"
#include "rayspace/scene_buffers.h"
#include "test_util.h"

namespace tl = rayspace::emu::tl;
using rayspace::test::MakeSegment;
using rayspace::test::MakeTriangle;
using rayspace::emu::kMissPacked;
using rayspace::layout::kNoPrim;
using rayspace::layout::Ray;
using rayspace::layout::Triangle;

namespace {

// Triangles of uniformly random orientation: a unit normal from a normal distribution, an edge pair
// in its plane wound so that (v1 - v0) x (v2 - v0) points along it.
std::vector<Triangle> Oriented(std::uint32_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Triangle> t;
  while (t.size() < n) {
    const glm::dvec3 nrm(g(rng), g(rng), g(rng));
    if (glm::length(nrm) < 1e-3) continue;
    const glm::dvec3 z = glm::normalize(nrm);
    const glm::dvec3 a = glm::normalize(glm::cross(z, std::fabs(z.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(z, a);  // a x b = z
    const glm::dvec3 c(u(rng), u(rng), u(rng));
    t.push_back(MakeTriangle(glm::vec3(c), glm::vec3(c + 0.05 * a), glm::vec3(c + 0.05 * b)));
  }
  return t;
}

// The triangles list k holds.
std::vector<std::uint32_t> Held(const tl::Lists& l, std::uint32_t k) {
  std::vector<std::uint32_t> p;
  for (std::uint32_t i = l.first[k]; i < l.first[k + 1]; ++i)
    if (tl::IsTriangle(static_cast<tl::Escape>(l.escapes[i]))) p.push_back(l.words[i].w);
  std::sort(p.begin(), p.end());
  return p;
}

// The corners of list k's direction class (tl::ListFor), as doubles.
std::vector<glm::dvec3> Corners(std::uint32_t count, std::uint32_t k) {
  std::vector<glm::dvec3> g;
  if (count == 8) {
    const glm::dvec3 s((k & 1u) ? -1 : 1, (k & 2u) ? -1 : 1, (k & 4u) ? -1 : 1);
    return {{s.x, 0, 0}, {0, s.y, 0}, {0, 0, s.z}};
  }
  const int a = static_cast<int>(k / 2), b = (a + 1) % 3, c = (a + 2) % 3;
  for (const double sb : {-1.0, 1.0})
    for (const double sc : {-1.0, 1.0}) {
      glm::dvec3 v(0);
      v[a] = (k & 1u) ? -1 : 1;
      v[b] = sb;
      v[c] = sc;
      g.push_back(v);
    }
  return g;
}

tl::Lists Build(const std::vector<Triangle>& tris, std::uint32_t k, bool cull) {
  tl::Options o;
  o.lists = k;
  o.cull = cull;
  return tl::Build(tris, o);
}

}  // namespace

TEST_CASE("tl: a front hit has det > 0, a back hit det < 0 (the one-sided convention)") {
  // (v1 - v0) x (v2 - v0) = +z: the front faces +z.
  const glm::vec3 v0(0, 0, 0), v1(1, 0, 0), v2(0, 1, 0);
  for (const float dz : {-1.0f, 1.0f}) {
    const glm::vec3 o(0.2f, 0.3f, -dz), d(0.01f, -0.02f, dz);
    const rayspace::emu::WatertightRay wr = rayspace::emu::SetupWatertight(o, d);
    float t = 0, det = 0;
    REQUIRE(rayspace::emu::IntersectWatertight(wr, v0, v1, v2, 0.0f, INFINITY, t, &det));
    CAPTURE(dz);
    CHECK((dz < 0 ? det > 0.0f : det < 0.0f));
    const bool exact_front = rayspace::refs::ExactContact(MakeSegment(o, d), MakeTriangle(v0, v1, v2), true) != rayspace::refs::Contact::kMiss;
    CHECK(exact_front == (dz < 0));
  }
}

TEST_CASE("tl: the culled share of uniformly oriented triangles is the class's solid angle") {
  // Every ray of a sextant class meets a triangle's back iff n_a >= |n_b| + |n_c|: the spherical
  // square with corners (1, +-1, 0), (1, 0, +-1), 0.10817 of the sphere (two spherical triangles by
  // Van Oosterom and Strackee's formula). An octant class: n in the octant, 1/8. The classes of 1
  // and 2 lists contain directions along every plane: nothing is culled.
  const std::vector<Triangle> tris = Oriented(20000, 5);
  const double sigma6 = std::sqrt(0.10817 * (1 - 0.10817) / tris.size()), sigma8 = std::sqrt(0.125 * 0.875 / tris.size());
  for (const std::uint32_t k : {1u, 2u, 6u, 8u}) {
    const tl::Lists l = Build(tris, k, true);
    for (std::uint32_t j = 0; j < k; ++j) {
      const double culled = 1.0 - static_cast<double>(Held(l, j).size()) / static_cast<double>(tris.size());
      CAPTURE(k);
      CAPTURE(j);
      CAPTURE(culled);
      if (k <= 2) CHECK(culled == 0.0);
      if (k == 6) CHECK(std::fabs(culled - 0.10817) < 4 * sigma6);
      if (k == 8) CHECK(std::fabs(culled - 0.125) < 4 * sigma8);
    }
  }
}

TEST_CASE("tl: a culled triangle faces away from every corner of its list's class; the rest stay, once") {
  const std::vector<Triangle> tris = Oriented(3000, 9);
  for (const std::uint32_t k : {6u, 8u}) {
    const tl::Lists l = Build(tris, k, true);
    for (std::uint32_t j = 0; j < k; ++j) {
      const std::vector<std::uint32_t> held = Held(l, j);
      CHECK(std::adjacent_find(held.begin(), held.end()) == held.end());
      std::size_t i = 0;
      for (std::uint32_t p = 0; p < tris.size(); ++p) {
        const bool in = i < held.size() && held[i] == p;
        if (in) ++i;
        if (in) continue;
        const glm::dvec3 v0(glm::vec3(tris[p].v0));
        const glm::dvec3 n = glm::cross(glm::dvec3(glm::vec3(tris[p].v1)) - v0, glm::dvec3(glm::vec3(tris[p].v2)) - v0);
        for (const glm::dvec3& g : Corners(k, j)) REQUIRE(glm::dot(g, n) > 0.0);
      }
      CHECK(i == held.size());
    }
  }
}

TEST_CASE("tl: culling changes no walk: culled lists answer as the one-sided lists without culling") {
  // Both are one-sided; the lists without culling hold every triangle, so their walk is brute force
  // under the one-sided rule (the spheres only prune what cannot be hit).
  const std::vector<Triangle> tris = Oriented(2000, 17);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < 3000; ++i) {
    const Triangle& t = tris[rng() % tris.size()];
    const glm::vec3 c = (glm::vec3(t.v0) + glm::vec3(t.v1) + glm::vec3(t.v2)) / 3.0f;
    const glm::vec3 o(1.5f * u(rng), 1.5f * u(rng), 1.5f * u(rng));
    rays.push_back(MakeSegment(o, i % 3 ? c - o : glm::vec3(u(rng), u(rng), u(rng))));
  }
  for (const std::uint32_t k : {6u, 8u}) {
    const tl::Lists culled = Build(tris, k, true);
    tl::Lists sided = Build(tris, k, false);
    sided.one_sided = true;
    std::size_t hits = 0, differ = 0, any_differ = 0, culled_tests = 0, full_tests = 0;
    for (const Ray& r : rays) {
      tl::Stats a, b;
      const std::uint64_t x = tl::Closest(culled, r, &a), y = tl::Closest(sided, r, &b);
      hits += y != kMissPacked;
      differ += x != y;
      any_differ += tl::Any(culled, r) != (y != kMissPacked);
      culled_tests += a.spheres + a.triangles;
      full_tests += b.spheres + b.triangles;
    }
    CAPTURE(k);
    CHECK(hits > rays.size() / 4);
    CHECK(differ == 0);
    CHECK(any_differ == 0);
    CHECK(culled_tests < full_tests);  // the dropped triangles are not visited
  }
}

TEST_CASE("tl: one-sided lists ignore backs: a ray through a back face hits the front behind it") {
  // Two parallel squares facing -z at z = 1 and z = 2 ... a ray going +z meets both from the front;
  // a ray going -z meets their backs: none under the one-sided rule.
  std::vector<Triangle> tris;
  for (const float z : {1.0f, 2.0f}) {
    tris.push_back(MakeTriangle({-1, -1, z}, {-1, 1, z}, {1, -1, z}));  // normal -z
    tris.push_back(MakeTriangle({1, 1, z}, {1, -1, z}, {-1, 1, z}));
  }
  tl::Lists l = Build(tris, 6, true);
  const Ray up = MakeSegment({0.1f, 0.2f, 0.0f}, {0, 0, 1}), down = MakeSegment({0.1f, 0.2f, 3.0f}, {0, 0, -1});
  CHECK(tl::Closest(l, up) != kMissPacked);
  CHECK(rayspace::emu::HitT(tl::Closest(l, up)) == 1.0f);
  CHECK(tl::Closest(l, down) == kMissPacked);
  CHECK(Held(l, 5).empty());  // -z list: every triangle faces away from every -z ray
  CHECK(Held(l, 4).size() == 4);
  l = Build(tris, 6, false);
  CHECK(tl::Closest(l, down) != kMissPacked);  // two-sided: the back counts
}

TEST_CASE("refs: the oracle and the exact judge apply the one-sided rule") {
  rayspace::SceneBuffers b;
  b.triangles = {MakeTriangle({-1, -1, 1}, {-1, 1, 1}, {1, -1, 1})};  // normal -z
  b.lo = glm::vec3(-1, -1, 1);
  b.hi = glm::vec3(1, 1, 1);
  const std::vector<Ray> rays = {MakeSegment({-0.5f, -0.5f, 0}, {0, 0, 1}), MakeSegment({-0.5f, -0.5f, 2}, {0, 0, -1})};
  for (const bool one_sided : {false, true}) {
    b.one_sided = one_sided;
    const auto embree = rayspace::refs::MakeEmbreeTracer(b, 1);
    std::vector<std::uint64_t> hits;
    std::vector<std::uint32_t> occluded;
    embree->Closest(rays, hits);
    embree->Occluded(rays, occluded);
    CAPTURE(one_sided);
    CHECK(hits[0] != kMissPacked);
    CHECK((hits[1] == kMissPacked) == one_sided);
    CHECK(occluded[0] == 1u);
    CHECK(occluded[1] == (one_sided ? 0u : 1u));
    CHECK(rayspace::refs::ExactClosest(rays[1], b).empty() == one_sided);
    const rayspace::refs::Judgement j = rayspace::refs::ExactJudge(rays[1], b.triangles[0], 0x1p-20f, one_sided);
    CHECK(j.hit == !one_sided);
    CHECK(j.robust);
    CHECK(rayspace::refs::JudgeClosest(rays[1], 0, b) == (one_sided ? rayspace::refs::Answer::kWrong : rayspace::refs::Answer::kExact));
  }
  // A ray at 2^-30 rad to the plane, through the middle: its side is fragile under the judge's
  // rounding, so either answer is defensible; well clear of the plane it is robust.
  b.one_sided = true;
  const Ray grazing = MakeSegment({-0.5f, -0.5f, 0.0f}, {1.0f, 0.0f, 0x1p-30f}, 0.0f, INFINITY);
  const rayspace::refs::Judgement g = rayspace::refs::ExactJudge(grazing, MakeTriangle({-1, -1, 0}, {-1, 1, 0}, {1, -1, 0}), 0x1p-20f, true);
  CHECK_FALSE(g.robust);
}

TEST_CASE("tl.lists with culling: the same bits on every schedule (threads, chunk sizes)") {
  rayspace::test::TestSettings settings;
  const std::vector<Triangle> tris = Oriented(1500, 23);
  const tl::Tree tree = tl::PrepareTree(tris);
  for (const std::uint32_t k : {6u, 8u}) {
    const std::vector<glm::vec4> dirs = tl::Directions(k);
    auto on = [&](int threads, std::size_t chunk) {
      settings->threads = threads;
      settings->chunk = chunk;
      rayspace::emu::TlListArrays a = rayspace::emu::PassTlLists({.tree = tree.View(), .directions = dirs, .order = 0, .cull = 1});
      return a;
    };
    const rayspace::emu::TlListArrays ref = on(1, 0);
    for (std::uint32_t j = 0; j < k; ++j) CHECK(ref.lengths[j] < tree.links.size() + tree.triangles.size());
    for (const auto& [threads, chunk] : {std::pair{2, std::size_t{1}}, {3, std::size_t{7}}, {2, std::size_t{1000}}}) {
      const rayspace::emu::TlListArrays a = on(threads, chunk);
      CAPTURE(threads);
      CAPTURE(chunk);
      CHECK(a.lengths == ref.lengths);
      CHECK(a.escapes == ref.escapes);
      CHECK(std::memcmp(a.words.data(), ref.words.data(), a.words.size() * sizeof(tl::Word)) == 0);
    }
  }
}
