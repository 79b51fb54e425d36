// The bounds of every call's outputs (emu/output_checks.h): each index a later pass or the host reads
// with, and each count the host adds up, against the call's own inputs.
#include "rayspace/emu/output_checks.h"
#include "grid_bin.h"

#include <algorithm>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "rayspace/contract.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/tl.h"

namespace rayspace::emu {
namespace {

using layout::kPairTriangleBits;
using layout::kPairTriangleMask;
using layout::kTreeItemTriangle;
using layout::kTreeLevelShift;
using layout::kTreeNodeMask;

// Counts held in a float (a cone node's rays below) are exact below 2^24; above, the sums may round.
constexpr double kExactFloatCount = 16777216.0;

class Check {
 public:
  Check(std::string_view call, const OutputSource& from) : call_(call), from_(from) {}

  template <typename... A>
  [[noreturn]] void Fail(std::string_view buffer, std::size_t i, fmt::format_string<A...> f, A&&... a) const {
    throw DeviceOutputError(fmt::format("{}{} from the {} backend: output '{}' element {} {}", call_,
                                        from_.label.empty() || from_.label == call_ ? "" : fmt::format(" ({})", from_.label),
                                        from_.backend, buffer, i, fmt::format(f, std::forward<A>(a)...)));
  }

  void Size(std::string_view buffer, std::size_t got, std::size_t want) const {
    if (got != want)
      throw DeviceOutputError(fmt::format("{}{} from the {} backend: output '{}' holds {} elements, expected {}", call_,
                                          from_.label.empty() || from_.label == call_ ? "" : fmt::format(" ({})", from_.label),
                                          from_.backend, buffer, got, want));
  }

  template <typename T>
  void Below(std::string_view buffer, const std::vector<T>& v, std::uint64_t bound) const {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (std::uint64_t{v[i]} >= bound) Fail(buffer, i, "is {}, out of range [0, {})", std::uint64_t{v[i]}, bound);
  }

  // A primitive id: kNoPrim or a triangle of the scene.
  void Prims(std::string_view buffer, const std::vector<std::uint32_t>& v, std::size_t triangles) const {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (v[i] != layout::kNoPrim && v[i] >= triangles)
        Fail(buffer, i, "names triangle {}, out of range [0, {})", v[i], triangles);
  }

  void Surfaces(const std::vector<layout::Surface>& v, std::size_t pixels, const SceneBuffers& scene) const {
    for (std::size_t i = 0; i < v.size(); ++i) {
      const glm::uvec4 info = v[i].info;
      if (info.y >= pixels) Fail("surfaces", i, "names pixel {}, out of range [0, {})", info.y, pixels);
      if (info.x == layout::kNoPrim) continue;
      if (info.x >= scene.triangles.size()) Fail("surfaces", i, "names triangle {}, out of range [0, {})", info.x, scene.triangles.size());
      if (info.z >= scene.materials.size()) Fail("surfaces", i, "names material {}, out of range [0, {})", info.z, scene.materials.size());
    }
  }

  // Closest hits (packed distance and primitive, ~0 for a miss) or occlusion flags, merged in place.
  void Records(const std::vector<std::uint64_t>* hits, const std::vector<std::uint32_t>* occluded, std::size_t rays,
               std::size_t triangles) const {
    if (hits) {
      Size("hits", hits->size(), rays);
      for (std::size_t i = 0; i < hits->size(); ++i)
        if ((*hits)[i] != ~std::uint64_t{0} && static_cast<std::uint32_t>((*hits)[i]) >= triangles)
          Fail("hits", i, "names triangle {}, out of range [0, {})", static_cast<std::uint32_t>((*hits)[i]), triangles);
    }
    if (occluded) {
      Size("occluded", occluded->size(), rays);
      Below("occluded", *occluded, 2);
    }
  }

  // A cone node's count of rays below (extra.y), where a float holds it exactly.
  void RaysBelow(const layout::ConeNode& n, std::size_t i, double want) const {
    if (want < kExactFloatCount && static_cast<double>(n.extra.y) != want)
      Fail("nodes", i, "counts {} rays below, expected {}", n.extra.y, want);
  }

