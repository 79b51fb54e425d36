// The ray-space hierarchy tracer: order rays (hash + compress/sort/decompress for CRSH, screen order
// for RAH, quadtree order for Roger's original), build cone-sphere nodes bottom-up, traverse top-down
// with (node, triangle) pair streams reduced after every level, and intersect the surviving pairs.
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include <nlohmann/json.hpp>

#include "rayspace/emu/backend.h"
#include "rayspace/stopwatch.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect_simd.h"
#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/emu/passes.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::uint64_t BatchStats::Total() const {
  std::uint64_t t = final_tests + leaf_sphere_tests + ray_level.intersections;
  for (const LevelStats& l : levels) t += l.intersections;
  return t;
}

namespace {

constexpr std::uint32_t kTriBits = layout::kPairTriangleBits;
constexpr std::uint32_t kTriMask = layout::kPairTriangleMask;
constexpr std::uint32_t kMaxLevelNodes = 1u << (32 - kTriBits);  // the node ids left in a packed pair
// --objects tree: rays below one group of top nodes descended together.
constexpr std::uint32_t kTreeGroupRays = 1u << 17;

// Levels 1..D of one batch's hierarchy. first[L-1] is a CSR offset array: the children of level-L
// node i are [first[i], first[i+1]) among the level L-1 nodes (the sorted rays for L = 1).
struct Hierarchy {
  std::vector<std::vector<layout::ConeNode>> nodes;
  std::vector<std::vector<std::uint32_t>> first;
};

// Half the diagonal of the scene's bounding box (1 for an empty or point-like scene).
double SceneRadius(const SceneBuffers& scene) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const layout::Triangle& t : scene.triangles)
    for (const glm::vec4& v : {t.v0, t.v1, t.v2}) lo = glm::min(lo, glm::dvec3(v)), hi = glm::max(hi, glm::dvec3(v));
  const double r = scene.triangles.empty() ? 0.0 : glm::length(hi - lo) / 2;
  return r > 0.0 ? r : 1.0;
}

// BatchStats::leaf_spread of the level-1 nodes, summed in node order.
double LeafSpread(const std::vector<layout::ConeNode>& leaves, double scene_radius) {
  double sum = 0.0;
  for (const layout::ConeNode& n : leaves) sum += std::min(1.0, (n.cone.w > 0.0f ? double(n.extra.x) : 1.0) + n.sphere.w / scene_radius);
  return leaves.empty() ? 0.0 : sum / static_cast<double>(leaves.size());
}

class Impl final : public HierarchyTracer {
 public:
  Impl(const SceneBuffers& scene, const HierarchyConfig& cfg)
      : scene_(scene),
        cfg_(cfg),
        checked_(cfg.passes && cfg.passes != &EmuHierarchyPasses() ? CheckedHierarchyPasses(*cfg.passes) : nullptr),
        passes_(checked_ ? *checked_ : EmuHierarchyPasses()) {
    RS_CHECK(cfg.subdivision >= 2 && cfg.depth >= 1 && cfg.component_size >= 1);
    RS_CHECK(cfg.max_batch_triangles >= 1 && cfg.max_batch_triangles <= (1u << kTriBits));
    RS_CHECK_MSG(cfg.cone_test == layout::kConeTestConservative ||
                     ((cfg.cone_test == layout::kConeTestPrinted || cfg.cone_test == layout::kConeTestPrintedSigned) && !cfg.object_tree &&
                      cfg.auto_tree_spread <= 0.0f),
                 "cone test {}: the object tree's descent has only the conservative test", cfg.cone_test);

    eps_ = TraversalEpsilon(scene);
  }

