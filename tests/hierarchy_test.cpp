// The ray-space hierarchy: sorting, stream reduction, node containment, conservative traversal,
// statistics identities and determinism.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;

TEST_CASE("sort: compress, radix sort and decompress equal a stable sort by key") {
  std::mt19937 rng(5);
  for (std::size_t n : {1u, 2u, 100u, 5000u, 70000u}) {
    std::vector<std::uint32_t> keys(n);
    // Runs of equal keys (what compression exploits) and keys using every byte.
    for (std::size_t i = 0; i < n;) {
      const std::uint32_t k = rng() % 7 == 0 ? rng() : rng() % 97;
      for (std::size_t r = 1 + rng() % 5; r > 0 && i < n; --r) keys[i++] = k;
    }
    const Chunks c = PassCompress({.keys = keys});
    const std::vector<std::uint32_t> sorted = PassSortChunks({.chunk_key = c.key});
    const std::vector<std::uint32_t> order =
        PassDecompress({.chunk_key = c.key, .chunk_base = c.base, .chunk_size = c.size, .chunk_order = sorted});
    std::vector<std::uint32_t> expect(n);
    std::iota(expect.begin(), expect.end(), 0u);
    std::stable_sort(expect.begin(), expect.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    INFO("n = " << n);
    CHECK(order == expect);
    CHECK(c.key.size() <= n);
  }
}

TEST_CASE("reduction: hierarchical and scan-based give identical streams for every component size") {
  std::mt19937 rng(9);
  for (std::size_t n : {0u, 1u, 63u, 64u, 65u, 10007u}) {
    std::vector<std::uint8_t> flags(n);
    std::vector<std::uint32_t> values(n);
    for (std::size_t i = 0; i < n; ++i) {
      flags[i] = rng() % 4 == 0;
      values[i] = static_cast<std::uint32_t>(i * 2654435761u);
    }
    const auto scan = ReduceScan(flags, values);
    std::vector<std::uint32_t> expect;
    for (std::size_t i = 0; i < n; ++i)
      if (flags[i]) expect.push_back(values[i]);
    CHECK(scan == expect);
    for (int s : {1, 2, 7, 64, 1000}) CHECK(ReduceHierarchical(flags, values, s) == expect);
  }
}

namespace {

glm::dvec3 RandomUnit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  glm::dvec3 v(g(rng), g(rng), g(rng));
  return glm::normalize(v);
}

// A random direction at angle <= alpha from axis.
glm::dvec3 InCone(std::mt19937& rng, glm::dvec3 axis, double alpha) {
  std::uniform_real_distribution<double> u(0, 1);
  const double a = alpha * u(rng);
  glm::dvec3 p = glm::cross(axis, RandomUnit(rng));
  p = glm::normalize(p);
  return glm::normalize(axis * std::cos(a) + p * std::sin(a));
}

double Angle(glm::dvec3 a, glm::dvec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }
double HalfAngle(const gpu::ConeNode& n) { return std::atan2(static_cast<double>(n.extra.x), static_cast<double>(n.cone.w)); }

}  // namespace

TEST_CASE("cone: leaf nodes hold their rays and parents hold their children (randomized, in double)") {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1), spread(0, 1);
  int full = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Children: leaves over 8 rays with origins in a small cloud and directions in a random cone,
    // including near-identical, antiparallel and wide configurations.
    const int mode = trial % 4;
    std::vector<gpu::ConeNode> kids;
    const glm::dvec3 base_axis = RandomUnit(rng);
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 axis = mode == 2 && k % 2 ? -base_axis : (mode == 3 ? RandomUnit(rng) : InCone(rng, base_axis, 0.2));
      const double alpha = mode == 0 ? 1e-4 * spread(rng) : 0.5 * spread(rng);
      const glm::dvec3 centre(u(rng) * 10, u(rng) * 10, u(rng) * 10);
      std::vector<gpu::Ray> rays(8);
      for (auto& r : rays) {
        r.origin_tmin = glm::vec4(glm::vec3(centre + glm::dvec3(u(rng), u(rng), u(rng)) * 0.1), 0);
        r.direction_tmax = glm::vec4(glm::vec3(InCone(rng, axis, alpha)), 1);
      }
      const gpu::ConeNode leaf = cone::LeafNode(8, [&](std::uint32_t j) -> const gpu::Ray& { return rays[j]; });
      for (const auto& r : rays) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(r.direction_tmax));
        if (!cone::IsFull(leaf)) CHECK(Angle(glm::dvec3(leaf.cone), d) <= HalfAngle(leaf));
        CHECK(glm::length(glm::dvec3(r.origin_tmin) - glm::dvec3(leaf.sphere)) <= leaf.sphere.w);
      }
      kids.push_back(leaf);
    }
    const gpu::ConeNode parent = cone::ParentNode(kids.data(), static_cast<std::uint32_t>(kids.size()));
    if (cone::IsFull(parent)) {
      ++full;
    } else {
      for (const auto& k : kids) {
        INFO("trial " << trial);
        CHECK(Angle(glm::dvec3(parent.cone), glm::dvec3(k.cone)) + HalfAngle(k) <= HalfAngle(parent));
      }
    }
    for (const auto& k : kids)
      CHECK(glm::length(glm::dvec3(k.sphere) - glm::dvec3(parent.sphere)) + k.sphere.w <= parent.sphere.w);
  }
  CHECK(full > 0);     // antiparallel children really produce the whole sphere
  CHECK(full < 2000);  // and most parents stay proper cones
}