 private:
  std::string_view call_;
  OutputSource from_;
};

std::size_t Pixels(const layout::FrameConstants& fc) { return static_cast<std::size_t>(fc.dims.x) * fc.dims.y; }

// A tree pair's halves: a node of its cone level and an object-tree node or triangle-list entry.
bool TreePairInRange(const ConeTreeView& c, const ObjectTreeView& t, std::uint32_t cone, std::uint32_t item) {
  const std::uint32_t L = cone >> kTreeLevelShift, n = cone & kTreeNodeMask, k = item & ~kTreeItemTriangle;
  const bool tri = (item & kTreeItemTriangle) != 0;
  return L <= static_cast<std::uint32_t>(c.Depth()) && n < c.Count(L) && k < (tri ? t.tree_triangles.size() : t.tree_spheres.size());
}

// Final: a level-0 or level-1 node with a triangle, whose rays intersect.tree tests; the other pairs
// go on to tree.expand, which refines them.
bool TreePairFinal(std::uint32_t cone, std::uint32_t item) { return (cone >> kTreeLevelShift) <= 1 && (item & kTreeItemTriangle); }

// `kind`: per pair 1 (goes on) or 2 (final), 0 (dropped, never read); null: all of `all_kind`.
void CheckTreePairs(const Check& k, std::string_view cone_name, std::string_view item_name, const TreePairs& p, const ConeTreeView& c,
               const ObjectTreeView& t, const std::vector<std::uint8_t>* kind, std::uint8_t all_kind) {
  k.Size(item_name, p.item.size(), p.cone.size());
  for (std::size_t i = 0; i < p.cone.size(); ++i) {
    const std::uint8_t want = kind ? (*kind)[i] : all_kind;
    if (want == 0) continue;
    if (!TreePairInRange(c, t, p.cone[i], p.item[i]))
      k.Fail(cone_name, i, "is the pair ({:#x}, {:#x}), outside the cone tree's levels or the object tree", p.cone[i], p.item[i]);
    if (TreePairFinal(p.cone[i], p.item[i]) != (want == 2))
      k.Fail(cone_name, i, "is the pair ({:#x}, {:#x}), {}", p.cone[i], p.item[i],
             want == 2 ? "marked final, but not a level-0 or level-1 node with a triangle" : "final, but marked to go on");
  }
}

void TreeCountSizes(const Check& k, const TreeCounts& n, const ConeTreeView& c, const ObjectTreeView& t) {
  std::uint32_t depths = 0;
  for (const std::uint32_t d : t.tree_depth) depths = std::max(depths, d + 1);
  const std::size_t levels = static_cast<std::size_t>(c.Depth()) + 1;
  k.Size("counts.cone_tests", n.cone_tests.size(), levels);
  k.Size("counts.cone_hits", n.cone_hits.size(), levels);
  k.Size("counts.node_tests", n.node_tests.size(), depths);
  k.Size("counts.node_hits", n.node_hits.size(), depths);
}

void TreeSlotsOut(const Check& k, const TreeSlots& s, std::size_t slots, const ConeTreeView& c, const ObjectTreeView& t) {
  k.Size("flags", s.flags.size(), slots);
  k.Size("cone", s.pairs.cone.size(), slots);
  k.Below("flags", s.flags, 3);
  CheckTreePairs(k, "cone", "item", s.pairs, c, t, &s.flags, 0);
  TreeCountSizes(k, s.counts, c, t);
}

// The rays a final tree pair's tests cover: a level-1 node's, or the one ray of a level-0 node.
std::uint64_t TreeFinalRayCount(const call::IntersectTree& c, std::size_t p) {
  const std::uint32_t L = c.pair_cone[p] >> kTreeLevelShift, n = c.pair_cone[p] & kTreeNodeMask;
  return L == 1 ? std::uint64_t{c.first1[n + 1]} - c.first1[n] : 1;
}

}  // namespace

void CheckOutputs(const call::Raster& c, const GBuffer* g, const OutputSource& from) {
  const Check k(c.kName, from);
  if (g->width != static_cast<int>(c.frame.dims.x) || g->height != static_cast<int>(c.frame.dims.y))
    k.Fail("width", 0, "is a {}x{} G-buffer, not the frame's {}x{}", g->width, g->height, c.frame.dims.x, c.frame.dims.y);
  const std::size_t n = Pixels(c.frame);
  k.Size("diffuse", g->diffuse.size(), n);
  k.Size("specular", g->specular.size(), n);
  k.Size("position", g->position.size(), n);
  k.Size("normal", g->normal.size(), n);
  k.Size("prim", g->prim.size(), n);
  k.Size("depth", g->depth.size(), n);
  k.Prims("prim", g->prim, c.scene->triangles.size());
}

void CheckOutputs(const call::SurfacesFromGBuffer& c, const std::vector<layout::Surface>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("surfaces", r->size(), Pixels(c.frame));
  k.Surfaces(*r, Pixels(c.frame), *c.scene);
}

void CheckOutputs(const call::SurfacesFromHits& c, const std::vector<layout::Surface>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("surfaces", r->size(), c.rays.size());
  std::uint32_t pixels = 0;  // the pixels the rays came from bound those of their hits' surfaces
  for (const layout::Ray& ray : c.rays) pixels = std::max(pixels, ray.info.x + 1);
  k.Surfaces(*r, pixels, *c.scene);
}

void CheckOutputs(const call::Raygen& c, const SparseRays* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::size_t slots = c.surfaces.size() * (c.kind == layout::kRayShadow ? ShadowSlots(c.scene->lights) : 1);
  k.Size("rays", r->rays.size(), slots);
  k.Size("flags", r->flags.size(), slots);
  k.Below("flags", r->flags, 2);
  for (std::size_t i = 0; i < slots; ++i) {
    if (!r->flags[i]) continue;
    const glm::uvec4 info = r->rays[i].info;
    if (info.x >= Pixels(c.frame)) k.Fail("rays", i, "names pixel {}, out of range [0, {})", info.x, Pixels(c.frame));
    if (info.y != layout::kNoPrim && info.y >= c.scene->triangles.size())
      k.Fail("rays", i, "leaves triangle {}, out of range [0, {})", info.y, c.scene->triangles.size());
  }
}

void CheckOutputs(const call::Trim& c, const Trimmed* r, const OutputSource& from) {
  const Check k(c.kName, from);
  std::size_t heads = 0;
  for (std::uint32_t f : c.flags) heads += f;
  k.Size("rays", r->rays.size(), heads);
  k.Size("offsets", r->offsets.size(), c.flags.size());
  for (std::size_t i = 0; i < c.flags.size(); ++i)
    if (c.flags[i] && r->offsets[i] >= heads) k.Fail("offsets", i, "is {}, out of range [0, {})", r->offsets[i], heads);
}

void CheckOutputs(const call::Shade& c, const void*, const OutputSource& from) {
  Check(c.kName, from).Size("accum", c.accum->size(), Pixels(c.frame) * 3);
}

void CheckOutputs(const call::Resolve& c, const std::vector<std::uint8_t>* r, const OutputSource& from) {
  Check(c.kName, from).Size("rgb", r->size(), c.accum.size());
}

void CheckOutputs(const call::Hash& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  Check(c.kName, from).Size("keys", r->size(), c.rays.size());
}

void CheckOutputs(const call::Compress& c, const Chunks* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("chunk_base", r->base.size(), r->key.size());
  k.Size("chunk_size", r->size.size(), r->key.size());
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < r->key.size(); ++i) {
    if (std::uint64_t{r->base[i]} + r->size[i] > c.keys.size())
      k.Fail("chunk_base", i, "starts a chunk of {} rays at {}, beyond the {} rays", r->size[i], r->base[i], c.keys.size());
    total += r->size[i];
  }
  if (total != c.keys.size()) k.Fail("chunk_size", r->key.size() - 1, "ends chunks holding {} rays, not the {} keys", total, c.keys.size());
}

