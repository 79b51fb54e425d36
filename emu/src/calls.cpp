// The contract of each call's inputs, checked before a saved or hand-made call runs (diff, replay):
// a call that passes runs on every backend without reading out of bounds.
#include "rayspace/emu/calls.h"

#include <cmath>

#include "rayspace/contract.h"
#include "rayspace/emu/raster_detail.h"
#include "rayspace/error.h"

namespace rayspace::emu {
namespace {

// Frames larger than this are refused (the raster and the accumulators are sized by them).
constexpr std::uint32_t kMaxFrameSide = 1u << 14;

void CheckScene(std::string_view call, const SceneBuffers* scene) {
  if (!scene) ThrowInput("{}: the call has no scene", call);
}

void CheckFrame(std::string_view call, const layout::FrameConstants& fc) {
  if (fc.dims.x == 0 || fc.dims.y == 0 || fc.dims.x > kMaxFrameSide || fc.dims.y > kMaxFrameSide)
    ThrowInput("{}: frame size {}x{} is out of range [1, {}]", call, fc.dims.x, fc.dims.y, kMaxFrameSide);
}

template <typename T>
void CheckIndices(std::string_view call, const char* what, In<T> v, std::size_t bound) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] >= bound) ThrowInput("{}: input '{}' element {} is {}, out of range [0, {})", call, what, i, v[i], bound);
}

// A CSR offset array over `items`: from 0 to items, never decreasing.
void CheckFirst(std::string_view call, const char* what, In<std::uint32_t> first, std::size_t items) {
  if (first.empty() || first.front() != 0 || first.back() != items)
    ThrowInput("{}: input '{}' must run from 0 to {}", call, what, items);
  for (std::size_t i = 1; i < first.size(); ++i)
    if (first[i] < first[i - 1]) ThrowInput("{}: input '{}' decreases at {}", call, what, i);
}

void CheckSameLength(std::string_view call, const char* a, std::size_t na, const char* b, std::size_t nb) {
  if (na != nb) ThrowInput("{}: inputs '{}' ({}) and '{}' ({}) differ in length", call, a, na, b, nb);
}

void CheckKind(std::string_view call, std::uint32_t kind) {
  if (kind > layout::kRayRefraction) ThrowInput("{}: scalar 'kind' = {} is not a ray kind", call, kind);
}

void CheckSurfaces(std::string_view call, In<layout::Surface> surfaces, const layout::FrameConstants& fc,
                   const SceneBuffers& scene) {
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const layout::Surface& s = surfaces[i];
    if (s.info.y >= fc.dims.x * fc.dims.y || (s.info.x != layout::kNoPrim && (s.info.x >= scene.triangles.size() ||
                                                                           s.info.z >= scene.materials.size())))
      ThrowInput("{}: input 'surfaces' element {} names a pixel, triangle or material out of range", call, i);
  }
}

}  // namespace

void CheckInputs(const call::Raster& c) {
  CheckFrame(c.kName, c.frame);
  CheckScene(c.kName, c.scene);
  // Clip coordinates within 2^120 keep the clipper's plane distances, their differences and
  // products finite, so it never meets a NaN and a triangle never clips to more than 9 vertices.
  constexpr float kClipLimit = 0x1p120f;
  for (std::size_t t = 0; t < c.scene->triangles.size(); ++t) {
    const layout::Triangle& tri = c.scene->triangles[t];
    for (const glm::vec4& v : {tri.v0, tri.v1, tri.v2}) {
      const glm::vec4 clip = raster::VertexStage(c.frame.view_proj, glm::vec3(v));
      for (int k = 0; k < 4; ++k)
        if (!(std::fabs(clip[k]) <= kClipLimit))
          ThrowInput("{}: triangle {} has clip coordinate {} beyond 2^120 (the view-projection or the vertex is out of range)",
                     c.kName, t, clip[k]);
    }
  }
}

