// The kernel contract: what a compute kernel and the host code that launches it must agree on, beyond
// the buffer elements of layout.h. Binding numbers, push-constant blocks, phase numbers, block sizes,
// the packing of (node, triangle) pairs and the cone margins are declared here once, in the subset of
// C that is both GLSL and C++, and included by the kernels (gpu/shaders/), the Vulkan host code and the
// emulator. A user's replacement kernel (`--kernel PASS=FILE`) is checked against these bindings and
// push-constant sizes (docs/kernels.md).
//
// Conventions: kPassBindX is the binding of buffer X of a pass's kernel; a paged array (paged.glsl)
// takes kBufferPages consecutive bindings from its first; kPassBindings is the number of bindings;
// kPassPhaseX selects a phase of a kernel that runs in several dispatches; PassPush is its
// push-constant block (GLSL: `layout(push_constant) uniform Block { PassPush pc; };`).
#ifndef RAYSPACE_CONTRACT_H
#define RAYSPACE_CONTRACT_H

#include "rayspace/layout.h"  // the buffer elements, and RS_CONST (a constant in both languages)

#ifdef __cplusplus
namespace rayspace::layout {
#endif

// ---- shared by several kernels ----------------------------------------------------------------
// Blocked scans, histograms and scatters walk blocks of this many elements, one workgroup a block:
// lavapipe ends any loop after 65,535 iterations, so no loop may run over a whole stream.
RS_CONST(uint, kScanBlock, 4096u);
// The most invocations a workgroup may have (--local-size 1..kMaxLocalSize); the workgroup building
// blocks (workgroup.glsl) keep one shared word per subgroup in an array of this size.
RS_CONST(uint, kMaxLocalSize, 1024u);
// What an output word no invocation wrote holds: the host fills every new storage buffer it can map
// with it (a NaN as a float; never a flag, count, index or pair), and the emulated kernels' buffers
// start with it too, so that a kernel which leaves a word unwritten is compared bit for bit.
RS_CONST(uint, kPoisonWord, 0x7FA11A5Eu);
// Planted faults of the workgroup building blocks (gpu/shaders/workgroup.glsl and their emulator
// mirror, emu/workgroup_ops.h), the mistakes GPU developers make: every pass whose kernel uses the
// blocks lists them under these numbers (rayspace/pass_registry.h), `--inject PASS:NAME[@emu]`.
RS_CONST(uint, kFaultDroppedBarrier, 11u);    // the barrier between publishing and reading subgroup sums
RS_CONST(uint, kFaultDivergentBarrier, 12u);  // that barrier reached by the first half of the workgroup only
RS_CONST(uint, kFaultSubgroup32, 13u);        // the subgroup size assumed to be 32
RS_CONST(uint, kFaultSharedOffByOne, 14u);    // subgroup sums published one shared word too far
RS_CONST(uint, kFaultWorkgroupOffset, 15u);   // a workgroup starts at the next block's offset of the global scan
// Planted faults for the simulated GPU's checkers, in trim's kernel only (no emulator mirror): each is
// a mistake a device may run benignly or that corrupts far from its cause.
RS_CONST(uint, kFaultGlobalRace, 16u);      // every invocation stores its workgroup's block sum, not the first alone
RS_CONST(uint, kFaultOutOfBounds, 17u);     // a flag is loaded before the bounds check, past the stream's end
RS_CONST(uint, kFaultUndefinedValue, 18u);  // the first workgroup's running offset is never set
RS_CONST(uint, kFaultLinearLanes, 19u);     // slots handed out by local index, as if lanes were local ids in order
RS_CONST(uint, kFaultFarOutOfBounds, 20u);  // a flag loaded a block past its own, beyond any guard words
// Planted faults that behave like a real GPU's arithmetic (gpu/shaders/common.glsl Div, Sqrt), which
// the relaxed comparison must accept, and one no conformant device produces, which it must refuse
// (docs/numerics.md, "The relaxed device model").
RS_CONST(uint, kFaultApproxDiv, 21u);   // a / b as a * (1 / b)
RS_CONST(uint, kFaultApproxSqrt, 22u);  // sqrt(x) as 1 / inversesqrt(x)
RS_CONST(uint, kFaultUlp4, 23u);        // a result 4 ULP off
RS_CONST(uint, kFaultSqrtHigh, 24u);    // sqrt(x) two ULP high, within what inversesqrt permits
// A (node, triangle) pair is packed as (node - level base) << kPairTriangleBits | (triangle - b0):
// a triangle batch holds at most 2^14 triangles and a level at most 2^18 nodes per batch.
RS_CONST(uint, kPairTriangleBits, 14u);
RS_CONST(uint, kPairTriangleMask, 16383u);  // (1 << kPairTriangleBits) - 1
// --objects tree: a pair of the joint descent is two words. cone = level << kTreeLevelShift | node
// within its level (level 0: a ray, by its place in the sorted order); item = an object-tree node,
// or kTreeItemTriangle | an index into the tree's triangle list.
RS_CONST(uint, kTreeLevelShift, 28u);
RS_CONST(uint, kTreeNodeMask, 268435455u);  // (1 << kTreeLevelShift) - 1
RS_CONST(uint, kTreeItemTriangle, 2147483648u);
// Margins of the cone-sphere nodes (docs/numerics.md, derived for any conformant device: division
// within 2.5 ULP, sqrt from inversesqrt, RTE or RTZ, denormals flushed): radii grow by a relative
// 2^-18 plus an absolute 2^-122 (a normal float, so flushing cannot erase it) and half-angles by
// 2^-18 when a node is finished; the cone-sphere test accepts a relative 2^-17 (|a| + |b|) slack.
RS_CONST(float, kRadiusSlack, 1.000003814697265625);  // 1 + 2^-18
RS_CONST(uint, kRadiusFloorBits, 0x02800000u);         // 2^-122
RS_CONST(float, kAngleSlack, 3.814697265625e-06);      // 2^-18
RS_CONST(float, kTestSlack, 7.62939453125e-06);        // 2^-17
// The fused top level's group cull on the device (cone_cull.glsl, emu cone::DeviceGroupMisses): in
// float, with margins 2^-11 (docs/performance.md, "Group culling on the device"); values at or above
// 2^60 in magnitude are not judged (no float overflow in the squares).
RS_CONST(float, kDeviceCullMargin, 4.8828125e-04);              // 2^-11
RS_CONST(float, kDeviceCullFloor, 9.094947017729282379150390625e-13);  // 2^-40, absolute
RS_CONST(float, kDeviceCullLimit, 1152921504606846976.0);        // 2^60
RS_CONST(float, kDeviceCullRadiusUp, 1.00000095367431640625);    // 1 + 2^-20
RS_CONST(float, kDeviceCullUnit, 1.9073486328125e-06);           // 2^-19

// ---- surfaces: G-buffer pixels -> shading points ----------------------------------------------
RS_CONST(uint, kSurfacesBindPosition, 0u);
RS_CONST(uint, kSurfacesBindNormal, 1u);
RS_CONST(uint, kSurfacesBindPrim, 2u);
RS_CONST(uint, kSurfacesBindInfo, 3u);
RS_CONST(uint, kSurfacesBindFrame, 4u);
RS_CONST(uint, kSurfacesBindSurfaces, 5u);
RS_CONST(uint, kSurfacesBindings, 6u);
struct SurfacesPush {
  uint pixels;  // pixels of this dispatch
  uint base;    // first pixel of this dispatch
};

// ---- surfaces.hits: reflection / refraction hits -> shading points ------------------------------
RS_CONST(uint, kSurfacesHitsBindRays, 0u);
RS_CONST(uint, kSurfacesHitsBindHits, 1u);
RS_CONST(uint, kSurfacesHitsBindTriangles, 2u);
RS_CONST(uint, kSurfacesHitsBindNormals, 3u);
RS_CONST(uint, kSurfacesHitsBindInfo, 4u);
RS_CONST(uint, kSurfacesHitsBindSurfaces, 5u);
RS_CONST(uint, kSurfacesHitsBindings, 6u);
struct SurfacesHitsPush {
  uint n;
};

// ---- raygen.shadow / raygen.reflection / raygen.refraction --------------------------------------
// The three ray-generation kernels share their bindings; binding 1 holds the lights (shadow) or the
// materials (reflection, refraction).
RS_CONST(uint, kRaygenBindSurfaces, 0u);
RS_CONST(uint, kRaygenBindLightsOrMaterials, 1u);
RS_CONST(uint, kRaygenBindFrame, 2u);
RS_CONST(uint, kRaygenBindRays, 3u);
RS_CONST(uint, kRaygenBindFlags, 4u);
RS_CONST(uint, kRaygenBindings, 5u);
// Which covered surfaces get a shadow ray per light (--shadow-rule): all, or only those the light
// lies in front of (n.l > 0, the thesis's count; docs/hierarchy.md, "Faithful to the thesis").
RS_CONST(uint, kShadowRuleAll, 0u);
RS_CONST(uint, kShadowRuleLit, 1u);
struct RaygenShadowPush {
  uint surface_count;
  uint light_count;
  uint rule;   // kShadowRuleAll or kShadowRuleLit
  uint slots;  // shadow slots per surface: the lights' samples (Light.sampling)
};
struct RaygenPush {  // reflection, refraction
  uint surface_count;
  uint base;  // first surface of this dispatch
};

// ---- trim: order-preserving compaction of sparse rays ------------------------------------------
RS_CONST(uint, kTrimBindFlags, 0u);
RS_CONST(uint, kTrimBindSums, 1u);     // per block, then the total
RS_CONST(uint, kTrimBindOffsets, 2u);
RS_CONST(uint, kTrimBindSparse, 3u);
RS_CONST(uint, kTrimBindDense, 4u);
RS_CONST(uint, kTrimBindings, 5u);
RS_CONST(uint, kTrimPhaseBlockSums, 0u);
RS_CONST(uint, kTrimPhaseScanSums, 1u);
RS_CONST(uint, kTrimPhaseScatter, 2u);
struct TrimPush {
  uint n;
  uint phase;
  uint carry;  // flagged slots before this dispatch's part of the stream
};

// ---- hash: 32-bit sort keys per ray ------------------------------------------------------------
RS_CONST(uint, kHashBindRays, 0u);
RS_CONST(uint, kHashBindFrame, 1u);
RS_CONST(uint, kHashBindKeys, 2u);
RS_CONST(uint, kHashBindings, 3u);
// The layout of a key's direction part (--hash-order): the polar and azimuth cells bit-interleaved,
// polar bit above azimuth bit (the default: sorted neighbours are close in both angles), or all the
// polar bits above all the azimuth bits (the CRSH thesis, sec. 3.8: light index, then the spherical
// coordinates, polar first).
RS_CONST(uint, kHashOrderInterleaved, 0u);
RS_CONST(uint, kHashOrderPolarFirst, 1u);
// Bits of a key; a shadow key holds the light index and both angles' cells in them.
RS_CONST(int, kHashKeyBits, 32);
struct HashPush {
  uint n;
  int light_bits;
  int polar_bits;
  int azimuth_bits;
  int origin_bits;
  int direction_bits;
  uint quad_width;  // > 0: Roger et al.'s quadtree keys
  uint quad_depth;
  uint order;  // kHashOrderInterleaved or kHashOrderPolarFirst
};

// ---- compress / sort / decompress: one kernel (sort.comp), three passes ------------------------
RS_CONST(uint, kSortBindKeys, 0u);
RS_CONST(uint, kSortBindChunkKey, 1u);
RS_CONST(uint, kSortBindChunkBase, 2u);
RS_CONST(uint, kSortBindChunkSize, 3u);
RS_CONST(uint, kSortBindSorted, 4u);   // chunk indices, 2 x chunks (ping-pong)
RS_CONST(uint, kSortBindOrder, 5u);    // ray order
RS_CONST(uint, kSortBindCount, 6u);    // [0] number of chunks
RS_CONST(uint, kSortBindScratch, 7u);
RS_CONST(uint, kSortBindSums, 8u);     // per block, plus a total
RS_CONST(uint, kSortBindings, 9u);
// compress over n keys
RS_CONST(uint, kCompressPhaseHeads, 0u);
RS_CONST(uint, kCompressPhaseBlockSums, 1u);
RS_CONST(uint, kCompressPhaseScanSums, 2u);
RS_CONST(uint, kCompressPhaseChunks, 3u);
RS_CONST(uint, kCompressPhaseSizes, 4u);
// one LSD radix pass over n chunks (8 bits at `shift`), sorted[src..] -> sorted[dst..]
RS_CONST(uint, kSortPhaseInit, 10u);
RS_CONST(uint, kSortPhaseHistograms, 11u);
RS_CONST(uint, kSortPhaseBinScan, 12u);
RS_CONST(uint, kSortPhaseTotalScan, 13u);
RS_CONST(uint, kSortPhaseScatter, 14u);
// The scatter ranks at most kSortRankStep elements a step: a bit per element in kSortRankWords words
// per digit, 8 KB of shared memory whatever the local size.
RS_CONST(uint, kSortRankStep, 256u);
RS_CONST(uint, kSortRankWords, 8u);
// BinScan runs 256 / per workgroups, `per` bins each: one while a bin's blocks fill half a workgroup,
// else as many whole bins as one pass of the workgroup holds (sort.comp's SortBinsPerGroup).
#ifdef __cplusplus
constexpr uint SortBinsPerGroup(uint blocks, uint local_size) {
  uint per = 1u;
  for (uint k = 0u; k < 8u && blocks > 0u && 2u * per * blocks <= local_size; ++k) per *= 2u;
  return per;
}
static_assert(SortBinsPerGroup(5u, 1024u) == 128u && SortBinsPerGroup(5u, 64u) == 8u && SortBinsPerGroup(33u, 64u) == 1u &&
              SortBinsPerGroup(1u, 1024u) == 256u && SortBinsPerGroup(0u, 64u) == 1u);
#endif
// decompress: sizes in sorted order, scan, then every ray finds its chunk
RS_CONST(uint, kDecompressPhaseSizes, 20u);
RS_CONST(uint, kDecompressPhaseBlockSums, 21u);
RS_CONST(uint, kDecompressPhaseScanSums, 22u);
RS_CONST(uint, kDecompressPhaseStarts, 23u);
RS_CONST(uint, kDecompressPhaseRays, 24u);
struct SortPush {
  uint n;
  uint phase;
  uint shift;  // decompress: the ray count
  uint src;
  uint dst;
  uint blocks;
};

// ---- build: cone-sphere nodes from sorted rays (leaves) or from the level below (parents) --------
RS_CONST(uint, kBuildBindFirst, 0u);
RS_CONST(uint, kBuildBindNodes, 1u);
RS_CONST(uint, kBuildBindRays, 2u);    // paged
RS_CONST(uint, kBuildBindOrder, 6u);   // paged
RS_CONST(uint, kBuildBindBelow, 10u);  // paged
RS_CONST(uint, kBuildBindings, 14u);
RS_CONST(uint, kBuildPhaseLeaves, 0u);
RS_CONST(uint, kBuildPhaseParents, 1u);
// How a parent unites its children (--child-merge): one after another (the thesis's fold), or as a
// balanced binary tree in child order, whose spheres grow with the depth of the tree instead of the
// number of children (docs/hierarchy.md, "Faithful to the thesis"). Either way the parent is then
// checked against every child and finished, so it holds them.
RS_CONST(uint, kChildMergeSequential, 0u);
RS_CONST(uint, kChildMergePairwise, 1u);
struct BuildPush {
  uint count;
  uint phase;
  uint ray_page;
  uint order_page;
  uint below_page;
  uint child_merge;  // parents: kChildMergeSequential or kChildMergePairwise
};

// ---- traverse: cone-sphere nodes against triangle or object spheres ----------------------------
RS_CONST(uint, kTraverseBindTriSpheres, 0u);  // the object spheres in kTraversePhaseObjects
RS_CONST(uint, kTraverseBindInfo, 1u);
RS_CONST(uint, kTraverseBindMask, 2u);        // the object mask's rows of this dispatch's top nodes
RS_CONST(uint, kTraverseBindPairs, 3u);
RS_CONST(uint, kTraverseBindFlags, 4u);
RS_CONST(uint, kTraverseBindValues, 5u);
RS_CONST(uint, kTraverseBindTested, 6u);
RS_CONST(uint, kTraverseBindNodes, 7u);       // paged
RS_CONST(uint, kTraverseBindFirst, 11u);      // paged
RS_CONST(uint, kTraverseBindings, 15u);
RS_CONST(uint, kTraversePhaseTop, 0u);        // top nodes x triangles
RS_CONST(uint, kTraversePhaseLevel, 1u);      // children of each surviving pair's node
RS_CONST(uint, kTraversePhaseObjects, 2u);    // top nodes x object spheres (CRSH's culling mask)
// The top phase runs one invocation per run of kTraverseTopRun consecutive slots of one row (one top
// node against kTraverseTopRun consecutive triangles): rows x ceil(tris / kTraverseTopRun)
// invocations for `count` = rows x tris slots. The row's node, a paged load of three vec4 that costs
// lavapipe more than the cone test, is loaded once per run rather than once per slot.
RS_CONST(uint, kTraverseTopRun, 8u);
// Which cone-sphere test the traversal runs (--cone-test; docs/hierarchy.md, "Faithful to the
// thesis"): the conservative one (cone.glsl ConeTest, emu cone::Test) or eq. 3.16 as the thesis prints
// it (PrintedConeTest, emu cone::PrintedTest), which can lose hits, or the same without the absolute
// value of the distance along the axis (kConeTestPrintedSigned: one cone, not two apex to apex). A push
// field, not a specialization constant: it is a frame's data like eps, carried by the emulator's calls
// and their saved replays, and one pipeline serves all three.
RS_CONST(uint, kConeTestConservative, 0u);
RS_CONST(uint, kConeTestPrinted, 1u);
RS_CONST(uint, kConeTestPrintedSigned, 2u);
struct TraversePush {
  uint phase;
  uint count;
  uint t0;
  uint b0;
  uint tris;
  uint objects;
  uint use_mask;
  uint base_up;
  uint base;
  uint children_max;
  float eps;
  uint id_base;  // top: packed node ids relative to this node (a dispatch may cover part of a block)
  uint node_page;
  uint first_page;
  uint cone_test;  // kConeTestConservative or kConeTestPrinted
};

// ---- traverse.compact: the traversal fused with its stream reduction ------------------------------
// Blocks of slots (traverse.comp's numbering), each with its region of the scratch buffer (slot-
// indexed: a block never has more survivors than slots): at the top level a block is one top node's
// row of `tris` slots, below it kCompactBlock consecutive slots. Phase A, Top: one workgroup per
// tile of kCompactRows rows, in rounds of kLocalSize x kCompactCols triangles, kCompactCols
// consecutive ones per invocation tested against every row's node; Level: one workgroup per block,
// in rounds of kLocalSize (pair, chunk)s, one per invocation, a chunk kCompactChunk children (one
// bit mask word). A workgroup scan places each round's survivors after the round before, in slot
// order. Phase Scan: one workgroup scans the block counts (exclusive offsets, the total last) and
// sums the block tests. Phase Scatter: one workgroup per block copies its survivors to its offset.
// Phase Groups, before Top: one workgroup per round of Top's triangles; each subgroup writes the
// group sphere of its lanes' triangles (centre and radius, a negative radius where the group may
// not be judged), which Top's subgroups cull rows by, and each invocation the object its
// kCompactCols triangles share (kCompactMixedObjects where they do not), which Top reads instead of
// each triangle's. The Groups buffer holds, per round, 5 x local size words: 4 words (the sphere's
// float bits) for each possible subgroup, then one object word per invocation.
RS_CONST(uint, kCompactBlock, 4096u);
RS_CONST(uint, kCompactChunk, 32u);
RS_CONST(uint, kCompactRows, 8u);  // a subgroup of at least this many lanes passes the rows' nodes around
RS_CONST(uint, kCompactCols, 8u);
RS_CONST(uint, kCompactMixedObjects, 0xFFFFFFFFu);  // no object id: ids are below the object count
// Groups' words per invocation and round: a group sphere (4) per possible subgroup, an object word.
RS_CONST(uint, kCompactGroupWords, 5u);
// Level and Scatter run on a grid of at most kCompactStrideGroups workgroups, each taking blocks g,
// g + grid, ...: lavapipe pays for every workgroup it starts, whatever its work.
RS_CONST(uint, kCompactStrideGroups, 256u);
RS_CONST(uint, kTraverseCompactBindTriSpheres, 0u);
RS_CONST(uint, kTraverseCompactBindInfo, 1u);
// top: the object mask of this dispatch's top nodes, a word per tile of kCompactRows rows (from the
// dispatch's first) and object, bit r set when the tile's row r may meet the object (emu::PackMaskTiles)
RS_CONST(uint, kTraverseCompactBindMask, 2u);
RS_CONST(uint, kTraverseCompactBindPairs, 3u);
RS_CONST(uint, kTraverseCompactBindScratch, 4u);  // one word per slot: each block's survivors from its first slot
RS_CONST(uint, kTraverseCompactBindCounts, 5u);   // survivors per block, then exclusive offsets; the total last
RS_CONST(uint, kTraverseCompactBindTested, 6u);   // tests per block; their sum last
RS_CONST(uint, kTraverseCompactBindOut, 7u);      // the survivors in slot order
RS_CONST(uint, kTraverseCompactBindNodes, 8u);    // paged
RS_CONST(uint, kTraverseCompactBindFirst, 12u);   // paged
RS_CONST(uint, kTraverseCompactBindGroups, 16u);  // top: per round, group spheres and object words (Groups)
RS_CONST(uint, kTraverseCompactBindings, 17u);
RS_CONST(uint, kTraverseCompactPhaseTop, 0u);      // phase A over top nodes x triangles
RS_CONST(uint, kTraverseCompactPhaseLevel, 1u);    // phase A over the children of each pair's node
RS_CONST(uint, kTraverseCompactPhaseScan, 2u);     // phase B
RS_CONST(uint, kTraverseCompactPhaseScatter, 3u);  // phase C
RS_CONST(uint, kTraverseCompactPhaseGroups, 4u);   // before Top: the group spheres its subgroups cull by
struct TraverseCompactPush {
  uint phase;
  uint count;   // slots of this dispatch's part
  uint blocks;  // top: rows (count / tris); level: (count + kCompactBlock - 1) / kCompactBlock
  uint region;  // slots a block's scratch region holds: top tris, level kCompactBlock
  uint t0;      // top: the part's first top node (its object-mask rows start there)
  uint b0;
  uint tris;
  uint objects;
  uint use_mask;
  uint base_up;
  uint base;
  uint children_max;
  float eps;
  uint id_base;  // top: packed node ids relative to this node (the call's first)
  uint node_page;
  uint first_page;
  uint cone_test;  // kConeTestConservative or kConeTestPrinted
};

// ---- reduce: stream reduction of (flag, value) slots -------------------------------------------
RS_CONST(uint, kReduceBindFlags, 0u);
RS_CONST(uint, kReduceBindValues, 1u);
RS_CONST(uint, kReduceBindLocal, 2u);
RS_CONST(uint, kReduceBindCounts, 3u);  // per component, then exclusive offsets
RS_CONST(uint, kReduceBindSums, 4u);    // per block of kScanBlock counts, plus the total
RS_CONST(uint, kReduceBindOut, 5u);
RS_CONST(uint, kReduceBindings, 6u);
// hierarchical (Roger et al.): components of s slots reduced on their own, then concatenated
RS_CONST(uint, kReducePhaseLocal, 0u);
RS_CONST(uint, kReducePhaseBlockSums, 1u);
RS_CONST(uint, kReducePhaseScanSums, 2u);  // also the scan-based reduction's middle phase
RS_CONST(uint, kReducePhaseOffsets, 3u);
RS_CONST(uint, kReducePhaseConcat, 4u);
// Local and Concat run a subgroup per component over a grid of at most kReduceStrideGroups
// workgroups, each subgroup striding from component to component: lavapipe pays for every
// workgroup it starts (docs/performance.md, "Workgroups that stride").
RS_CONST(uint, kReduceStrideGroups, 256u);
// scan-based
RS_CONST(uint, kReducePhaseFlagSums, 10u);
RS_CONST(uint, kReducePhaseScatter, 11u);
struct ReducePush {
  uint n;
  uint phase;
  uint s;
  uint comps;
  uint blocks;
};

// ---- intersect: final ray-triangle tests of (leaf, triangle) pairs -----------------------------
RS_CONST(uint, kIntersectBindPairs, 0u);
RS_CONST(uint, kIntersectBindTriangles, 1u);
RS_CONST(uint, kIntersectBindTests, 2u);
RS_CONST(uint, kIntersectBindFirst, 3u);     // paged
RS_CONST(uint, kIntersectBindOrder, 7u);     // paged
RS_CONST(uint, kIntersectBindRays, 11u);     // paged
RS_CONST(uint, kIntersectBindHits, 15u);     // paged
RS_CONST(uint, kIntersectBindOccluded, 19u); // paged
RS_CONST(uint, kIntersectBindTriSpheres, 23u);  // read with kLeafTestRaySphere only
RS_CONST(uint, kIntersectBindings, 24u);
// What a ray of a surviving level-1 pair meets before its ray-triangle test (--leaf-test): nothing
// (every ray of the node is tested against the triangle), or the triangle's bounding sphere, each ray
// as a one-ray cone node under the traversal's test (Roger et al. 2007: a leaf keeps "the ID of all
// triangles whose bounding sphere it intersects"); conservative, so the hits are the same.
RS_CONST(uint, kLeafTestNode, 0u);
RS_CONST(uint, kLeafTestRaySphere, 1u);
struct IntersectPush {
  uint count;
  uint base1;
  uint b0;
  uint shadow;
  uint first_page;
  uint order_page;
  uint ray_page;
  uint hit_page;
  uint occluded_page;
  uint leaf_test;  // kLeafTestNode or kLeafTestRaySphere
  float eps;       // the traversal's margin, for the ray-sphere test
};

// ---- --objects tree: the joint descent (tree.roots, tree.expand, tree.test, tree.step) ----------
// The four tree kernels share their bindings: the two hierarchies (emu/tree_streams.h), the pairs of
// the round, and what they write. Counters: u32 words, per cone level (levels) its tests then hits,
// per object-node depth (depths) its tests then hits, then the triangle spheres' tests and hits.
RS_CONST(uint, kTreeBindConeNodes, 0u);
RS_CONST(uint, kTreeBindConeBase, 1u);
RS_CONST(uint, kTreeBindConeFirst, 2u);
RS_CONST(uint, kTreeBindSpheres, 3u);
RS_CONST(uint, kTreeBindLinks, 4u);
RS_CONST(uint, kTreeBindDepth, 5u);
RS_CONST(uint, kTreeBindRoots, 6u);
RS_CONST(uint, kTreeBindTriSpheres, 7u);
RS_CONST(uint, kTreeBindPairCone, 8u);
RS_CONST(uint, kTreeBindPairItem, 9u);
RS_CONST(uint, kTreeBindOffsets, 10u);    // tree.test: per pair its first slot; tree.step: per block 2 counts, then their scan
RS_CONST(uint, kTreeBindFlags, 11u);      // tree.expand: per pair its candidates; tree.roots / tree.test: per slot
RS_CONST(uint, kTreeBindOutCone, 12u);    // per slot; tree.step: the next pairs, then the final ones
RS_CONST(uint, kTreeBindOutItem, 13u);
RS_CONST(uint, kTreeBindCounters, 14u);
RS_CONST(uint, kTreeBindings, 15u);
// tree.step: blocks of kTreeStepBlock pairs, one workgroup each, in rounds of kLocalSize pairs (one an
// invocation). Phase Count: each block's survivors of both kinds (and the counters); phase Scan: one
// workgroup scans the block counts (exclusive offsets; totals last); phase Scatter: each block tests
// again and writes its survivors at its offsets, pairs in pair order, candidates in candidate order.
RS_CONST(uint, kTreeStepBlock, 1024u);
RS_CONST(uint, kTreeStepPhaseCount, 0u);
RS_CONST(uint, kTreeStepPhaseScan, 1u);
RS_CONST(uint, kTreeStepPhaseScatter, 2u);
struct TreePush {
  uint count;    // roots: slots; otherwise pairs
  uint levels;   // cone levels, D + 1
  uint depths;   // object-node depths
  uint level;    // roots: the level of nodes t0 ..
  uint t0;
  uint roots;
  float eps;
  uint phase;    // tree.step
  uint blocks;   // tree.step
  uint slots;    // tree.test: the slots; tree.step Scatter: the next pairs' total (the final ones follow)
};

// ---- intersect.tree: final ray-triangle tests of (level-1 node or ray, triangle) pairs -------------
RS_CONST(uint, kIntersectTreeBindPairCone, 0u);
RS_CONST(uint, kIntersectTreeBindPairItem, 1u);
RS_CONST(uint, kIntersectTreeBindFirst, 2u);
RS_CONST(uint, kIntersectTreeBindTreeTriangles, 3u);
RS_CONST(uint, kIntersectTreeBindOrder, 4u);
RS_CONST(uint, kIntersectTreeBindRays, 5u);
RS_CONST(uint, kIntersectTreeBindTriangles, 6u);
RS_CONST(uint, kIntersectTreeBindTests, 7u);
RS_CONST(uint, kIntersectTreeBindHits, 8u);
RS_CONST(uint, kIntersectTreeBindOccluded, 9u);
RS_CONST(uint, kIntersectTreeBindings, 10u);
struct IntersectTreePush {
  uint count;
  uint shadow;
};

// ---- tl.lists, tl.trace: Toczek et al.'s traversal lists (docs/traversal-lists.md) ----------------
// The bounding-sphere tree is built on the host (the object tree's build, one for every consumer);
// tl.lists orders and flattens it into K lists, tl.trace walks them. tl.lists writes list k at
// [k E, k E + lengths[k]) of its outputs, E = nodes + triangle references: every element, or with
// back-face culling those left once the triangles no ray of the list's class can hit from the front
// are dropped, and with them every node left with no triangle below it. A tree element is a node
// n < nodes, or the triangle reference nodes + j (the tree's j-th triangle).
RS_CONST(uint, kTlListsBindLinks, 0u);      // per node: first_child, children, first_tri, tris
RS_CONST(uint, kTlListsBindSpheres, 1u);    // per node: centre, radius
RS_CONST(uint, kTlListsBindParents, 2u);    // per node: its parent, kTlNoParent for a root
RS_CONST(uint, kTlListsBindSizes, 3u);      // per node: the elements of its subtree, itself included
RS_CONST(uint, kTlListsBindRoots, 4u);      // the roots, in list order
RS_CONST(uint, kTlListsBindTriangles, 5u);  // per triangle reference: the scene triangle
RS_CONST(uint, kTlListsBindOwners, 6u);     // per triangle reference: the node holding it
RS_CONST(uint, kTlListsBindTriWords, 7u);   // per scene triangle: its word (three vertex indices, id)
RS_CONST(uint, kTlListsBindVertices, 8u);   // the shared vertex array
RS_CONST(uint, kTlListsBindDirections, 9u); // per list: its ordering direction (xyz)
RS_CONST(uint, kTlListsBindRel, 10u);       // per (list, element): its offset from its parent (scratch)
RS_CONST(uint, kTlListsBindEscapes, 11u);   // per list element: the escape's bits
RS_CONST(uint, kTlListsBindWords, 12u);     // per list element
RS_CONST(uint, kTlListsBindKept, 13u);      // per (list, node): kept triangles, kept nodes below it (uvec2, scratch)
RS_CONST(uint, kTlListsBindLengths, 14u);   // per list: its elements
RS_CONST(uint, kTlListsBindings, 15u);
RS_CONST(uint, kTlNoParent, 4294967295u);
// A node's children (own triangles, then child nodes) are ordered by key: earliest first by the low
// end of their projection on the list's direction, latest last by the high end.
RS_CONST(uint, kTlOrderEarliestFirst, 0u);
RS_CONST(uint, kTlOrderLatestLast, 1u);
// Phase Triangles: each (list, triangle reference) kept adds 1 to its owner's and every ancestor's
// kept triangles. Phase Nodes: each (list, node) with a kept triangle below adds 1 to its own and
// every ancestor's kept nodes. Phase Rank: each kept (list, element) its offset after its parent
// (1 + the kept subtrees of the siblings before it). Phase Place: its position (the offsets up to
// its root), escape and word.
RS_CONST(uint, kTlListsPhaseTriangles, 0u);
RS_CONST(uint, kTlListsPhaseNodes, 1u);
RS_CONST(uint, kTlListsPhaseRank, 2u);
RS_CONST(uint, kTlListsPhasePlace, 3u);
// Back-face culling (cull = 1): a triangle is dropped from a list when, with n = (v1 - v0) x (v2 - v0)
// in float, g . n > kTlCullMargin |e1| |e2| (max norms) for every corner g of the list's direction
// class: every ray of the class then meets its back (docs/traversal-lists.md, "Back-face culling").
RS_CONST(float, kTlCullMargin, 1.52587890625e-05);  // 2^-16
// Loops over siblings and walks over a list run in blocks of this many iterations (lavapipe ends a
// loop after 65,535), so a list may hold up to kTlMaxElements elements.
RS_CONST(uint, kTlLoopBlock, 4096u);
RS_CONST(uint, kTlMaxElements, 268431360u);  // 65,535 blocks
// The deepest node (a root at 0): the object tree's build stops splitting there.
RS_CONST(uint, kTlMaxDepth, 64u);
// The paper's special escapes, as the bits of a signed 32-bit offset: 0 ends the walk after the last
// triangle, -1 after a sphere with no super-sibling.
RS_CONST(uint, kTlEscapeLast, 0u);
RS_CONST(uint, kTlEscapeNone, 4294967295u);
struct TlListsPush {
  uint nodes;
  uint refs;    // triangle references
  uint lists;   // K
  uint roots;
  uint order;   // kTlOrder*
  uint phase;   // kTlListsPhase*
  uint cull;    // 1: drop the triangles every ray of a list's class meets from behind
};

RS_CONST(uint, kTlTraceBindFirst, 0u);      // K + 1 offsets
RS_CONST(uint, kTlTraceBindEscapes, 1u);
RS_CONST(uint, kTlTraceBindWords, 2u);
RS_CONST(uint, kTlTraceBindVertices, 3u);
RS_CONST(uint, kTlTraceBindRays, 4u);
RS_CONST(uint, kTlTraceBindHits, 5u);       // closest: packed hit per ray
RS_CONST(uint, kTlTraceBindOccluded, 6u);   // shadow: 1 per occluded ray
RS_CONST(uint, kTlTraceBindSpheres, 7u);    // per ray: the sphere elements it tested
RS_CONST(uint, kTlTraceBindTriangles, 8u);  // per ray: the triangle elements it tested
RS_CONST(uint, kTlTraceBindTriWords, 9u);   // per scene triangle: its vertex indices (heads only)
RS_CONST(uint, kTlTraceBindWindows, 10u);   // tl.heads' windows (heads only)
RS_CONST(uint, kTlTraceBindings, 11u);
struct TlTracePush {
  uint count;   // rays
  uint lists;   // K
  uint shadow;  // 1: any hit (occluded), 0: closest hit
  uint cull;    // 1: one-sided triangles, a hit only from the front (Woop's det > 0)
  uint heads;      // kTlHeads*: walk each ray's window of tl.heads (not kTlHeadsOff)
  uint triangles;  // with triangle heads: the scene triangles (words, windows); with kTlHeadsCells: the cells
};

// ---- tl.heads: per-polygon windows of the traversal lists (Toczek et al. section 3.1) ------------
// A ray that starts on a triangle (reflection, refraction) or ends on it (a shadow ray, which starts
// at the light) reaches only points on one side of the triangle's plane, and, within its list's
// direction class, only points past (or before) the triangle along the class's facet planes. Per
// (triangle, case, list) tl.heads writes the window [head, tail) of the packed list outside which
// every triangle lies beyond one of those planes by more than the margin: the walk need not visit
// it. Case = 2 * ends_on_triangle + (points behind the plane ? 1 : 0); window index
// (triangle * kTlCases + case) * K + list, each a uvec2 of absolute element indices.
RS_CONST(uint, kTlHeadsBindFirst, 0u);
RS_CONST(uint, kTlHeadsBindEscapes, 1u);
RS_CONST(uint, kTlHeadsBindWords, 2u);
RS_CONST(uint, kTlHeadsBindVertices, 3u);
RS_CONST(uint, kTlHeadsBindTriWords, 4u);   // per scene triangle: its vertex indices and id
RS_CONST(uint, kTlHeadsBindWindows, 5u);    // per (triangle, case, list): head, tail
RS_CONST(uint, kTlHeadsBindings, 6u);
RS_CONST(uint, kTlHeadsOff, 0u);
RS_CONST(uint, kTlHeadsSimple, 1u);   // the triangle's plane only
RS_CONST(uint, kTlHeadsRegular, 2u);  // and the facet planes of the list's class
RS_CONST(uint, kTlHeadsCells, 3u);    // tl.trace only: eye rays walk their screen cell's window (tl.cells)
RS_CONST(uint, kTlCases, 4u);
// A ray takes a window only when its direction is clearly off the plane: |d . n| > this x |d| |n|.
RS_CONST(float, kTlSideRatio, 9.765625e-04);  // 2^-10
struct TlHeadsPush {
  uint lists;      // K
  uint triangles;  // scene triangles
  uint mode;       // kTlHeadsSimple or kTlHeadsRegular
  float margin;    // how far beyond a plane an element must lie to be skipped (scene units)
};

// ---- tl.cells: per screen cell the window of each list its eye rays walk (section 3.2) -----------
// The eye rays of a cell of kTlCellPixels x kTlCellPixels pixels leave the eye inside the pyramid
// spanned by the directions through its corner pixels' centres (PixelDirection is affine in the
// pixel); an element wholly outside one of its four side planes by more than the margin is beyond.
// Window index cell * K + list, cell = cy * cells_x + cx; an eye ray names its cell in info.w.
RS_CONST(uint, kTlCellsBindFirst, 0u);
RS_CONST(uint, kTlCellsBindEscapes, 1u);
RS_CONST(uint, kTlCellsBindWords, 2u);
RS_CONST(uint, kTlCellsBindVertices, 3u);
RS_CONST(uint, kTlCellsBindFrame, 4u);     // FrameConstants: the eye and the pixel directions
RS_CONST(uint, kTlCellsBindWindows, 5u);   // per (cell, list): head, tail
RS_CONST(uint, kTlCellsBindings, 6u);
RS_CONST(uint, kTlCellPixels, 16u);
struct TlCellsPush {
  uint lists;    // K
  uint cells_x;  // cells per row: ceil(width / kTlCellPixels)
  uint cells;    // cells_x * ceil(height / kTlCellPixels)
  float margin;  // as tl.heads'
};

// ---- grid.trace: rays through Hunt and Mark's perspective grids and a regular grid --------------
// (docs/grids.md) A point light's shadow rays go through that light's perspective grid: six faces of
// kGridCells x kGridCells cells about the light (a cube map), per cell the triangles whose projection
// from the light meets it and the least distance from the light to any of them, so each ray visits
// exactly one cell. An area light's shadow rays go through its 3D perspective grid (below). Every
// other ray steps through the regular grid over the scene's box (3D DDA). Cells are numbered
// face-major (face * n * n + row * n + column) after each point light's base, the regular grid's
// cells x-fastest after its base, then each 3D grid's ((face * D + slice) * n + row) * n + column;
// `first` holds every cell's CSR offset into `cell_triangles`.
RS_CONST(uint, kGridFaces, 6u);
RS_CONST(uint, kGridNoLight, 4294967295u);  // light_grids[l].x of a light without a grid
// A triangle's projection is binned over a face widened by this fraction (rays on a cube edge may
// pick either face) and its cell range widened by this many cells (the ray's rounded (u, v)).
RS_CONST(float, kGridFaceSlack, 1.52587890625e-05);  // 2^-16
RS_CONST(float, kGridCellSlack, 0.0009765625);       // 2^-10 of a cell
// A cell's least distance is rounded down by this factor: a shadow ray ending before it skips the
// cell's tests (the watertight t carries a few ULP of its own).
RS_CONST(float, kGridDistanceSlack, 0.999755859375);  // 1 - 2^-12
// An area light's 3D perspective grid (Hunt and Mark 5.3; docs/grids.md) about the light's centre:
// a core cube of half-side zn (origins[l].w) holding every sample point, and outside it, per face,
// n x n x D cells in perspective space (u, v, r = 1 / depth), the depth slices' r boundaries from
// `slices`. A ray walks its part in the core through the regular grid, then each face's part in a
// 3D DDA along the straight line the ray becomes in perspective space. Faces start at zn shrunk by
// this factor and the core reaches zn widened by it, so rounding leaves no gap between them.
RS_CONST(float, kGridNearShrink, 0.9990234375);  // 1 - 2^-10
RS_CONST(float, kGridCoreWiden, 1.0009765625);   // 1 + 2^-10
RS_CONST(uint, kGridMaxSlices, 64u);             // D at most
RS_CONST(uint, kGridTraceBindFirst, 0u);      // CSR offsets of every cell, then the total
RS_CONST(uint, kGridTraceBindTriangles, 1u);  // cell_triangles
RS_CONST(uint, kGridTraceBindMinDist, 2u);    // per perspective cell: its least distance
RS_CONST(uint, kGridTraceBindLights, 3u);     // per light (then the eye's): uvec4 (first cell, n, D, first slice);
                                              // D = 0: a point light's (or the eye's) 2D grid
RS_CONST(uint, kGridTraceBindOrigins, 4u);    // per light (then the eye): vec4 (its position, 1; 3D: zn)
RS_CONST(uint, kGridTraceBindVolume, 5u);     // GridVolume
RS_CONST(uint, kGridTraceBindSceneTris, 6u);  // the scene's triangles
RS_CONST(uint, kGridTraceBindRays, 7u);
RS_CONST(uint, kGridTraceBindHits, 8u);       // closest: packed hit per ray
RS_CONST(uint, kGridTraceBindOccluded, 9u);   // shadow: 1 per occluded ray
RS_CONST(uint, kGridTraceBindSteps, 10u);     // per ray: cells visited
RS_CONST(uint, kGridTraceBindTests, 11u);     // per ray: triangles tested
RS_CONST(uint, kGridTraceBindBoxes, 12u);     // per perspective reference: its (u, v) rectangle
RS_CONST(uint, kGridTraceBindSlices, 13u);    // per 3D grid, per face: D + 1 depth boundaries in r, near to far
RS_CONST(uint, kGridTraceBindings, 14u);
// The regular grid over the scene: cells of size `cell` from `lo` to `hi`, dims.xyz of them, the
// first at cell index dims.w.
struct GridVolume {
  vec4 lo;
  vec4 cell;
  vec4 inv_cell;  // 1 / cell, rounded once on the host
  vec4 hi;        // lo + dims * cell
  uvec4 dims;
};
struct GridTracePush {
  uint count;   // rays
  uint shadow;  // 1: any hit (occluded), 0: closest hit
  uint lights;  // entries of light_grids
  uint closed;  // 1 (--closed-models): a shadow ray ending on a triangle that faces away from its
                // light is occluded untraced (the grids then hold only such triangles)
  uint eye;     // --primary grid: the entry of light_grids/origins holding the eye's grid, which
                // eye rays (kRayPrimary) from the eye go through; kGridNoLight: none
  uint secondary;  // --grid-secondary perspective: the entry of light_grids/origins holding the 3D
                   // perspective grid about the eye that every other closest-hit ray walks; kGridNoLight: none
};

// ---- grid.count, grid.emit, grid.cells: the grids built as kernels --------------------------------
// (docs/grids.md, "The build as kernels") One grid at a time, described by a GridBuildGrid. grid.count:
// per triangle and face the span of cells it is binned into (columns, rows, slices: x = first | last
// << 16 and likewise y, z; w = 1 when the face holds any; the regular grid uses face 0 for x, y, z),
// in a 2D grid its (u, v) rectangle, the triangle's references in all and a 2D grid's least distance.
// grid.emit: the counts' exclusive scan, then one invocation per reference, which finds its triangle
// by a binary search over the offsets and its cell from the spans (faces, slices, rows, columns in
// order), so no invocation loops over cells. The sort pass orders the references stably by cell;
// grid.cells gathers them into per-cell lists, each cell's CSR offset a lower bound over the sorted
// cells, and a 2D grid's least distance per cell by atomicMin over the bits of non-negative floats.
// The binning computes in double, as the host build does: the kernels need shaderFloat64 and
// correctly rounded double + - * / and sqrt (lavapipe's; tests/grid_build_test.cpp).
RS_CONST(uint, kGridKindPerspective, 0u);  // a point light's or the eye's 2D grid: n x n cells a face
RS_CONST(uint, kGridKindRegular, 1u);      // the regular grid over the scene's box
RS_CONST(uint, kGridKindVolume, 2u);       // an area light's or the eye's 3D perspective grid
RS_CONST(uint, kGridBuildBindTriangles, 0u);  // the scene's triangles
RS_CONST(uint, kGridBuildBindGrid, 1u);       // one GridBuildGrid
RS_CONST(uint, kGridBuildBindSlices, 2u);     // a 3D grid's per-face D + 1 depth boundaries
RS_CONST(uint, kGridBuildBindCounts, 3u);     // per triangle: its references
RS_CONST(uint, kGridBuildBindDist, 4u);       // per triangle (2D grids): least distance from the centre, rounded down
RS_CONST(uint, kGridBuildBindSpans, 5u);      // per (triangle, face): its span of cells
RS_CONST(uint, kGridBuildBindSpanBoxes, 6u);  // per (triangle, face) of a 2D grid: its (u, v) rectangle
RS_CONST(uint, kGridBuildBindSums, 7u);       // per block of kScanBlock triangles, then the total
RS_CONST(uint, kGridBuildBindOffsets, 8u);    // per triangle: its first reference
RS_CONST(uint, kGridBuildBindCells, 9u);      // per reference in triangle order: its cell
RS_CONST(uint, kGridBuildBindRefTris, 10u);   // per reference: its triangle
RS_CONST(uint, kGridBuildBindBoxes, 11u);     // per reference of a 2D grid: its (u, v) rectangle
RS_CONST(uint, kGridBuildBindOrder, 12u);     // the sort's stable order of the references by cell
RS_CONST(uint, kGridBuildBindFirst, 13u);     // per cell: CSR offset, then the total
RS_CONST(uint, kGridBuildBindListTris, 14u);  // the cells' lists (sorted references' triangles)
RS_CONST(uint, kGridBuildBindListBoxes, 15u); // and their rectangles
RS_CONST(uint, kGridBuildBindMinDist, 16u);   // per cell of a 2D grid: least distance of its triangles
RS_CONST(uint, kGridBuildBindings, 17u);
RS_CONST(uint, kGridBuildPhaseCount, 0u);      // grid.count: one invocation per triangle
RS_CONST(uint, kGridBuildPhaseBlockSums, 1u);  // grid.emit: sums of the counts per block
RS_CONST(uint, kGridBuildPhaseScanSums, 2u);   // one workgroup scans the block sums
RS_CONST(uint, kGridBuildPhaseOffsets, 3u);    // per block: each triangle's first reference
RS_CONST(uint, kGridBuildPhaseEmit, 4u);       // one invocation per reference
RS_CONST(uint, kGridBuildPhaseGather, 5u);     // grid.cells: one invocation per sorted reference
RS_CONST(uint, kGridBuildPhaseCells, 6u);      // one invocation per cell: its offset (and +inf as its least distance)
RS_CONST(uint, kGridBuildPhaseMin, 7u);        // one invocation per sorted reference: atomicMin into its cell
// What the kernels bin: centre and cell are the light's (or eye's) position and, for a 3D grid, the
// core's half-side zn in centre.w; the regular grid's lo and cell size. light_lo/hi: an area light's
// box (front-face culling). shape: kind, then n, D, 0 (2D: D = 0), or the regular grid's dims.
// flags: culling (1) and margins (2), the grid's first slice in `slices`, its cells.
struct GridBuildGrid {
  vec4 centre;
  vec4 cell;
  vec4 light_lo;
  vec4 light_hi;
  uvec4 shape;
  uvec4 flags;
};
RS_CONST(uint, kGridBuildCull, 1u);
RS_CONST(uint, kGridBuildMargins, 2u);
struct GridBuildPush {
  uint phase;
  uint count;   // triangles (count, emit), references (gather, min) or cells (cells)
  uint blocks;  // emit: blocks of kScanBlock triangles; gather (rectangles), cells (least distances): 1 in a 2D grid
  uint refs;    // the references in all
};

// ---- shade: direct light at the shading points into the fixed-point accumulator ---------------
RS_CONST(uint, kShadeBindSurfaces, 0u);
RS_CONST(uint, kShadeBindShadowFlags, 1u);
RS_CONST(uint, kShadeBindShadowOffsets, 2u);
RS_CONST(uint, kShadeBindMaterials, 3u);
RS_CONST(uint, kShadeBindLights, 4u);
RS_CONST(uint, kShadeBindOccluded, 5u);  // paged
RS_CONST(uint, kShadeBindAccum, 9u);     // paged
RS_CONST(uint, kShadeBindings, 13u);
struct ShadePush {
  uint surface_count;
  uint light_count;
  uint occluded_page;
  uint accum_page;
  uint slots;  // shadow slots per surface, as raygen.shadow's
};

// ---- element-wise passes: one invocation per element -----------------------------------------------
// A pass whose call (emu/calls.h, RS_ELEMENTWISE_CALLS) holds only input arrays of one length reads
// them at bindings 0.. in the call's field order, writes its result at the next binding (a uint per
// element for results narrower than 32 bits) and needs no host code of its own
// (gpu/src/elementwise.cpp). Launched in parts: `first` is the part's first element.
struct ElementwisePush {
  uint count;
  uint first;
};

// ---- resolve: accumulator -> 8-bit RGB (element-wise) ----------------------------------------------
RS_CONST(uint, kResolveBindAccum, 0u);
RS_CONST(uint, kResolveBindRgb, 1u);
RS_CONST(uint, kResolveBindings, 2u);

#ifdef __cplusplus
static_assert(kPairTriangleMask == (1u << kPairTriangleBits) - 1u);
static_assert(kTreeNodeMask == (1u << kTreeLevelShift) - 1u && kTreeItemTriangle == 1u << 31);
static_assert(kBufferPages == 4, "the paged bindings below assume four pages");
static_assert(kBuildBindOrder == kBuildBindRays + kBufferPages && kBuildBindBelow == kBuildBindOrder + kBufferPages &&
              kBuildBindings == kBuildBindBelow + kBufferPages);
static_assert(kTraverseBindFirst == kTraverseBindNodes + kBufferPages && kTraverseBindings == kTraverseBindFirst + kBufferPages);
static_assert(kIntersectBindOrder == kIntersectBindFirst + kBufferPages && kIntersectBindRays == kIntersectBindOrder + kBufferPages &&
              kIntersectBindHits == kIntersectBindRays + kBufferPages &&
              kIntersectBindOccluded == kIntersectBindHits + kBufferPages &&
              kIntersectBindTriSpheres == kIntersectBindOccluded + kBufferPages && kIntersectBindings == kIntersectBindTriSpheres + 1u);
static_assert(kShadeBindAccum == kShadeBindOccluded + kBufferPages && kShadeBindings == kShadeBindAccum + kBufferPages);
static_assert(kTraverseCompactBindFirst == kTraverseCompactBindNodes + kBufferPages &&
              kTraverseCompactBindGroups == kTraverseCompactBindFirst + kBufferPages &&
              kTraverseCompactBindings == kTraverseCompactBindGroups + 1u);
// traverse.compact below the top: a chunk is a word of bits, and a round's survivors and tests are
// scanned as one word, 16 bits each.
static_assert(kCompactChunk == 32u && kMaxLocalSize * kCompactChunk < 65536u);
// The top phase scans the rows' survivors as a uvec4 of 16-bit fields.
static_assert(kMaxLocalSize * kCompactCols < 65536u && kCompactRows <= 8u && kCompactCols <= 32u);
// Push-constant blocks: scalars only (same offsets in std430 and C++), within the 128 bytes every
// Vulkan device guarantees.
static_assert(sizeof(SurfacesPush) == 8 && sizeof(SurfacesHitsPush) == 4 && sizeof(RaygenShadowPush) == 16 &&
              sizeof(RaygenPush) == 8 && sizeof(TrimPush) == 12 && sizeof(HashPush) == 36 && sizeof(SortPush) == 24 &&
              sizeof(BuildPush) == 24 && sizeof(TraversePush) == 60 && sizeof(ReducePush) == 20 &&
              sizeof(IntersectPush) == 44 && sizeof(ShadePush) == 20 && sizeof(ElementwisePush) == 8 &&
              sizeof(TraverseCompactPush) == 68 && sizeof(TreePush) == 40 && sizeof(IntersectTreePush) == 8 &&
              sizeof(TlListsPush) == 28 && sizeof(TlTracePush) == 24 && sizeof(TlHeadsPush) == 16 &&
              sizeof(TlCellsPush) == 16 && sizeof(GridTracePush) == 24 && sizeof(GridVolume) == 80 &&
              sizeof(GridBuildGrid) == 96 && sizeof(GridBuildPush) == 16);
static_assert(kTlMaxElements == 65535u * kTlLoopBlock && kTlEscapeNone == ~0u && kTlNoParent == ~0u);
static_assert(kTreeStepBlock % kMaxLocalSize == 0u);
static_assert(kSortRankWords * 32u == kSortRankStep && kScanBlock % kSortRankStep == 0u);
static_assert(offsetof(TraversePush, eps) == 40);
}  // namespace rayspace::layout
#endif
#undef RS_CONST
#endif  // RAYSPACE_CONTRACT_H