void CheckOutputs(const call::SortChunks& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("chunk_order", r->size(), c.chunk_key.size());
  k.Below("chunk_order", *r, c.chunk_key.size());
}

void CheckOutputs(const call::Decompress& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  std::uint64_t total = 0;
  for (std::uint32_t s : c.chunk_size) total += s;
  k.Size("ray_order", r->size(), total);
  k.Below("ray_order", *r, total);
}

void CheckOutputs(const call::BuildLeaves& c, const std::vector<layout::ConeNode>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("nodes", r->size(), c.first.size() - 1);
  for (std::size_t i = 0; i < r->size(); ++i) k.RaysBelow((*r)[i], i, double(c.first[i + 1]) - double(c.first[i]));
}

void CheckOutputs(const call::BuildParents& c, const std::vector<layout::ConeNode>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("nodes", r->size(), c.first.size() - 1);
  for (std::size_t i = 0; i < r->size(); ++i) {
    double below = 0.0;
    for (std::uint32_t j = c.first[i]; j < c.first[i + 1]; ++j) below += c.below[j].extra.y;
    k.RaysBelow((*r)[i], i, below);
  }
}

void CheckOutputs(const call::ObjectMask& c, const std::vector<std::uint8_t>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("mask", r->size(), c.top.size() * c.object_spheres.size());
  k.Below("mask", *r, 2);
}