void CheckInputs(const call::SurfacesFromGBuffer& c) {
  CheckFrame(c.kName, c.frame);
  CheckScene(c.kName, c.scene);
  if (c.width < 0 || c.height < 0 || static_cast<std::uint32_t>(c.width) != c.frame.dims.x ||
      static_cast<std::uint32_t>(c.height) != c.frame.dims.y)
    ThrowInput("{}: G-buffer size {}x{} is not the frame's {}x{}", c.kName, c.width, c.height, c.frame.dims.x, c.frame.dims.y);
  const std::size_t n = static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
  if (c.position.size() != n || c.normal.size() != n || c.prim.size() != n)
    ThrowInput("{}: G-buffer inputs hold {}/{}/{} pixels, expected {}", c.kName, c.position.size(), c.normal.size(),
               c.prim.size(), n);
  for (std::size_t i = 0; i < n; ++i)
    if (c.prim[i] != layout::kNoPrim && c.prim[i] >= c.scene->triangles.size())
      ThrowInput("{}: input 'prim' element {} names triangle {}", c.kName, i, c.prim[i]);
}

void CheckInputs(const call::SurfacesFromHits& c) {
  CheckScene(c.kName, c.scene);
  CheckSameLength(c.kName, "rays", c.rays.size(), "hits", c.hits.size());
  for (std::size_t i = 0; i < c.hits.size(); ++i)
    if (c.hits[i] != ~std::uint64_t{0} && static_cast<std::uint32_t>(c.hits[i]) >= c.scene->triangles.size())
      ThrowInput("{}: input 'hits' element {} names triangle {}", c.kName, i, static_cast<std::uint32_t>(c.hits[i]));
}

void CheckInputs(const call::Raygen& c) {
  CheckKind(c.kName, c.kind);
  CheckFrame(c.kName, c.frame);
  CheckScene(c.kName, c.scene);
  CheckSurfaces(c.kName, c.surfaces, c.frame, *c.scene);
  if (c.shadow_rule != layout::kShadowRuleAll && c.shadow_rule != layout::kShadowRuleLit)
    ThrowInput("{}: shadow_rule {} is neither all (0) nor lit (1)", c.kName, c.shadow_rule);
}

void CheckInputs(const call::Trim& c) {
  CheckKind(c.kName, c.kind);
  CheckSameLength(c.kName, "rays", c.rays.size(), "flags", c.flags.size());
  for (std::size_t i = 0; i < c.flags.size(); ++i)  // head flags: the scan counts them into offsets
    if (c.flags[i] > 1) ThrowInput("{}: input 'flags' element {} is {}, not a head flag (0 or 1)", c.kName, i, c.flags[i]);
}

void CheckInputs(const call::Shade& c) {
  CheckFrame(c.kName, c.frame);
  CheckScene(c.kName, c.scene);
  if (!c.accum || c.accum->size() != static_cast<std::size_t>(c.frame.dims.x) * c.frame.dims.y * 3)
    ThrowInput("{}: input 'accum' does not hold 3 words per pixel of the frame", c.kName);
  const std::size_t slots = ShadowSlots(c.scene->lights);
  if (slots) {
    if (c.shadow_flags.size() != c.surfaces.size() * slots || c.shadow_offsets.size() != c.shadow_flags.size())
      ThrowInput("{}: inputs 'shadow_flags'/'shadow_offsets' do not hold surfaces x light samples slots", c.kName);
    for (std::size_t i = 0; i < c.shadow_flags.size(); ++i)
      if (c.shadow_flags[i] && c.shadow_offsets[i] >= c.occluded.size())
        ThrowInput("{}: input 'shadow_offsets' element {} is out of range", c.kName, i);
  }
  CheckSurfaces(c.kName, c.surfaces, c.frame, *c.scene);
}

void CheckInputs(const call::Resolve& c) {
  if (c.accum.size() % 3 != 0) ThrowInput("{}: input 'accum' holds {} words, not 3 per pixel", c.kName, c.accum.size());
}

