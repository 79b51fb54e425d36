// One struct per pass call: the call's inputs as data. The hierarchy tracer and the frame runner build
// a call once and hand it to a backend (emu/backend.h), which executes it; the diff and `replay` move
// the same struct to and from named buffers (its RS_FIELDS) without restating its signature.
//
// Field kinds and what they mean to the buffer sets (verify/call_codec.h):
//   In<T>                 an input array (a view the caller keeps alive for the call)
//   std::vector<T>*       an array read and updated in place (results merged into it); may be null
//   const SceneBuffers*   the scene's buffers
//   a struct with fields  flattened into the call (its fields named as its own)
//   integer, enum, float  a scalar (a float is saved as its bit pattern)
// `Result` is what the call returns: void, an array saved under `kResult`, or a struct with fields.
#pragma once
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/fields.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/streams.h"
#include "rayspace/emu/tl/streams.h"
#include "rayspace/emu/tree_streams.h"
#include "rayspace/layout.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

template <typename T>
using In = std::span<const T>;

namespace call {

// ---- frame passes ---------------------------------------------------------------------------------
struct Raster {
  static constexpr std::string_view kName = "raster";
  using Result = GBuffer;
  layout::FrameConstants frame{};
  const SceneBuffers* scene = nullptr;
  RS_FIELDS(frame, scene)
};

// Shading points from the G-buffer's covered pixels.
struct SurfacesFromGBuffer {
  static constexpr std::string_view kName = "surfaces";
  using Result = std::vector<layout::Surface>;
  static constexpr std::string_view kResult = "surfaces";
  layout::FrameConstants frame{};
  int width = 0, height = 0;
  In<glm::vec4> position{}, normal{};
  In<std::uint32_t> prim{};
  const SceneBuffers* scene = nullptr;
  RS_FIELDS(frame, width, height, position, normal, prim, scene)
};

// One surface per ray; rays that missed give empty slots.
struct SurfacesFromHits {
  static constexpr std::string_view kName = "surfaces.hits";
  using Result = std::vector<layout::Surface>;
  static constexpr std::string_view kResult = "surfaces";
  In<layout::Ray> rays{};
  In<std::uint64_t> hits{};
  const SceneBuffers* scene = nullptr;
  RS_FIELDS(rays, hits, scene)
};

// Shadow: slot s * lights + l, a ray from light l towards surface s (thesis eqs. 3.1-3.2).
// Reflection: slot s, the mirror ray (eqs. 3.3-3.4) where the material reflects.
// Refraction: slot s, the refracted ray (eqs. 3.5-3.7) where transparent; none on total internal reflection.
struct Raygen {
  static constexpr std::string_view kName = "raygen";
  using Result = SparseRays;
  std::uint32_t kind = layout::kRayShadow;
  layout::FrameConstants frame{};
  In<layout::Surface> surfaces{};
  const SceneBuffers* scene = nullptr;
  std::uint32_t shadow_rule = layout::kShadowRuleAll;  // shadow rays: layout::kShadowRule*
  RS_FIELDS(kind, frame, surfaces, scene, shadow_rule)
};

// Order-preserving compaction (exclusive scan of flags + scatter); one kernel for every kind.
struct Trim {
  static constexpr std::string_view kName = "trim";
  using Result = Trimmed;
  std::uint32_t kind = layout::kRayShadow;
  In<layout::Ray> rays{};
  In<std::uint32_t> flags{};
  RS_FIELDS(kind, rays, flags)
};

// Phong/Lambert with attenuation (eq. 3.19) added into the fixed-point accumulator `accum`.
// `shadow_offsets` / `shadow_flags` map slot s * lights + l to its shadow ray; `occluded` is per ray.
struct Shade {
  static constexpr std::string_view kName = "shade";
  using Result = void;
  layout::FrameConstants frame{};
  In<layout::Surface> surfaces{};
  In<std::uint32_t> shadow_flags{}, shadow_offsets{}, occluded{};
  std::vector<std::uint64_t>* accum = nullptr;
  const SceneBuffers* scene = nullptr;
  RS_FIELDS(frame, surfaces, shadow_flags, shadow_offsets, occluded, accum, scene)
};

// Fixed point -> 8-bit RGB with display gamma 2 (sqrt), channel by channel (element-wise).
struct Resolve {
  static constexpr std::string_view kName = "resolve";
  using Result = std::vector<std::uint8_t>;
  static constexpr std::string_view kResult = "rgb";
  In<std::uint64_t> accum{};
  RS_FIELDS(accum)
};

// ---- hierarchy passes -----------------------------------------------------------------------------
// 32-bit sort key per ray (docs/hierarchy.md, "Hash keys"); quadtree_width > 0: Roger's quadtree keys
// (light, Morton order of the pixel) instead.
struct Hash {
  static constexpr std::string_view kName = "hash";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "keys";
  In<layout::Ray> rays{};
  const SceneBuffers* scene = nullptr;
  HashConfig hash{};
  std::uint32_t quadtree_width = 0;
  int quadtree_depth = 0;
  RS_FIELDS(rays, scene, hash, quadtree_width, quadtree_depth)
};

struct Compress {
  static constexpr std::string_view kName = "compress";
  using Result = Chunks;
  In<std::uint32_t> keys{};
  RS_FIELDS(keys)
};

// Stable LSD radix sort of chunk keys (8 bits per pass); the chunk indices in sorted order.
struct SortChunks {
  static constexpr std::string_view kName = "sort";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "chunk_order";
  In<std::uint32_t> chunk_key{};
  RS_FIELDS(chunk_key)
};

// Sorted ray order: the rays of each chunk, chunks in sorted order.
struct Decompress {
  static constexpr std::string_view kName = "decompress";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "ray_order";
  In<std::uint32_t> chunk_key{}, chunk_base{}, chunk_size{}, chunk_order{};
  RS_FIELDS(chunk_key, chunk_base, chunk_size, chunk_order)
};

// Hierarchy build (docs/hierarchy.md). `first` is a CSR offset array: node i covers items
// [first[i], first[i+1]) (sorted rays through `order` for leaves, nodes of the level below for parents).
struct BuildLeaves {
  static constexpr std::string_view kName = "build.leaves";
  using Result = std::vector<layout::ConeNode>;
  static constexpr std::string_view kResult = "nodes";
  In<layout::Ray> rays{};
  In<std::uint32_t> order{}, first{};
  RS_FIELDS(rays, order, first)
};

struct BuildParents {
  static constexpr std::string_view kName = "build.parents";
  using Result = std::vector<layout::ConeNode>;
  static constexpr std::string_view kResult = "nodes";
  In<layout::ConeNode> below{};
  In<std::uint32_t> first{};
  std::uint32_t child_merge = layout::kChildMergeSequential;  // cone::ParentNode's merge
  RS_FIELDS(below, first, child_merge)
};

// CRSH's object culling: 1 where top node e / objects may meet object sphere e % objects.
struct ObjectMask {
  static constexpr std::string_view kName = "traverse.objects";
  using Result = std::vector<std::uint8_t>;
  static constexpr std::string_view kResult = "mask";
  In<layout::ConeNode> top{};
  In<glm::vec4> object_spheres{};
  float eps = 0.0f;
  std::uint32_t cone_test = layout::kConeTestConservative;  // the cone-sphere test: layout::kConeTest*
  RS_FIELDS(top, object_spheres, eps, cone_test)
};

// Top level of one block: top nodes [t0, t1) x triangles [b0, b1). `object_mask` (top nodes x
// objects, CRSH) empty = no object culling; `eps` is the cone-sphere test's absolute margin.
struct TraverseTop {
  static constexpr std::string_view kName = "traverse.top";
  using Result = PairSlots;
  In<layout::ConeNode> top{};
  std::uint32_t t0 = 0, t1 = 0, b0 = 0, b1 = 0;
  In<glm::vec4> tri_spheres{};
  const SceneBuffers* scene = nullptr;
  In<std::uint8_t> object_mask{};
  float eps = 0.0f;
  std::uint32_t cone_test = layout::kConeTestConservative;  // the cone-sphere test: layout::kConeTest*
  RS_FIELDS(top, t0, t1, b0, b1, tri_spheres, scene, object_mask, eps, cone_test)
};

// One level down: the node of each pair (base_up + id) tests its children [first[.], first[. + 1])
// among `nodes`; slots are pairs x children_max; new ids are relative to `base`.
struct TraverseLevel {
  static constexpr std::string_view kName = "traverse.level";
  using Result = PairSlots;
  In<std::uint32_t> pairs{};
  In<layout::ConeNode> nodes{};
  In<std::uint32_t> first{};
  std::uint32_t base_up = 0, base = 0, children_max = 0, b0 = 0;
  In<glm::vec4> tri_spheres{};
  float eps = 0.0f;
  std::uint32_t cone_test = layout::kConeTestConservative;  // the cone-sphere test: layout::kConeTest*
  RS_FIELDS(pairs, nodes, first, base_up, base, children_max, b0, tri_spheres, eps, cone_test)
};

// traverse.compact: the same inputs as TraverseTop / TraverseLevel, tested and compacted in one pass.
// The result is what the slots followed by a reduction give: the survivors' values in slot order and
// the number of tests run. Each call has its own name, so saved calls replay as the call they were.
struct TraverseTopCompacted : TraverseTop {
  static constexpr std::string_view kName = "traverse.compact.top";
  using Result = Compacted;
};

struct TraverseLevelCompacted : TraverseLevel {
  static constexpr std::string_view kName = "traverse.compact.level";
  using Result = Compacted;
};

// Stream reduction of (flag, value) slots to the flagged values in slot order: Roger et al.'s
// hierarchical reduction with components of `component` slots, or a scan.
struct Reduce {
  static constexpr std::string_view kName = "reduce";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "pairs";
  Reduction reduction = Reduction::kHierarchical;
  int component = 64;
  In<std::uint8_t> flags{};
  In<std::uint32_t> values{};
  RS_FIELDS(reduction, component, flags, values)
};

// Final tests of surviving level-1 pairs: every ray of the node (first1 over `order`) against the
// triangle; closest hits by atomic minimum into `hits`, or shadow rays by atomic store into
// `occluded` (exactly one of them is set, sized to the rays). Returns the tests per pair.
struct Intersect {
  static constexpr std::string_view kName = "intersect";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "tests";
  In<std::uint32_t> pairs{}, first1{};
  std::uint32_t base1 = 0, b0 = 0;
  In<std::uint32_t> order{};
  In<layout::Ray> rays{};
  const SceneBuffers* scene = nullptr;
  std::vector<std::uint64_t>* hits = nullptr;
  std::vector<std::uint32_t>* occluded = nullptr;
  // kLeafTestRaySphere: each ray meets the triangle's sphere (cone::RayMayMeetSphere with the margin
  // eps) before its ray-triangle test, and a pair's tests count only the rays that did.
  std::uint32_t leaf_test = layout::kLeafTestNode;
  In<glm::vec4> tri_spheres{};
  float eps = 0.0f;
  RS_FIELDS(pairs, first1, base1, b0, order, rays, scene, hits, occluded, leaf_test, tri_spheres, eps)
};

// ---- --objects tree: the joint descent of both hierarchies (emu/object_tree_traverse.h) -------------
// Cone nodes [t0, t1) of `level` against every object's root sphere: per slot (node, root), in that
// order, its flag (1 goes on, 2 final, 0 missed), its pair and the counts.
struct TreeRoots {
  static constexpr std::string_view kName = "tree.roots";
  using Result = TreeSlots;
  ConeTreeView cones;
  ObjectTreeView tree;
  std::uint32_t level = 0, t0 = 0, t1 = 0;
  float eps = 0.0f;
  RS_FIELDS(cones, tree, level, t0, t1, eps)
};

// Per pair (pair_cone, pair_item): the number of its candidates, the children of the side refined.
struct TreeExpand {
  static constexpr std::string_view kName = "tree.expand";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "counts";
  ConeTreeView cones;
  ObjectTreeView tree;
  In<std::uint32_t> pair_cone{}, pair_item{};
  RS_FIELDS(cones, tree, pair_cone, pair_item)
};

// Every candidate of every pair tested: pair p's candidates in slots offsets[p] .. (the exclusive
// scan of tree.expand's counts; `slots` their total).
struct TreeTest {
  static constexpr std::string_view kName = "tree.test";
  using Result = TreeSlots;
  ConeTreeView cones;
  ObjectTreeView tree;
  In<std::uint32_t> pair_cone{}, pair_item{}, offsets{};
  std::uint32_t slots = 0;
  float eps = 0.0f;
  RS_FIELDS(cones, tree, pair_cone, pair_item, offsets, slots, eps)
};

// One round fused: the survivors of tree.test's slots in slot order, split into the pairs that go on
// and the final ones.
struct TreeStep {
  static constexpr std::string_view kName = "tree.step";
  using Result = TreeRound;
  ConeTreeView cones;
  ObjectTreeView tree;
  In<std::uint32_t> pair_cone{}, pair_item{};
  float eps = 0.0f;
  RS_FIELDS(cones, tree, pair_cone, pair_item, eps)
};

// The final tests: each final pair's rays (a level-1 node's through first1 and `order`, or the one
// ray at level 0) against its triangle (tree_triangles[item]); merged into `hits` or `occluded` as
// Intersect does. Returns the tests per pair.
struct IntersectTree {
  static constexpr std::string_view kName = "intersect.tree";
  using Result = std::vector<std::uint32_t>;
  static constexpr std::string_view kResult = "tests";
  In<std::uint32_t> pair_cone{}, pair_item{}, first1{}, tree_triangles{}, order{};
  In<layout::Ray> rays{};
  const SceneBuffers* scene = nullptr;
  std::vector<std::uint64_t>* hits = nullptr;
  std::vector<std::uint32_t>* occluded = nullptr;
  RS_FIELDS(pair_cone, pair_item, first1, tree_triangles, order, rays, scene, hits, occluded)
};

// ---- --algo tl: Toczek et al.'s traversal lists (docs/traversal-lists.md) ---------------------------
// The tree ordered and flattened into one list per direction (`directions`, xyz): a node's children
// (own triangles, then child nodes) sorted by their projection's low end (kTlOrderEarliestFirst) or
// high end (kTlOrderLatestLast), ties in that order; escapes relative, the paper's 0 and -1 at the end.
struct TlLists {
  static constexpr std::string_view kName = "tl.lists";
  using Result = TlListArrays;
  TlTreeView tree;
  In<glm::vec4> directions{};
  std::uint32_t order = layout::kTlOrderEarliestFirst;
  std::uint32_t cull = 0;  // 1: back-face culling (rayspace/contract.h, kTlCullMargin)
  RS_FIELDS(tree, directions, order, cull)
};

// Per (scene triangle, case, list) the window of the packed lists a ray on that triangle walks
// (rayspace/contract.h, kTlHeads*): every triangle element outside it lies beyond one of the case's
// planes by more than `margin`.
struct TlHeads {
  static constexpr std::string_view kName = "tl.heads";
  using Result = TlWindows;
  In<std::uint32_t> first{}, escapes{};
  In<glm::uvec4> words{};
  In<glm::vec4> vertices{};
  In<glm::uvec4> tri_words{};
  std::uint32_t mode = layout::kTlHeadsRegular;
  float margin = 0.0f;
  RS_FIELDS(first, escapes, words, vertices, tri_words, mode, margin)
};

// Per (screen cell, list) the window of the packed lists the cell's eye rays walk (rayspace/contract.h,
// kTlCells*): every triangle element outside it lies wholly outside one of the cell's four side planes
// by more than `margin`. The cells are those of `frame`'s image, kTlCellPixels on a side.
struct TlCells {
  static constexpr std::string_view kName = "tl.cells";
  using Result = TlWindows;
  In<std::uint32_t> first{}, escapes{};
  In<glm::uvec4> words{};
  In<glm::vec4> vertices{};
  layout::FrameConstants frame{};
  float margin = 0.0f;
  RS_FIELDS(first, escapes, words, vertices, frame, margin)
};

// Every ray walks the list of its direction class (tl::ListFor over `first`'s K lists) without a
// stack: the closest hit (shadow = 0) or whether any triangle but the ray's own is hit (shadow = 1).
struct TlTrace {
  static constexpr std::string_view kName = "tl.trace";
  using Result = TlWalks;
  In<std::uint32_t> first{}, escapes{};
  In<glm::uvec4> words{};
  In<glm::vec4> vertices{};
  In<layout::Ray> rays{};
  std::uint32_t shadow = 0;
  std::uint32_t cull = 0;  // 1: one-sided triangles, met only from the front
  // heads kTlHeadsSimple or kTlHeadsRegular: a ray whose info.y names a triangle walks that
  // triangle's window (tl.heads): a closest-hit ray starts on it, a shadow ray ends on it.
  // kTlHeadsCells: an eye ray walks the window of the screen cell its info.w names (tl.cells).
  std::uint32_t heads = layout::kTlHeadsOff;
  In<glm::uvec4> tri_words{};
  In<std::uint32_t> windows{};  // tl.heads' windows per (triangle, case, list), or tl.cells' per (cell, list)
  RS_FIELDS(first, escapes, words, vertices, rays, shadow, cull, heads, tri_words, windows)
};

// Rays through the grids of `--algo grid` (rayspace/contract.h, kGridTrace*; docs/grids.md): a point
// light's shadow ray tests its one perspective cell unless it ends before the cell's least distance;
// an area light's walks its 3D perspective grid; every other ray steps through the regular grid. Closest hit (shadow = 0) or any hit (shadow = 1).
struct GridTrace {
  static constexpr std::string_view kName = "grid.trace";
  using Result = GridWalks;
  In<std::uint32_t> first{}, cell_triangles{};
  In<float> min_dist{};
  In<glm::vec4> boxes{};  // per perspective reference: the (u, v) rectangle a ray must fall in to test it
  In<glm::uvec4> light_grids{};
  In<glm::vec4> origins{};
  In<glm::vec4> volume{};        // lo, cell, inv_cell, hi
  In<glm::uvec4> volume_dims{};  // one entry: cells along x, y, z, the first cell
  In<float> slices{};            // per 3D grid, per face: D + 1 depth boundaries (r = 1 / depth)
  In<layout::Triangle> triangles{};
  In<layout::Ray> rays{};
  std::uint32_t shadow = 0;
  std::uint32_t closed = 0;                   // --closed-models (grid::Options::closed)
  std::uint32_t eye = layout::kGridNoLight;   // --primary grid: the eye's entry of light_grids/origins
  std::uint32_t secondary = layout::kGridNoLight;  // --grid-secondary perspective: the eye's 3D grid's entry
  RS_FIELDS(first, cell_triangles, min_dist, boxes, light_grids, origins, volume, volume_dims, slices, triangles, rays, shadow, closed, eye,
            secondary)
};

// The grids' build, one grid a call (rayspace/contract.h, kGridBuild*; docs/grids.md). `grid` and
// `shape` are the grid's layout::GridBuildGrid (grid::Describe): centre, cell, light_lo, light_hi;
// shape, flags. grid.count: per triangle its references, spans and a 2D grid's least distance.
struct GridCount {
  static constexpr std::string_view kName = "grid.count";
  using Result = GridCounts;
  In<layout::Triangle> triangles{};
  In<glm::vec4> grid{};
  In<glm::uvec4> shape{};
  In<float> slices{};
  RS_FIELDS(triangles, grid, shape, slices)
};

// grid.emit: the counts' exclusive scan, and every reference expanded from its triangle's spans.
struct GridEmit {
  static constexpr std::string_view kName = "grid.emit";
  using Result = GridRefs;
  In<glm::vec4> grid{};
  In<glm::uvec4> shape{};
  In<std::uint32_t> counts{};
  In<glm::uvec4> spans{};
  In<glm::vec4> span_boxes{};
  RS_FIELDS(grid, shape, counts, spans, span_boxes)
};

// grid.cells: the references gathered in `order` (the sort's stable order by cell) into per-cell
// lists, each cell's CSR offset, and in a 2D grid (`dist` per triangle non-empty) its least distance.
struct GridCells {
  static constexpr std::string_view kName = "grid.cells";
  using Result = GridLists;
  In<std::uint32_t> cells{}, triangles{};
  In<glm::vec4> boxes{};
  In<std::uint32_t> order{};
  In<float> dist{};
  std::uint32_t cell_count = 0;
  RS_FIELDS(cells, triangles, boxes, order, dist, cell_count)
};

}  // namespace call