namespace {
// A top-level pair: a node of [t0, t1) and a triangle of [b0, b1), both relative.
void TopPair(const Check& k, std::string_view buffer, std::size_t i, std::uint32_t v, std::uint32_t nodes, std::uint32_t tris) {
  if ((v >> kPairTriangleBits) >= nodes || (v & kPairTriangleMask) >= tris)
    k.Fail(buffer, i, "is the pair {:#x} (node {}, triangle {}), outside the block's {} nodes x {} triangles", v,
           v >> kPairTriangleBits, v & kPairTriangleMask, nodes, tris);
}

// A lower level's pair: a node of the level below (relative to base) and a triangle of the block.
void LevelPair(const Check& k, std::string_view buffer, std::size_t i, std::uint32_t v, const call::TraverseLevel& c) {
  const std::uint64_t node = std::uint64_t{c.base} + (v >> kPairTriangleBits), tri = std::uint64_t{c.b0} + (v & kPairTriangleMask);
  if (node >= c.nodes.size() || tri >= c.tri_spheres.size())
    k.Fail(buffer, i, "is the pair {:#x} (node {}, triangle {}), outside the level's {} nodes or the {} triangles", v, node, tri,
           c.nodes.size(), c.tri_spheres.size());
}
}  // namespace

void CheckOutputs(const call::TraverseTop& c, const PairSlots* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::uint32_t nodes = c.t1 - c.t0, tris = c.b1 - c.b0;
  const std::size_t slots = std::size_t{nodes} * tris;
  k.Size("flags", r->flags.size(), slots);
  k.Size("values", r->values.size(), slots);
  k.Size("tested", r->tested.size(), slots);
  k.Below("flags", r->flags, 2);
  k.Below("tested", r->tested, 2);
  for (std::size_t i = 0; i < slots; ++i)
    if (r->flags[i]) TopPair(k, "values", i, r->values[i], nodes, tris);
}

void CheckOutputs(const call::TraverseLevel& c, const PairSlots* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::size_t S = c.children_max, slots = c.pairs.size() * S;
  k.Size("flags", r->flags.size(), slots);
  k.Size("values", r->values.size(), slots);
  k.Size("tested", r->tested.size(), c.pairs.size());
  k.Below("flags", r->flags, 2);
  for (std::size_t p = 0; p < c.pairs.size(); ++p) {
    const std::uint32_t parent = c.base_up + (c.pairs[p] >> kPairTriangleBits), c0 = c.first[parent], c1 = c.first[parent + 1];
    if (r->tested[p] != c1 - c0) k.Fail("tested", p, "counts {} children, but the pair's node has {}", r->tested[p], c1 - c0);
    for (std::size_t s = p * S; s < (p + 1) * S; ++s) {
      if (!r->flags[s]) continue;
      const std::uint32_t v = r->values[s], child = c.base + (v >> kPairTriangleBits);
      if (child < c0 || child >= c1 || (v & kPairTriangleMask) != (c.pairs[p] & kPairTriangleMask))
        k.Fail("values", s, "is the pair {:#x}, not a child of pair {}'s node (children [{}, {})) with its triangle", v, p, c0, c1);
    }
  }
}