TEST_CASE("cone test: wide cones, spheres behind the apex, the full sphere") {
  gpu::ConeNode n = cone::FromRay({0, 0, 0}, {0, 0, 1});
  // A narrow cone misses a sphere beside and behind the apex but meets one around the apex.
  CHECK_FALSE(cone::Test(n, {5, 0, 1, 1}, 0));
  CHECK_FALSE(cone::Test(n, {0, 0, -5, 1}, 0));
  CHECK(cone::Test(n, {0, 0.5f, -0.5f, 1}, 0));
  CHECK(cone::Test(n, {0, 0.9f, 10, 1}, 0));
  // Half-angle 120 degrees: everything but a 60-degree cone behind the apex.
  n.cone.w = -0.5f;
  n.extra.x = std::sqrt(3.0f) / 2;
  CHECK(cone::Test(n, {5, 0, -1, 0.1f}, 0));        // 101 degrees off the axis: inside
  CHECK_FALSE(cone::Test(n, {0, 0.5f, -5, 0.1f}, 0));  // 174 degrees: outside, far from the surface
  CHECK(cone::Test(cone::FullSphereCone(n), {0, 0, -5, 0.1f}, 0));
}

namespace {

struct HRun {
  FrameResult frame;
  std::vector<BatchStats> stats;
};

HRun RunHierarchy(const Scene& s, int w, int h, HierarchyConfig cfg, std::vector<std::uint64_t>* log = nullptr) {
  const SceneBuffers b = FlattenScene(s);
  cfg.image_width = w;
  cfg.image_height = h;
  cfg.candidate_log = log;
  auto tracer = MakeHierarchyTracer(b, cfg);
  FrameOptions fo;
  fo.width = w;
  fo.height = h;
  HRun r;
  r.frame = RenderFrame(s, b, *tracer, fo);
  r.stats = tracer->Stats();
  return r;
}

std::uint64_t Total(const std::vector<BatchStats>& v) {
  std::uint64_t t = 0;
  for (const auto& b : v) t += b.Total();
  return t;
}

// Hashes of the traced results (hits, occlusion) and the image, which every algorithm must share.
std::vector<std::uint64_t> Results(const FrameResult& f) {
  std::vector<std::uint64_t> out;
  for (const auto& e : f.digest.entries())
    if (e.pass.rfind("trace.", 0) == 0 || e.pass == "resolve" || e.pass.rfind("shade", 0) == 0) out.push_back(e.hash);
  return out;
}

}  // namespace