// The calls of each backend group, for code generated per call (X-macros): X(Call).
#define RS_FRAME_CALLS(X) X(Raster) X(SurfacesFromGBuffer) X(SurfacesFromHits) X(Raygen) X(Trim) X(Shade) X(Resolve)
#define RS_HIERARCHY_CALLS(X)                                                                        \
  X(Hash) X(Compress) X(SortChunks) X(Decompress) X(BuildLeaves) X(BuildParents) X(ObjectMask) X(TraverseTop) \
  X(TraverseLevel) X(Reduce) X(TraverseTopCompacted) X(TraverseLevelCompacted) X(Intersect) X(TreeRoots) \
  X(TreeExpand) X(TreeTest) X(TreeStep) X(IntersectTree) X(TlLists) X(TlHeads) X(TlCells) X(TlTrace) X(GridCount) X(GridEmit) \
  X(GridCells) X(GridTrace)

// Calls whose kernel runs one invocation per element over input arrays of one length, with no other
// input (rayspace/contract.h, "element-wise passes"): the Vulkan backend launches them generically.
#define RS_ELEMENTWISE_CALLS(X) X(Resolve)

// Throws InputError when a call's inputs break its contract (an index out of range, lengths that
// disagree): what the diff and `replay` check before running a saved or hand-made call, so that no
// backend reads out of bounds.
#define RS_DECLARE_CHECK(C) void CheckInputs(const call::C& c);
RS_FRAME_CALLS(RS_DECLARE_CHECK)
RS_HIERARCHY_CALLS(RS_DECLARE_CHECK)
#undef RS_DECLARE_CHECK

}  // namespace rayspace::emu