void CheckInputs(const call::Hash& c) {
  CheckScene(c.kName, c.scene);
  const HashConfig& h = c.hash;
  for (int bits : {h.light_bits, h.polar_bits, h.azimuth_bits, h.origin_bits, h.direction_bits})
    if (bits < 0 || bits > 31) ThrowInput("{}: hash bit counts must be in [0, 31]", c.kName);
  if (h.order != layout::kHashOrderInterleaved && h.order != layout::kHashOrderPolarFirst)
    ThrowInput("{}: hash order {} is neither interleaved (0) nor polar-first (1)", c.kName, h.order);
  if (h.light_bits + h.polar_bits + h.azimuth_bits > layout::kHashKeyBits ||
      3 * h.origin_bits + 2 * h.direction_bits > layout::kHashKeyBits)
    ThrowInput("{}: hash keys need more than 32 bits (light {} + polar {} + azimuth {}; 3 x origin {} + 2 x direction {})",
               c.kName, h.light_bits, h.polar_bits, h.azimuth_bits, h.origin_bits, h.direction_bits);
  if (c.quadtree_depth < 0 || c.quadtree_depth > 15)
    ThrowInput("{}: scalar 'quadtree_depth' = {} is out of range [0, 15]", c.kName, c.quadtree_depth);
}

void CheckInputs(const call::Compress&) {}  // any keys
void CheckInputs(const call::SortChunks&) {}  // any keys

void CheckInputs(const call::Decompress& c) {
  CheckSameLength(c.kName, "chunk_key", c.chunk_key.size(), "chunk_base", c.chunk_base.size());
  CheckSameLength(c.kName, "chunk_key", c.chunk_key.size(), "chunk_size", c.chunk_size.size());
  CheckSameLength(c.kName, "chunk_key", c.chunk_key.size(), "chunk_order", c.chunk_order.size());
  CheckIndices(c.kName, "chunk_order", c.chunk_order, c.chunk_key.size());
  std::uint64_t total = 0;
  for (std::uint32_t s : c.chunk_size) total += s;
  if (total > 0xFFFFFFFFu) ThrowInput("{}: the chunks hold {} rays, more than 32-bit indices address", c.kName, total);
}

void CheckInputs(const call::BuildLeaves& c) {
  CheckIndices(c.kName, "order", c.order, c.rays.size());
  CheckFirst(c.kName, "first", c.first, c.order.size());
}

void CheckInputs(const call::BuildParents& c) {
  CheckFirst(c.kName, "first", c.first, c.below.size());
  if (c.child_merge != layout::kChildMergeSequential && c.child_merge != layout::kChildMergePairwise)
    ThrowInput("{}: scalar 'child_merge' = {} is neither 0 (sequential) nor 1 (pairwise)", c.kName, c.child_merge);
}

namespace {
void CheckConeTest(std::string_view call, std::uint32_t cone_test) {
  if (cone_test != layout::kConeTestConservative && cone_test != layout::kConeTestPrinted && cone_test != layout::kConeTestPrintedSigned)
    ThrowInput("{}: cone_test {} is neither conservative (0), printed (1) nor printed-signed (2)", call, cone_test);
}
}  // namespace

void CheckInputs(const call::ObjectMask& c) { CheckConeTest(c.kName, c.cone_test); }  // any nodes and spheres