void CheckOutputs(const call::TraverseTopCompacted& c, const Compacted* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::uint32_t nodes = c.t1 - c.t0, tris = c.b1 - c.b0;
  const std::uint64_t slots = std::uint64_t{nodes} * tris;
  if (r->tested > slots) k.Fail("tested", 0, "counts {} tests, more than the block's {} slots", r->tested, slots);
  if (r->pairs.size() > r->tested) k.Size("pairs", r->pairs.size(), r->tested);
  for (std::size_t i = 0; i < r->pairs.size(); ++i) TopPair(k, "pairs", i, r->pairs[i], nodes, tris);
}

void CheckOutputs(const call::TraverseLevelCompacted& c, const Compacted* r, const OutputSource& from) {
  const Check k(c.kName, from);
  std::uint64_t children = 0;
  for (const std::uint32_t p : c.pairs) {
    const std::uint32_t parent = c.base_up + (p >> kPairTriangleBits);
    children += c.first[parent + 1] - c.first[parent];
  }
  if (r->tested != children) k.Fail("tested", 0, "counts {} tests, but the pairs' nodes have {} children", r->tested, children);
  if (r->pairs.size() > r->tested) k.Size("pairs", r->pairs.size(), r->tested);
  for (std::size_t i = 0; i < r->pairs.size(); ++i) LevelPair(k, "pairs", i, r->pairs[i], c);
}

void CheckOutputs(const call::Reduce& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  std::vector<std::uint32_t> flagged;
  for (std::size_t i = 0; i < c.flags.size(); ++i)
    if (c.flags[i]) flagged.push_back(c.values[i]);
  if (r->size() > flagged.size()) k.Size("pairs", r->size(), flagged.size());
  std::sort(flagged.begin(), flagged.end());
  for (std::size_t i = 0; i < r->size(); ++i)
    if (!std::binary_search(flagged.begin(), flagged.end(), (*r)[i]))
      k.Fail("pairs", i, "is {:#x}, the value of no flagged slot", (*r)[i]);
}

void CheckOutputs(const call::Intersect& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("tests", r->size(), c.pairs.size());
  for (std::size_t p = 0; p < c.pairs.size(); ++p) {
    const std::uint32_t node = c.base1 + (c.pairs[p] >> kPairTriangleBits), rays = c.first1[node + 1] - c.first1[node];
    // The leaf sphere test leaves any number of the node's rays to the ray-triangle test.
    if (c.leaf_test == layout::kLeafTestRaySphere ? (*r)[p] > rays : (*r)[p] != rays)
      k.Fail("tests", p, "counts {} tests, but the pair's node holds {} rays", (*r)[p], rays);
  }
  k.Records(c.hits, c.occluded, c.rays.size(), c.scene->triangles.size());
}

void CheckOutputs(const call::TreeRoots& c, const TreeSlots* r, const OutputSource& from) {
  TreeSlotsOut(Check(c.kName, from), *r, std::size_t{c.t1 - c.t0} * c.tree.tree_roots.size(), c.cones, c.tree);
}

void CheckOutputs(const call::TreeExpand& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  Check(c.kName, from).Size("counts", r->size(), c.pair_cone.size());
}

void CheckOutputs(const call::TreeTest& c, const TreeSlots* r, const OutputSource& from) {
  TreeSlotsOut(Check(c.kName, from), *r, c.slots, c.cones, c.tree);
}

void CheckOutputs(const call::TreeStep& c, const TreeRound* r, const OutputSource& from) {
  const Check k(c.kName, from);
  CheckTreePairs(k, "next_cone", "next_item", r->next, c.cones, c.tree, nullptr, 1);
  CheckTreePairs(k, "final_cone", "final_item", r->final, c.cones, c.tree, nullptr, 2);
  TreeCountSizes(k, r->counts, c.cones, c.tree);
}