TEST_CASE("traversal: every pair the final test accepts is a hierarchy candidate (cornell-mirrors)") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  for (Algorithm a : {Algorithm::kCrsh, Algorithm::kRah, Algorithm::kRahQuadtree}) {
    HierarchyConfig cfg;
    cfg.algorithm = a;
    cfg.depth = a == Algorithm::kRahQuadtree ? 5 : 2;
    cfg.subdivision = a == Algorithm::kRahQuadtree ? 4 : 8;
    std::vector<std::uint64_t> log;
    std::vector<std::vector<gpu::Ray>> batches;
    // Re-run the frame with an observer to keep every batch's rays.
    const HRun r = RunHierarchy(s, 32, 32, cfg, &log);
    (void)r;
    // The log holds (ray, prim) per batch in batch order; rebuild the batches with the direct tracer.
    auto direct = MakeDirectTracer(b, DirectMode::kExhaustive);
    FrameOptions fo;
    fo.width = 32;
    fo.height = 32;
    RenderFrame(s, b, *direct, fo, [&](const Batch& batch) { batches.push_back(*batch.rays); });
    // Split the log at batch boundaries: ray indices restart per batch, so use the candidate count per
    // batch from the statistics.
    std::size_t at = 0, missing = 0, accepted = 0;
    REQUIRE(r.stats.size() == batches.size());
    for (std::size_t k = 0; k < batches.size(); ++k) {
      std::set<std::uint64_t> cand(log.begin() + at, log.begin() + at + r.stats[k].final_tests);
      at += r.stats[k].final_tests;
      const auto& rays = batches[k];
      for (std::uint32_t i = 0; i < rays.size(); ++i) {
        const WatertightRay wr = SetupWatertight(Xyz(rays[i].origin_tmin), Xyz(rays[i].direction_tmax));
        for (std::uint32_t p = 0; p < b.triangles.size(); ++p) {
          if (p == rays[i].info.y) continue;
          float t;
          if (!IntersectWatertight(wr, Xyz(b.triangles[p].v0), Xyz(b.triangles[p].v1), Xyz(b.triangles[p].v2),
                                   rays[i].origin_tmin.w, rays[i].direction_tmax.w, t))
            continue;
          ++accepted;
          missing += !cand.count((static_cast<std::uint64_t>(i) << 32) | p);
        }
      }
    }
    CHECK(at == log.size());
    CHECK(accepted > 1000);
    CHECK(missing == 0);
  }
}

TEST_CASE("statistics: accounting identity, RAH top level, and all algorithms agree on every hit") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  HierarchyConfig cfg;
  cfg.algorithm = Algorithm::kRah;
  const HRun rah = RunHierarchy(s, 64, 64, cfg);
  for (const BatchStats& b : rah.stats) {
    std::uint64_t sum = b.final_tests;
    for (const auto& l : b.levels) sum += l.intersections;
    CHECK(sum == b.Total());
    // RAH tests every top node against every triangle: ceil(rays / 64) x triangles.
    CHECK(b.levels.back().intersections == (b.rays + 63) / 64 * b.triangles);
    for (const auto& l : b.levels) CHECK(l.hits <= l.intersections);
  }
  cfg.algorithm = Algorithm::kCrsh;
  const HRun crsh = RunHierarchy(s, 64, 64, cfg);
  CHECK(Total(crsh.stats) < Total(rah.stats));
  cfg.algorithm = Algorithm::kRahQuadtree;
  cfg.subdivision = 4;
  cfg.depth = 6;
  const HRun quad = RunHierarchy(s, 64, 64, cfg);
  // Same hits, shading and image as the direct tracer.
  const SceneBuffers b = FlattenScene(s);
  auto direct = MakeDirectTracer(b, DirectMode::kAuto);
  FrameOptions fo;
  fo.width = 64;
  fo.height = 64;
  const FrameResult ref = RenderFrame(s, b, *direct, fo);
  CHECK(Results(rah.frame) == Results(ref));
  CHECK(Results(crsh.frame) == Results(ref));
  CHECK(Results(quad.frame) == Results(ref));
  CHECK(crsh.frame.rgb == ref.rgb);
}

TEST_CASE("determinism: hierarchy digests across threads, reductions, component sizes and forced overflow") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  HierarchyConfig cfg;
  const std::uint64_t ref = RunHierarchy(s, 64, 64, cfg).frame.digest.Frame();
  SetThreadCount(1);
  CHECK(RunHierarchy(s, 64, 64, cfg).frame.digest.Frame() == ref);
  SetThreadCount(2);
  SetChunkSize(3);
  CHECK(RunHierarchy(s, 64, 64, cfg).frame.digest.Frame() == ref);
  SetChunkSize(0);
  SetThreadCount(0);
  for (int comp : {1, 5, 64, 4096}) {
    HierarchyConfig c = cfg;
    c.component_size = comp;
    CHECK(RunHierarchy(s, 64, 64, c).frame.digest.Frame() == ref);
  }
  HierarchyConfig scan = cfg;
  scan.reduction = Reduction::kScan;
  CHECK(RunHierarchy(s, 64, 64, scan).frame.digest.Frame() == ref);
  HierarchyConfig small = cfg;
  small.pair_capacity = 2000;
  small.max_batch_triangles = 100;
  const HRun over = RunHierarchy(s, 64, 64, small);
  std::uint64_t splits = 0;
  for (const auto& b : over.stats) splits += b.overflow_splits;
  CHECK(splits > 0);  // overflow really happened
  CHECK(over.frame.digest.Frame() == ref);
}