namespace {
// traverse.top and traverse.compact.top read the same inputs, as do the two level calls; errors name
// the call (C::kName).
template <typename C>
void CheckTopCall(const C& c) {
  CheckScene(c.kName, c.scene);
  CheckConeTest(c.kName, c.cone_test);
  const SceneBuffers& s = *c.scene;
  if (c.t0 > c.t1 || c.t1 > c.top.size()) ThrowInput("{}: top nodes [{}, {}) out of [0, {})", c.kName, c.t0, c.t1, c.top.size());
  if (c.b0 > c.b1 || c.b1 > s.triangles.size() || c.b1 - c.b0 > (1u << layout::kPairTriangleBits))
    ThrowInput("{}: triangles [{}, {}) out of [0, {}) or wider than a packed pair holds", c.kName, c.b0, c.b1, s.triangles.size());
  if (c.t1 - c.t0 > (1u << (32 - layout::kPairTriangleBits)))
    ThrowInput("{}: {} top nodes are more than a packed pair holds", c.kName, c.t1 - c.t0);
  CheckSameLength(c.kName, "tri_spheres", c.tri_spheres.size(), "scene.triangles", s.triangles.size());
  if (!c.object_mask.empty() && c.object_mask.size() != c.top.size() * s.objects.size())
    ThrowInput("{}: input 'object_mask' holds {} entries, not top nodes x objects = {}", c.kName, c.object_mask.size(),
               c.top.size() * s.objects.size());
  if (!c.object_mask.empty())
    for (std::uint32_t t = c.b0; t < c.b1; ++t)
      if (s.info[t].ids.y >= s.objects.size()) ThrowInput("{}: triangle {} names object {}", c.kName, t, s.info[t].ids.y);
}

template <typename C>
void CheckLevelCall(const C& c) {
  CheckFirst(c.kName, "first", c.first, c.nodes.size());
  CheckConeTest(c.kName, c.cone_test);
  if (c.children_max > 255) ThrowInput("{}: scalar 'children_max' = {} exceeds 255", c.kName, c.children_max);
  for (std::size_t i = 0; i < c.pairs.size(); ++i) {
    const std::uint32_t p = c.pairs[i];
    const std::uint64_t parent = std::uint64_t{c.base_up} + (p >> layout::kPairTriangleBits);
    if (parent + 1 >= c.first.size() || std::uint64_t{c.b0} + (p & layout::kPairTriangleMask) >= c.tri_spheres.size() ||
        c.first[parent + 1] - c.first[parent] > c.children_max || c.first[parent] < c.base)
      ThrowInput("{}: input 'pairs' element {} ({}) is out of range", c.kName, i, p);
  }
}
}  // namespace

void CheckInputs(const call::TraverseTop& c) { CheckTopCall(c); }
void CheckInputs(const call::TraverseTopCompacted& c) { CheckTopCall(c); }
void CheckInputs(const call::TraverseLevel& c) { CheckLevelCall(c); }
void CheckInputs(const call::TraverseLevelCompacted& c) { CheckLevelCall(c); }

void CheckInputs(const call::Reduce& c) {
  CheckSameLength(c.kName, "flags", c.flags.size(), "values", c.values.size());
  for (std::size_t i = 0; i < c.flags.size(); ++i)  // survival flags: the scans count them
    if (c.flags[i] > 1) ThrowInput("{}: input 'flags' element {} is {}, not 0 or 1", c.kName, i, c.flags[i]);
  if (c.component < 1) ThrowInput("{}: scalar 'component' = {} must be at least 1", c.kName, c.component);
  if (c.reduction != Reduction::kHierarchical && c.reduction != Reduction::kScan)
    ThrowInput("{}: scalar 'reduction' = {} is neither 0 (hierarchical) nor 1 (scan)", c.kName,
               static_cast<std::uint32_t>(c.reduction));
}

void CheckInputs(const call::Intersect& c) {
  CheckScene(c.kName, c.scene);
  CheckIndices(c.kName, "order", c.order, c.rays.size());
  CheckFirst(c.kName, "first1", c.first1, c.order.size());
  for (std::size_t i = 0; i < c.pairs.size(); ++i) {
    const std::uint32_t p = c.pairs[i];
    if (std::uint64_t{c.base1} + (p >> layout::kPairTriangleBits) + 1 >= c.first1.size() ||
        std::uint64_t{c.b0} + (p & layout::kPairTriangleMask) >= c.scene->triangles.size())
      ThrowInput("{}: input 'pairs' element {} ({}) is out of range", c.kName, i, p);
  }
  if ((c.hits == nullptr) == (c.occluded == nullptr)) ThrowInput("{}: exactly one of 'hits' and 'occluded' is needed", c.kName);
  const std::size_t n = c.hits ? c.hits->size() : c.occluded->size();
  CheckSameLength(c.kName, c.hits ? "hits" : "occluded", n, "rays", c.rays.size());
  if (c.leaf_test != layout::kLeafTestNode && c.leaf_test != layout::kLeafTestRaySphere)
    ThrowInput("{}: scalar 'leaf_test' = {} is neither 0 (node) nor 1 (ray-sphere)", c.kName, c.leaf_test);
  if (c.leaf_test == layout::kLeafTestRaySphere)
    CheckSameLength(c.kName, "tri_spheres", c.tri_spheres.size(), "triangles", c.scene->triangles.size());
}

}  // namespace rayspace::emu