void CheckOutputs(const call::IntersectTree& c, const std::vector<std::uint32_t>* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("tests", r->size(), c.pair_cone.size());
  for (std::size_t p = 0; p < c.pair_cone.size(); ++p)
    if ((*r)[p] != TreeFinalRayCount(c, p))
      k.Fail("tests", p, "counts {} tests, but the pair covers {} rays", (*r)[p], TreeFinalRayCount(c, p));
  k.Records(c.hits, c.occluded, c.rays.size(), c.scene->triangles.size());
}

}  // namespace rayspace::emu

namespace rayspace::emu {

// The lists are what tl.trace walks: each must be a list the walk can follow (tl::ListsError), and a
// triangle's id one the scene has.
void CheckOutputs(const call::TlLists& c, const TlListArrays* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::size_t e = c.tree.Elements(), total = c.directions.size() * e;
  k.Size("escapes", r->escapes.size(), total);
  k.Size("words", r->words.size(), total);
  k.Size("lengths", r->lengths.size(), c.directions.size());
  k.Below("lengths", r->lengths, e + 1);
  // Without culling every list holds every element.
  if (c.cull == 0)
    for (std::size_t j = 0; j < r->lengths.size(); ++j)
      if (r->lengths[j] != e) k.Fail("lengths", j, "is {}, the tree has {} elements", r->lengths[j], e);
  const tl::Packed p = tl::Pack(*r, e, c.kName);
  std::size_t bad = 0;
  const std::string why = tl::ListsError({p.first, p.escapes, p.words, c.tree.tl_vertices}, &bad);
  if (!why.empty()) k.Fail("escapes", bad, "makes no list ({})", why);
  for (std::size_t i = 0; i < p.words.size(); ++i)
    if (tl::IsTriangle(static_cast<tl::Escape>(p.escapes[i])) && p.words[i].w >= c.tree.tl_tri_words.size())
      k.Fail("words", i, "names triangle {}, out of range [0, {})", p.words[i].w, c.tree.tl_tri_words.size());
}

// The windows are what tl.trace walks: each inside its list.
void CheckOutputs(const call::TlHeads& c, const TlWindows* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("windows", r->windows.size(), 2 * c.tri_words.size() * layout::kTlCases * (c.first.size() - 1));
  std::size_t bad = 0;
  const std::string why = WindowsError(c.first, r->windows, c.tri_words.size() * layout::kTlCases, &bad);
  if (!why.empty()) k.Fail("windows", bad, "{}", why);
}

void CheckOutputs(const call::TlCells& c, const TlWindows* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Size("windows", r->windows.size(), 2 * std::size_t{tl::CellCount(c.frame)} * (c.first.size() - 1));
  std::size_t bad = 0;
  const std::string why = WindowsError(c.first, r->windows, tl::CellCount(c.frame), &bad);
  if (!why.empty()) k.Fail("windows", bad, "{}", why);
}

void CheckOutputs(const call::TlTrace& c, const TlWalks* r, const OutputSource& from) {
  const Check k(c.kName, from);
  std::uint64_t prims = 0;  // the ids a hit may name: those of the lists' triangles
  for (std::size_t i = 0; i < c.words.size(); ++i)
    if (tl::IsTriangle(static_cast<tl::Escape>(c.escapes[i]))) prims = std::max<std::uint64_t>(prims, std::uint64_t{c.words[i].w} + 1);
  k.Records(c.shadow ? nullptr : &r->hits, c.shadow ? &r->occluded : nullptr, c.rays.size(), prims);
  k.Size(c.shadow ? "hits" : "occluded", c.shadow ? r->hits.size() : r->occluded.size(), 0);
  k.Size("spheres", r->spheres.size(), c.rays.size());
  k.Size("triangles", r->triangles.size(), c.rays.size());
  const std::uint64_t longest = c.escapes.size() + 1;
  k.Below("spheres", r->spheres, longest);
  k.Below("triangles", r->triangles, longest);
}

// The grids' build: counts, spans and references that let the next pass run in bounds.
void CheckOutputs(const call::GridCount& c, const GridCounts* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::size_t n = c.triangles.size();
  const bool perspective = c.shape.size() == 2 && c.shape[0].x == layout::kGridKindPerspective;
  k.Size("counts", r->counts.size(), n);
  k.Size("dist", r->dist.size(), perspective ? n : 0);
  k.Size("spans", r->spans.size(), n * layout::kGridFaces);
  k.Size("span_boxes", r->span_boxes.size(), perspective ? n * layout::kGridFaces : 0);
  std::uint64_t total = 0;
  for (std::size_t t = 0; t < n; ++t) {
    std::uint64_t size = 0;
    for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
      const grid::bin::Span s = grid::bin::Unpack(r->spans[t * layout::kGridFaces + f]);
      if (s.valid && (s.i0 > s.i1 || s.j0 > s.j1 || s.k0 > s.k1)) k.Fail("spans", t * layout::kGridFaces + f, "is an empty range");
      size += s.Size();
    }
    if (size != r->counts[t]) k.Fail("counts", t, "is {}, its spans hold {}", r->counts[t], size);
    if ((total += size) >= (std::uint64_t{1} << 31)) k.Fail("counts", t, "brings the references to {}", total);
  }
}

