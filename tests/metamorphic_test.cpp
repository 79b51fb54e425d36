// Metamorphic tests: transformations of a scene that must not change what the pipeline computes.
// - Scaling the whole scene by a power of two scales every float of the geometry exactly, so every
//   ray count, hierarchy statistic and hit (primitive, and distance times the scale) is identical.
// - Permuting the triangles changes nothing but primitive ids, except where two triangles are hit
//   at exactly the same distance (a tie, resolved by the lower id); every difference must be such a
//   tie, proven with exact arithmetic.
#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/refs/exact.h"
#include "test_util.h"

using namespace rayspace;

namespace {

Scene Scaled(Scene s, float k) {
  for (Object& o : s.objects)
    for (glm::vec3& p : o.positions) p *= k;
  s.camera.eye *= k;
  s.camera.target *= k;
  for (LightDesc& l : s.lights) l.position *= k;
  return s;
}

struct Traced {
  std::vector<std::string> names;
  std::vector<std::vector<std::uint64_t>> hits;
  std::vector<std::vector<std::uint32_t>> occluded;
  std::vector<std::vector<layout::Ray>> rays;
};

struct FrameRun {
  emu::FrameResult frame;
  std::vector<emu::BatchStats> stats;
  Traced traced;
};

FrameRun Run(const Scene& s, emu::Algorithm algo, bool object_tree = false) {
  FrameRun out;
  const SceneBuffers b = FlattenScene(s);
  emu::HierarchyConfig hc;
  hc.algorithm = algo;
  hc.object_tree = object_tree;
  auto tracer = emu::MakeHierarchyTracer(b, hc);
  emu::FrameOptions fo;
  fo.width = 64;
  fo.height = 64;
  out.frame = emu::RenderFrame(s, b, *tracer, fo, [&](const emu::Batch& batch) {
    out.traced.names.push_back(batch.name);
    out.traced.rays.push_back(*batch.rays);
    out.traced.hits.push_back(batch.hits ? *batch.hits : std::vector<std::uint64_t>{});
    out.traced.occluded.push_back(batch.occluded ? *batch.occluded : std::vector<std::uint32_t>{});
  });
  out.stats = tracer->Stats();
  return out;
}

}  // namespace

TEST_CASE("metamorphic: scaling the scene by a power of two changes no statistic and no hit") {
  const Scene base = test::LoadBundled("cornell-mirrors.json");
  for (const bool tree : {false, true})
  for (emu::Algorithm algo : {emu::Algorithm::kCrsh, emu::Algorithm::kRah}) {
    CAPTURE(tree);
    const FrameRun a = Run(base, algo, tree);
    // cornell-mirrors spans about 2^9 units: 2^50 brings it close to the 2^62 domain limit.
    for (float k : {0x1p-60f, 0x1p-12f, 0x1p20f, 0x1p50f}) {
      CAPTURE(k);
      const FrameRun b = Run(Scaled(base, k), algo, tree);
      for (int kind = 0; kind < 3; ++kind) CHECK(a.frame.rays[kind] == b.frame.rays[kind]);
      REQUIRE(a.stats.size() == b.stats.size());
      for (std::size_t i = 0; i < a.stats.size(); ++i) {
        CAPTURE(a.stats[i].batch);
        CHECK(a.stats[i].final_tests == b.stats[i].final_tests);
        CHECK(a.stats[i].object_sphere_hits == b.stats[i].object_sphere_hits);
        CHECK(a.stats[i].ray_level.hits == b.stats[i].ray_level.hits);
        CHECK(a.stats[i].object_triangles.intersections == b.stats[i].object_triangles.intersections);
        for (std::size_t l = 0; l < a.stats[i].levels.size(); ++l) {
          CHECK(a.stats[i].levels[l].intersections == b.stats[i].levels[l].intersections);
          CHECK(a.stats[i].levels[l].hits == b.stats[i].levels[l].hits);
        }
      }
      REQUIRE(a.traced.names == b.traced.names);
      std::size_t compared = 0;
      for (std::size_t i = 0; i < a.traced.names.size(); ++i) {
        CAPTURE(a.traced.names[i]);
        CHECK(a.traced.occluded[i] == b.traced.occluded[i]);
        REQUIRE(a.traced.hits[i].size() == b.traced.hits[i].size());
        for (std::size_t r = 0; r < a.traced.hits[i].size(); ++r) {
          const std::uint64_t ha = a.traced.hits[i][r], hb = b.traced.hits[i][r];
          if (ha == emu::kMissPacked || hb == emu::kMissPacked) {
            CHECK(ha == hb);
            continue;
          }
          CHECK(emu::HitPrim(ha) == emu::HitPrim(hb));
          CHECK(emu::HitT(ha) * k == emu::HitT(hb));
          ++compared;
        }
      }
      CHECK(compared > 1000);
    }
  }
}

TEST_CASE("metamorphic: permuting the triangles changes hits only at exact distance ties") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  const FrameRun frame = Run(s, emu::Algorithm::kCrsh);

  // A seeded permutation of the triangle buffers: new index perm[i] holds old triangle i.
  const std::size_t n = b.triangles.size();
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(12345));
  SceneBuffers p = b;
  for (std::size_t i = 0; i < n; ++i) {
    p.triangles[perm[i]] = b.triangles[i];
    p.normals[perm[i]] = b.normals[i];
    p.info[perm[i]] = b.info[i];
  }
  std::vector<std::uint32_t> inverse(n);
  for (std::size_t i = 0; i < n; ++i) inverse[perm[i]] = static_cast<std::uint32_t>(i);

  auto original = emu::MakeDirectTracer(b, emu::DirectMode::kAuto);
  auto permuted = emu::MakeDirectTracer(p, emu::DirectMode::kAuto);
  std::size_t rays = 0, ties = 0;
  for (std::size_t i = 0; i < frame.traced.names.size(); ++i) {
    CAPTURE(frame.traced.names[i]);
    std::vector<layout::Ray> r = frame.traced.rays[i], rp = r;
    for (layout::Ray& ray : rp)
      if (ray.info.y != layout::kNoPrim) ray.info.y = perm[ray.info.y];
    rays += r.size();
    if (!frame.traced.occluded[i].empty() || frame.traced.hits[i].empty()) {
      std::vector<std::uint32_t> oa, ob;
      original->Occluded(r, oa);
      permuted->Occluded(rp, ob);
      CHECK(oa == ob);  // occlusion does not depend on order at all
      continue;
    }
    std::vector<std::uint64_t> ha, hb;
    original->Closest(r, ha);
    permuted->Closest(rp, hb);
    for (std::size_t k = 0; k < r.size(); ++k) {
      if (ha[k] == emu::kMissPacked || hb[k] == emu::kMissPacked) {
        CHECK(ha[k] == hb[k]);
        continue;
      }
      CHECK(emu::HitT(ha[k]) == emu::HitT(hb[k]));
      const std::uint32_t pa = emu::HitPrim(ha[k]), pb = inverse[emu::HitPrim(hb[k])];
      if (pa == pb) continue;
      // Different primitives at the same float distance: exact arithmetic must find both at the same t.
      const std::vector<std::uint32_t> exact = refs::ExactClosest(r[k], b);
      const bool tie = exact.size() >= 2 && std::count(exact.begin(), exact.end(), pa) && std::count(exact.begin(), exact.end(), pb);
      CHECK_MESSAGE(tie, "ray " << k << ": triangles " << pa << " and " << pb << " are not an exact tie");
      ties += tie;
    }
  }
  MESSAGE("permutation: " << rays << " rays, " << ties << " exact ties resolved differently");
  CHECK(rays > 10000);
}