  std::string Name() const override {
    switch (cfg_.algorithm) {
      case Algorithm::kCrsh: return "crsh";
      case Algorithm::kRah: return "rah";
      case Algorithm::kRahQuadtree: return "rah-quadtree";
    }
    return "?";
  }
  void Describe(nlohmann::json& out) const override {
    out["name"] = Name();
    out["subdivision"] = Children();
    out["depth"] = cfg_.depth;
    out["reduction"] = cfg_.reduction == Reduction::kHierarchical ? "hierarchical" : "scan";
    out["component_size"] = cfg_.component_size;
    out["pair_capacity"] = cfg_.pair_capacity;
    out["batch_triangles"] = cfg_.max_batch_triangles;
    out["object_spheres"] = cfg_.algorithm == Algorithm::kCrsh;
    out["backend"] = passes_.Name();
    if (cfg_.cone_test == layout::kConeTestPrinted) out["cone_test"] = "printed";  // the default's description unchanged
    if (cfg_.cone_test == layout::kConeTestPrintedSigned) out["cone_test"] = "printed-signed";
  }
  void Prepare(const std::vector<glm::vec4>& tri_spheres, const std::vector<glm::vec4>& obj_spheres) override {
    RS_CHECK(tri_spheres.size() == scene_.triangles.size() && obj_spheres.size() == scene_.objects.size());
    tri_spheres_ = &tri_spheres;
    obj_spheres_ = &obj_spheres;
    scene_radius_ = SceneRadius(scene_);
  }
  void BeginBatch(const BatchContext& ctx) override { ctx_ = ctx; }
  const std::vector<BatchStats>& Stats() const override { return stats_; }

  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    hits.assign(rays.size(), kMissPacked);
    Run(rays, &hits, nullptr);
  }
  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) override {
    occluded.assign(rays.size(), 0u);
    Run(rays, nullptr, &occluded);
  }

 private:
  int Children() const { return cfg_.algorithm == Algorithm::kRahQuadtree ? 4 : cfg_.subdivision; }

  template <typename F>
  auto Sub(const std::string& pass, std::size_t elements, F&& body) {
    passes_.Label(pass + "." + ctx_.name);
    Stopwatch c;
    if constexpr (std::is_void_v<decltype(body())>) {
      body();
      Record(pass, elements, c.Ms());
    } else {
      auto r = body();
      Record(pass, elements, c.Ms());
      return r;
    }
  }
  void Record(const std::string& pass, std::size_t elements, double ms) {
    if (ctx_.subpasses) ctx_.subpasses->push_back({pass + "." + ctx_.name, ms, elements});
  }
  template <typename T>
  void Digest(const std::string& pass, const std::string& buffer, const std::vector<T>& v) {
    if (ctx_.digest) ctx_.digest->Add(pass + "." + ctx_.name, buffer, v);
  }

  bool HasBigObject() const {
    if (cfg_.auto_tree_triangles == 0) return false;
    for (const glm::uvec4& o : scene_.objects)
      if (o.y >= cfg_.auto_tree_triangles) return true;
    return false;
  }

  // Ray order and the group id of each sorted ray per level (rays with equal ids share a node).
  std::vector<std::uint32_t> Order(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& quad_keys) {
    const std::size_t n = rays.size();
    if (cfg_.algorithm == Algorithm::kRah) {
      // Screen order, one run per light: shadow slots interleave the lights (surface x lights + light),
      // and a node mixing two lights would span the space between them.
      std::vector<std::uint32_t> order;
      order.reserve(n);
      std::uint32_t lights = 1;
      for (const layout::Ray& r : rays)
        if (r.info.z == layout::kRayShadow) lights = std::max(lights, r.info.w + 1);
      for (std::uint32_t l = 0; l < lights; ++l)
        for (std::size_t i = 0; i < n; ++i)
          if ((rays[i].info.z == layout::kRayShadow ? rays[i].info.w : 0u) == l) order.push_back(static_cast<std::uint32_t>(i));
      Digest("order", "ray_order", order);
      return order;
    }
    // CRSH hashes directions (and origins); Roger's quadtree orders screen tiles, one tree per light.
    const bool quad = cfg_.algorithm == Algorithm::kRahQuadtree;
    const std::uint32_t qw = quad ? static_cast<std::uint32_t>(std::max(1, cfg_.image_width)) : 0u;
    const std::vector<std::uint32_t> keys = Sub("hash", n, [&] { return passes_.Hash({.rays = rays, .scene = &scene_, .hash = cfg_.hash, .quadtree_width = qw, .quadtree_depth = cfg_.depth}); });
    Digest("hash", "keys", keys);
    const Chunks chunks = Sub("compress", n, [&] { return passes_.Compress({.keys = keys}); });
    Digest("compress", "chunk_keys", chunks.key);
    Digest("compress", "chunk_base", chunks.base);
    const std::vector<std::uint32_t> sorted = Sub("sort", chunks.key.size(), [&] {
      const call::SortChunks call{.chunk_key = chunks.key};
      return HostFastPath() ? SortChunksHost(call) : passes_.SortChunks(call);
    });
    Digest("sort", "chunk_order", sorted);
    std::vector<std::uint32_t> order = Sub("decompress", n, [&] { return passes_.Decompress(
        {.chunk_key = chunks.key, .chunk_base = chunks.base, .chunk_size = chunks.size, .chunk_order = sorted}); });
    Digest("decompress", "ray_order", order);
    if (cfg_.algorithm == Algorithm::kRahQuadtree) {
      quad_keys.resize(n);
      for (std::size_t j = 0; j < n; ++j) quad_keys[j] = keys[order[j]];
    }
    return order;
  }

  // CSR offsets grouping `count` consecutive items whose group ids are equal.
  static std::vector<std::uint32_t> Group(std::size_t count, const std::function<std::uint32_t(std::size_t)>& id) {
    std::vector<std::uint32_t> first;
    for (std::size_t i = 0; i < count; ++i)
      if (i == 0 || id(i) != id(i - 1)) first.push_back(static_cast<std::uint32_t>(i));
    first.push_back(static_cast<std::uint32_t>(count));
    return first;
  }

  // CSR offsets of groups of s consecutive items (the last one shorter).
  static std::vector<std::uint32_t> Fixed(std::size_t count, std::uint32_t s) {
    std::vector<std::uint32_t> first((count + s - 1) / s + 1);
    for (std::size_t g = 0; g + 1 < first.size(); ++g) first[g] = static_cast<std::uint32_t>(g * s);
    first.back() = static_cast<std::uint32_t>(count);
    return first;
  }

  Hierarchy Build(const std::vector<layout::Ray>& rays, const std::vector<std::uint32_t>& order,
                  const std::vector<std::uint32_t>& quad_keys) {
    Hierarchy h;
    const int D = cfg_.depth;
    const std::uint32_t s = static_cast<std::uint32_t>(Children());
    h.nodes.resize(D);
    h.first.resize(D);
    const bool quad = cfg_.algorithm == Algorithm::kRahQuadtree;
    // Level 1 groups sorted rays; level L groups level L-1 nodes (fixed fan-out, or quadtree tiles).
    std::vector<std::uint32_t> rep;  // quadtree key of each item's first ray
    if (quad) rep = quad_keys;
    for (int L = 1; L <= D; ++L) {
      const std::size_t items = L == 1 ? order.size() : h.nodes[L - 2].size();
      if (quad) {
        h.first[L - 1] = Group(items, [&](std::size_t i) { return rep[i] >> (2 * L); });
      } else {
        h.first[L - 1] = Fixed(items, s);
      }
      const auto& f = h.first[L - 1];
      const std::size_t nodes = f.size() - 1;
      if (L == 1) {
        h.nodes[0] = passes_.BuildLeaves({.rays = rays, .order = order, .first = f});
      } else {
        h.nodes[L - 1] = passes_.BuildParents({.below = h.nodes[L - 2], .first = f, .child_merge = cfg_.child_merge});
      }
      if (quad) {
        std::vector<std::uint32_t> next(nodes);
        for (std::size_t i = 0; i < nodes; ++i) next[i] = rep[f[i]];
        rep.swap(next);
      }
    }
    return h;
  }

  // Range of level-L descendants of top nodes [lo, hi).
  std::pair<std::uint32_t, std::uint32_t> Descendants(const Hierarchy& h, int L, std::uint32_t lo, std::uint32_t hi) const {
    for (int l = cfg_.depth; l > L; --l) {
      lo = h.first[l - 1][lo];
      hi = h.first[l - 1][hi];
    }
    return {lo, hi};
  }

  std::vector<std::uint32_t> Reduce(const std::vector<std::uint8_t>& flags, const std::vector<std::uint32_t>& values) {
    return passes_.Reduce({.reduction = cfg_.reduction, .component = cfg_.component_size, .flags = flags, .values = values});
  }

  template <typename V>
  static std::uint64_t Sum(const V& v) {
    return std::accumulate(v.begin(), v.end(), std::uint64_t{0});
  }

  // The fused path on the emulator's own passes: the sort and the final tests take host shortcuts
  // with the same results (SortChunksHost, IntersectLanes). A backend runs its kernels.
  bool HostFastPath() const { return cfg_.fused && cfg_.passes == nullptr; }

  // One level of a block: its tests and the compaction of the survivors, fused in one pass
  // (traverse.compact) or as the two passes traverse and reduce; the same pairs in the same order.
  template <typename Call>
  UninitVector<std::uint32_t> TestAndCompact(int L, std::size_t slots_n, const Call& call, LevelStats& st) {
    const std::string level = std::to_string(L);
    UninitVector<std::uint32_t> pairs;
    if (cfg_.fused) {
      Compacted c = Sub("traverse.compact.L" + level, slots_n, [&] {
        if constexpr (std::is_same_v<Call, call::TraverseTop>)
          return passes_.TraverseTopCompacted(call::TraverseTopCompacted{call});
        else
          return passes_.TraverseLevelCompacted(call::TraverseLevelCompacted{call});
      });
      st.intersections = c.tested;
      pairs = std::move(c.pairs);
    } else {
      const PairSlots slots = Sub("traverse.L" + level, slots_n, [&] {
        if constexpr (std::is_same_v<Call, call::TraverseTop>)
          return passes_.TraverseTop(call);
        else
          return passes_.TraverseLevel(call);
      });
      st.intersections = Sum(slots.tested);
      const std::vector<std::uint32_t> reduced = Sub("reduce.L" + level, slots.flags.size(), [&] { return Reduce(slots.flags, slots.values); });
      pairs.assign(reduced.begin(), reduced.end());
    }
    st.hits = pairs.size();
    if (cfg_.pair_log) cfg_.pair_log->emplace_back(pairs.begin(), pairs.end());
    return pairs;
  }

  // Traverses one block (top nodes [t0, t1) x triangles [b0, b1)); false when a level overflows the
  // pair capacity, in which case nothing was written.
  bool Block(const Hierarchy& h, const std::vector<layout::Ray>& rays, const std::vector<std::uint32_t>& order,
             const std::vector<std::uint8_t>& object_mask, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
             std::uint32_t b1, BatchStats& st, std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) {
    const int D = cfg_.depth;
    const std::uint32_t T = b1 - b0, N = t1 - t0;
    const bool crsh = cfg_.algorithm == Algorithm::kCrsh;
    std::vector<LevelStats> lv(D);

    // Top level: every (node, triangle) of the block, skipping triangles whose object sphere the
    // node missed (CRSH).
    static const std::vector<std::uint8_t> kNoMask;
    const std::size_t grid = static_cast<std::size_t>(N) * T;
    const call::TraverseTop top{.top = h.nodes[D - 1], .t0 = t0, .t1 = t1, .b0 = b0, .b1 = b1, .tri_spheres = *tri_spheres_,
                                .scene = &scene_, .object_mask = crsh ? object_mask : kNoMask, .eps = eps_,
                                .cone_test = cfg_.cone_test};
    UninitVector<std::uint32_t> pairs = TestAndCompact(D, grid, top, lv[D - 1]);
    if (pairs.size() > cfg_.pair_capacity) return false;

    // Levels D-1 .. 1: each surviving pair tests the node's children.
    const std::uint32_t S = static_cast<std::uint32_t>(Children());
    for (int L = D - 1; L >= 1; --L) {
      const std::uint32_t base_up = Descendants(h, L + 1, t0, t1).first, base = Descendants(h, L, t0, t1).first;
      const call::TraverseLevel level{.pairs = pairs, .nodes = h.nodes[L - 1], .first = h.first[L], .base_up = base_up, .base = base,
                                      .children_max = S, .b0 = b0, .tri_spheres = *tri_spheres_, .eps = eps_,
                                      .cone_test = cfg_.cone_test};
      pairs = TestAndCompact(L, pairs.size() * S, level, lv[L - 1]);
      if (pairs.size() > cfg_.pair_capacity) return false;
    }

    // Final ray-triangle tests on the surviving level-1 pairs.
    const std::uint32_t base1 = Descendants(h, 1, t0, t1).first;
    const auto& f1 = h.first[0];
    std::uint64_t performed = 0, expected = 0;
    Sub("intersect", pairs.size(), [&] {
      const call::Intersect call{.pairs = pairs, .first1 = f1, .base1 = base1, .b0 = b0, .order = order, .rays = rays,
                                 .scene = &scene_, .hits = hits, .occluded = occluded, .leaf_test = cfg_.leaf_test,
                                 .tri_spheres = *tri_spheres_, .eps = eps_};
      if (HostFastPath()) {
        performed = IntersectLanes(call, watertight_);
        return;
      }
      performed = Sum(passes_.Intersect(call));
    });
    if (cfg_.candidate_log) {
      for (std::uint32_t pair : pairs) {
        const std::uint32_t node = base1 + (pair >> kTriBits), prim = b0 + (pair & kTriMask);
        for (std::uint32_t j = f1[node]; j < f1[node + 1]; ++j)
          if (cfg_.leaf_test != layout::kLeafTestRaySphere || cone::RayMayMeetSphere(rays[order[j]], (*tri_spheres_)[prim], eps_))
            cfg_.candidate_log->push_back((static_cast<std::uint64_t>(order[j]) << 32) | prim);
      }
    }
    for (const std::uint32_t pair : pairs) expected += static_cast<std::uint64_t>(h.nodes[0][base1 + (pair >> kTriBits)].extra.y);
    // The thesis's accounting: final tests = rays below the surviving level-1 nodes; with the leaf
    // sphere test those rays are its tests, and the final tests the ones that passed.
    if (cfg_.leaf_test == layout::kLeafTestRaySphere) {
      RS_CHECK_MSG(performed <= expected, "final tests {} > rays below surviving nodes {}", performed, expected);
      st.leaf_sphere_tests += expected;
    } else {
      RS_CHECK_MSG(performed == expected, "final tests {} != rays below surviving nodes {}", performed, expected);
    }
    st.final_tests += performed;
    for (int L = 0; L < D; ++L) {
      st.levels[L].intersections += lv[L].intersections;
      st.levels[L].hits += lv[L].hits;
    }
    ++st.triangle_batches;
    return true;
  }

  // --objects tree (emu/object_tree_traverse.h): the hierarchy's levels with one node per sorted ray
  // below them (the build pass with groups of one), descended together with the object tree by
  // top-node groups.
  void TraceTree(const Hierarchy& h, const std::vector<layout::Ray>& rays, const std::vector<std::uint32_t>& order, BatchStats& st,
                 std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) {
    // The object tree depends on the scene alone: built once, as Embree's and the direct tracer's BVHs,
    // when the first batch takes it (with --objects auto, a frame of flat batches never does).
    if (tree_.tree.nodes.empty())
      tree_ = Sub("build.objects", scene_.triangles.size(), [&] {
        return IndexObjectTree(BuildObjectTree(scene_.triangles, scene_.objects, cfg_.object_tree_options, *tri_spheres_), *tri_spheres_,
                               scene_.triangles);
      });
    const std::vector<std::uint32_t> singles = Fixed(order.size(), 1);
    const std::vector<layout::ConeNode> ray_nodes =
        Sub("build.rays", rays.size(), [&] { return passes_.BuildLeaves({.rays = rays, .order = order, .first = singles}); });
    // The levels as one tree (and, for the host's lanes, as arrays): part of the hierarchy's build.
    ConeTree cones = Sub("build.cones", rays.size(), [&] {
      ConeTree c = MakeConeTree(ray_nodes, h.nodes, h.first);
      if (HostFastPath())
        for (int L = 0; L <= cfg_.depth; ++L) c.lanes.push_back(cone::ToArrays(c.View().Level(L)));
      return c;
    });
    const TreeBatch batch{&cones, cones.View(), tree_.View(), &rays, &order, hits, occluded};
    // Groups of top nodes over at most kTreeGroupRays rays: a frame's pairs at the ray level would
    // otherwise outgrow the pair capacity and a whole group's rounds run twice.
    const std::uint32_t top = static_cast<std::uint32_t>(h.nodes.back().size());
    for (std::uint32_t t0 = 0; t0 < top;) {
      std::uint32_t t1 = t0 + 1;
      while (t1 < top && RaysBelow(h, t0, t1 + 1) <= kTreeGroupRays) ++t1;
      TreeGroup(batch, static_cast<std::uint32_t>(cfg_.depth), t0, t1, st);
      t0 = t1;
    }
  }

  std::uint32_t RaysBelow(const Hierarchy& h, std::uint32_t t0, std::uint32_t t1) const {
    const auto [lo, hi] = Descendants(h, 1, t0, t1);
    return h.first[0][hi] - h.first[0][lo];
  }

  struct TreeBatch {
    const ConeTree* cones;
    ConeTreeView cv;
    ObjectTreeView tv;
    const std::vector<layout::Ray>* rays;
    const std::vector<std::uint32_t>* order;
    std::vector<std::uint64_t>* hits;
    std::vector<std::uint32_t>* occluded;
  };

  // Cone nodes [t0, t1) of `level`: split in halves when a round's pairs overflow the pair capacity,
  // a single node into its children.
  void TreeGroup(const TreeBatch& b, std::uint32_t level, std::uint32_t t0, std::uint32_t t1, BatchStats& st) {
    if (TreeBlock(b, level, t0, t1, st)) return;
    ++st.overflow_splits;
    if (t1 - t0 > 1) {
      const std::uint32_t mid = t0 + (t1 - t0) / 2;
      TreeGroup(b, level, t0, mid, st);
      TreeGroup(b, level, mid, t1, st);
    } else if (level > 0) {
      TreeGroup(b, level - 1, b.cv.First(level, t0), b.cv.First(level, t0 + 1), st);
    } else {
      ThrowInput("--pair-capacity {}: too small to hold the pairs of one ray with --objects tree", cfg_.pair_capacity);
    }
  }

  void LogTree(const TreeRound& r) {
    if (!cfg_.pair_log) return;
    for (const TreePairs* p : {&r.next, &r.final}) {
      cfg_.pair_log->push_back(p->cone);
      cfg_.pair_log->push_back(p->item);
    }
  }

  // The final tests of `finals` as (ray, triangle), in the order the final tests take them.
  void LogTreeCandidates(const TreeBatch& b, const TreePairs& finals) {
    for (std::size_t p = 0; p < finals.size(); ++p) {
      const std::uint32_t prim = tree_.tree.triangles[finals.item[p] & ~layout::kTreeItemTriangle];
      const auto [j0, j1] = TreeFinalRays(b.cv.FirstOf(1), finals.cone[p], finals.item[p]);
      for (std::uint32_t j = j0; j < j1; ++j) cfg_.candidate_log->push_back((static_cast<std::uint64_t>((*b.order)[j]) << 32) | prim);
    }
  }

  // Slots compacted into the pairs that go on and the final ones: two reductions over slot indices.
  TreeRound CompactTreeSlots(const TreeSlots& s) {
    const std::size_t slots = s.flags.size();
    std::vector<std::uint32_t> index(slots);
    for (std::size_t k = 0; k < slots; ++k) index[k] = static_cast<std::uint32_t>(k);
    TreeRound r;
    r.counts = s.counts;
    for (const std::uint8_t kind : {std::uint8_t{1}, std::uint8_t{2}}) {
      std::vector<std::uint8_t> flags(slots);
      for (std::size_t k = 0; k < slots; ++k) flags[k] = s.flags[k] == kind;
      const std::vector<std::uint32_t> kept = Sub("reduce.tree", slots, [&] { return Reduce(flags, index); });
      TreePairs& to = kind == 1 ? r.next : r.final;
      for (const std::uint32_t k : kept) to.cone.push_back(s.pairs.cone[k]), to.item.push_back(s.pairs.item[k]);
    }
    return r;
  }

  // One round as its passes: expand, the exclusive scan of the counts (on the host), test, and the
  // two reductions.
  TreeRound TreeRoundByPasses(const TreeBatch& b, const TreePairs& pairs) {
    const std::vector<std::uint32_t> counts = Sub("tree.expand", pairs.size(), [&] {
      return passes_.TreeExpand({.cones = b.cv, .tree = b.tv, .pair_cone = pairs.cone, .pair_item = pairs.item});
    });
    std::vector<std::uint32_t> offsets(counts.size());
    std::size_t slots = 0;
    for (std::size_t p = 0; p < counts.size(); ++p) offsets[p] = static_cast<std::uint32_t>(slots), slots += counts[p];
    // The pairs of a round are bounded by the pair capacity, what they expand to is not: a capacity
    // near its maximum can ask for more slots than 32-bit offsets address.
    if (slots >= (std::size_t{1} << 32))
      ThrowInput("--pair-capacity {}: an object-tree round expands {} pairs to {} slots, beyond 32-bit offsets; give a smaller "
                 "capacity",
                 cfg_.pair_capacity, pairs.size(), slots);
    const TreeSlots s = Sub("tree.test", slots, [&] {
      return passes_.TreeTest({.cones = b.cv, .tree = b.tv, .pair_cone = pairs.cone, .pair_item = pairs.item, .offsets = offsets,
                               .slots = static_cast<std::uint32_t>(slots), .eps = eps_});
    });
    return CompactTreeSlots(s);
  }

  TreeRound TreeRoundFused(const TreeBatch& b, const TreePairs& pairs) {
    return Sub("tree.step", pairs.size(), [&] {
      const call::TreeStep c{.cones = b.cv, .tree = b.tv, .pair_cone = pairs.cone, .pair_item = pairs.item, .eps = eps_};
      return HostFastPath() ? PassTreeStepLanes(c, {&b.cones->lanes, &tree_}) : passes_.TreeStep(c);
    });
  }

  bool TreeBlock(const TreeBatch& b, std::uint32_t level, std::uint32_t t0, std::uint32_t t1, BatchStats& st) {
    const TreeSlots roots = Sub("tree.roots", static_cast<std::size_t>(t1 - t0) * tree_.tree.roots.size(), [&] {
      return passes_.TreeRoots({.cones = b.cv, .tree = b.tv, .level = level, .t0 = t0, .t1 = t1, .eps = eps_});
    });
    TreeRound r = CompactTreeSlots(roots);
    LogTree(r);
    TreeCounts counts = r.counts;
    TreePairs finals = std::move(r.final), pairs = std::move(r.next);
    std::uint64_t rounds = 1;
    while (pairs.size() > 0) {
      if (pairs.size() > cfg_.pair_capacity || finals.size() > cfg_.pair_capacity) return false;
      TreeRound next = cfg_.fused ? TreeRoundFused(b, pairs) : TreeRoundByPasses(b, pairs);
      LogTree(next);
      counts.Add(next.counts);
      Sub("tree.gather", next.final.size(), [&] {
        finals.cone.insert(finals.cone.end(), next.final.cone.begin(), next.final.cone.end());
        finals.item.insert(finals.item.end(), next.final.item.begin(), next.final.item.end());
      });
      pairs = std::move(next.next);
      ++rounds;
    }
    if (finals.size() > cfg_.pair_capacity) return false;
    const std::vector<std::uint32_t> tests = Sub("intersect.tree", finals.size(), [&] {
      const call::IntersectTree call{.pair_cone = finals.cone, .pair_item = finals.item, .first1 = b.cv.FirstOf(1),
                                     .tree_triangles = tree_.tree.triangles, .order = *b.order, .rays = *b.rays, .scene = &scene_,
                                     .hits = b.hits, .occluded = b.occluded};
      return HostFastPath() ? PassIntersectTreeLanes(call, watertight_, tree_) : passes_.IntersectTree(call);
    });
    for (const std::uint32_t t : tests) st.final_tests += t;
    if (cfg_.candidate_log) LogTreeCandidates(b, finals);
    AddTreeCounts(counts, rounds, st);
    return true;
  }

  void AddTreeCounts(const TreeCounts& counts, std::uint64_t rounds, BatchStats& st) const {
    for (int L = 1; L <= cfg_.depth; ++L) {
      st.levels[L - 1].intersections += counts.cone_tests[L];
      st.levels[L - 1].hits += counts.cone_hits[L];
    }
    st.ray_level.intersections += counts.cone_tests[0];
    st.ray_level.hits += counts.cone_hits[0];
    st.object_levels.resize(std::max(st.object_levels.size(), counts.node_tests.size()));
    for (std::size_t d = 0; d < counts.node_tests.size(); ++d) {
      st.object_levels[d].intersections += counts.node_tests[d];
      st.object_levels[d].hits += counts.node_hits[d];
    }
    st.object_triangles.intersections += counts.tri_tests;
    st.object_triangles.hits += counts.tri_hits;
    st.tree_rounds += rounds;
    ++st.triangle_batches;
  }

  void Process(const Hierarchy& h, const std::vector<layout::Ray>& rays, const std::vector<std::uint32_t>& order,
               const std::vector<std::uint8_t>& mask, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0, std::uint32_t b1,
               BatchStats& st, std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) {
    if (Block(h, rays, order, mask, t0, t1, b0, b1, st, hits, occluded)) return;
    // Overflow: split the triangle batch (or, for a single triangle, the nodes) and go again.
    ++st.overflow_splits;
    if (b1 - b0 > 1) {
      const std::uint32_t mid = b0 + (b1 - b0) / 2;
      Process(h, rays, order, mask, t0, t1, b0, mid, st, hits, occluded);
      Process(h, rays, order, mask, t0, t1, mid, b1, st, hits, occluded);
    } else if (t1 - t0 > 1) {
      const std::uint32_t mid = t0 + (t1 - t0) / 2;
      Process(h, rays, order, mask, t0, mid, b0, b1, st, hits, occluded);
      Process(h, rays, order, mask, mid, t1, b0, b1, st, hits, occluded);
    } else {
      ThrowInput("--pair-capacity {}: too small to hold the pairs of one node and one triangle", cfg_.pair_capacity);
    }
  }

  void Run(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) {
    BatchStats st;
    st.batch = ctx_.name;
    st.kind = ctx_.kind;
    st.bounce = ctx_.bounce;
    st.rays = rays.size();
    st.triangles = scene_.triangles.size();
    st.levels.assign(cfg_.depth, {});
    RS_CHECK_MSG(tri_spheres_ != nullptr, "the hierarchy tracer needs Prepare() before tracing");
    if (rays.empty()) {
      stats_.push_back(st);
      return;
    }
    std::vector<std::uint32_t> quad_keys;
    const std::vector<std::uint32_t> order = Order(rays, quad_keys);
    const Hierarchy h = Sub("build", rays.size(), [&] { return Build(rays, order, quad_keys); });
    if (HostFastPath()) watertight_ = Sub("intersect.setup", rays.size(), [&] { return ToWatertightArrays(rays, order); });
    for (int L = 1; L <= cfg_.depth; ++L) Digest("build", "nodes.L" + std::to_string(L), h.nodes[L - 1]);
    const std::uint32_t top = static_cast<std::uint32_t>(h.nodes[cfg_.depth - 1].size());

    st.leaf_spread = LeafSpread(h.nodes[0], scene_radius_);
    st.object_tree = cfg_.auto_tree_spread > 0.0f ? st.leaf_spread >= cfg_.auto_tree_spread || HasBigObject() : cfg_.object_tree;
    if (st.object_tree) {
      TraceTree(h, rays, order, st, hits, occluded);
      stats_.push_back(st);
      return;
    }

    // CRSH: top nodes against object spheres first, once per batch.
    std::vector<std::uint8_t> mask;
    if (cfg_.algorithm == Algorithm::kCrsh) {
      mask = Sub("traverse.objects", static_cast<std::size_t>(top) * scene_.objects.size(),
                 [&] { return passes_.ObjectMask({.top = h.nodes[cfg_.depth - 1], .object_spheres = *obj_spheres_, .eps = eps_,
                                              .cone_test = cfg_.cone_test}); });
      st.object_sphere_tests = mask.size();
      st.object_sphere_hits = Sum(mask);
    }

    // Node groups keep packed node ids within 18 bits and the top-level grid bounded.
    const std::uint32_t T = static_cast<std::uint32_t>(scene_.triangles.size());
    std::uint32_t t0 = 0;
    while (t0 < top) {
      std::uint32_t t1 = t0 + 1;
      const std::size_t grid_nodes = std::max<std::size_t>(1, kMaxTopGrid / std::min<std::uint32_t>(T, cfg_.max_batch_triangles));
      while (t1 < top && t1 - t0 < grid_nodes) {
        const auto [lo, hi] = Descendants(h, 1, t0, t1 + 1);
        if (hi - lo > kMaxLevelNodes) break;
        ++t1;
      }
      for (std::uint32_t b0 = 0; b0 < T; b0 += cfg_.max_batch_triangles)
        Process(h, rays, order, mask, t0, t1, b0, std::min(T, b0 + cfg_.max_batch_triangles), st, hits, occluded);
      t0 = t1;
    }
    stats_.push_back(st);
  }

  const SceneBuffers& scene_;
  const std::vector<glm::vec4>* tri_spheres_ = nullptr;
  const std::vector<glm::vec4>* obj_spheres_ = nullptr;
  HierarchyConfig cfg_;
  // A backend other than the emulator's own hands back outputs checked where it returns them
  // (emu/output_checks.h): pairs, counts and hit primitives are in range before the host reads with them.
  std::unique_ptr<HierarchyPasses> checked_;
  HierarchyPasses& passes_;
  float eps_ = 0;
  ObjectTreeIndex tree_;  // --objects tree
  double scene_radius_ = 1.0;
  WatertightArrays watertight_;  // the fused path's rays of the batch, set up for the final tests
  BatchContext ctx_;
  std::vector<BatchStats> stats_;
};

}  // namespace

std::vector<std::uint32_t> FixedGroups(std::size_t count, std::uint32_t per) {
  std::vector<std::uint32_t> first;
  for (std::size_t i = 0; i < count; i += per) first.push_back(static_cast<std::uint32_t>(i));
  first.push_back(static_cast<std::uint32_t>(count));
  return first;
}

std::unique_ptr<HierarchyTracer> MakeHierarchyTracer(const SceneBuffers& scene, const HierarchyConfig& config) {
  return std::make_unique<Impl>(scene, config);
}

}  // namespace rayspace::emu