void CheckOutputs(const call::GridEmit& c, const GridRefs* r, const OutputSource& from) {
  const Check k(c.kName, from);
  std::uint64_t total = 0;
  for (const std::uint32_t n : c.counts) total += n;
  k.Size("offsets", r->offsets.size(), c.counts.size());
  k.Size("cells", r->cells.size(), total);
  k.Size("triangles", r->triangles.size(), total);
  const layout::GridBuildGrid g = grid::FromDescriptor(c.grid, c.shape);
  k.Size("boxes", r->boxes.size(), g.shape.x == layout::kGridKindPerspective ? total : 0);
  k.Below("cells", r->cells, grid::bin::CellCount(g));
  k.Below("triangles", r->triangles, c.counts.size());
}

void CheckOutputs(const call::GridCells& c, const GridLists* r, const OutputSource& from) {
  const Check k(c.kName, from);
  const std::size_t refs = c.cells.size();
  k.Size("first", r->first.size(), std::size_t{c.cell_count} + 1);
  k.Size("triangles", r->triangles.size(), refs);
  k.Size("boxes", r->boxes.size(), c.boxes.empty() ? 0 : refs);
  k.Size("min_dist", r->min_dist.size(), c.dist.empty() ? 0 : c.cell_count);
  for (std::size_t i = 0; i < r->first.size(); ++i)
    if (r->first[i] > refs || (i > 0 && r->first[i] < r->first[i - 1]) || (i + 1 == r->first.size() && r->first[i] != refs))
      k.Fail("first", i, "is {}: the offsets do not rise from 0 to the {} references", r->first[i], refs);
  std::uint64_t bound = 0;
  for (const std::uint32_t t : c.triangles) bound = std::max<std::uint64_t>(bound, std::uint64_t{t} + 1);
  k.Below("triangles", r->triangles, bound);
}

void CheckOutputs(const call::GridTrace& c, const GridWalks* r, const OutputSource& from) {
  const Check k(c.kName, from);
  k.Records(c.shadow ? nullptr : &r->hits, c.shadow ? &r->occluded : nullptr, c.rays.size(), c.triangles.size());
  k.Size(c.shadow ? "hits" : "occluded", c.shadow ? r->hits.size() : r->occluded.size(), 0);
  k.Size("steps", r->steps.size(), c.rays.size());
  k.Size("tests", r->tests.size(), c.rays.size());
  const glm::uvec4 d = c.volume_dims.empty() ? glm::uvec4(0) : c.volume_dims[0];
  std::uint64_t most_steps = std::uint64_t{d.x} + d.y + d.z + 1;  // the regular grid's walk
  for (const glm::uvec4& g : c.light_grids)  // a 3D grid's: the core, then each face's
    if (g.x != layout::kGridNoLight && g.z != 0) most_steps = std::max(most_steps, std::uint64_t{d.x} + d.y + d.z + layout::kGridFaces * (2 * std::uint64_t{g.y} + g.z));
  k.Below("steps", r->steps, most_steps);
  k.Below("tests", r->tests, std::uint64_t{c.cell_triangles.size()} + 1);
}

}  // namespace rayspace::emu
