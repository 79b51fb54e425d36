// The pass registry: one declaration per GPU pass. A pass's name is the one statistics, timings,
// `--progress`, `diff` reports and `--inject` use; the registry also names its kernel and phases, its
// bindings and push-constant block (rayspace/contract.h), the backend calls that run it (their inputs
// and outputs are what `diff` compares), which thesis phase its time counts to, and its planted faults.
// The Vulkan kernel loader, the diff's pass table, the timing table and `--inject` read this table,
// and tests hold every backend to it (tests/pass_registry_test.cpp): adding a pass starts here
// (docs/kernels.md).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "rayspace/contract.h"

namespace rayspace {

enum class PassId : std::uint8_t {
  kRaster,
  kSurfaces,
  kSurfacesHits,
  kRaygenShadow,
  kRaygenReflection,
  kRaygenRefraction,
  kTrim,
  kHash,
  kCompress,
  kSort,
  kDecompress,
  kBuild,
  kTraverse,
  kReduce,
  kTraverseCompact,
  kIntersect,
  kTreeRoots,
  kTreeExpand,
  kTreeTest,
  kTreeStep,
  kIntersectTree,
  kTlLists,
  kTlHeads,
  kTlCells,
  kTlTrace,
  kGridCount,
  kGridEmit,
  kGridCells,
  kGridTrace,
  kShade,
  kResolve,
  kCount
};
inline constexpr std::size_t kPassCount = static_cast<std::size_t>(PassId::kCount);

// A planted fault: a known bug compiled into the kernel through specialization constant 0
// (`--inject PASS:N` or `PASS:NAME`), which the diff must report in this pass first. Faults with a name
// are the workgroup faults (kFault* of rayspace/contract.h), plantable on the emulator's side too
// (`PASS:NAME@emu`), where the workgroup checker must name them before any comparison. A pass's own
// fault marked `emu` is mirrored by its emulated kernel too (`PASS:N@emu`), where the diff must catch
// it as it catches the kernel's.
// What a run must do for a fault to fire at all: a fault of the split, paged or folded paths changes
// nothing on a frame that fits the device (`rayspace diff` and `replay` warn then).
enum class FaultNeeds : std::uint8_t {
  kNothing,
  kSplit,          // a buffer split into parts or paged over bindings (--split-bytes)
  kRows,           // a launch folded into rows of workgroups (--max-groups)
  kScanReduction,  // the scan-based reduction (--reduction scan)
};

struct FaultSpec {
  std::uint32_t number;
  std::string_view effect;
  std::string_view name = {};
  bool emu = false;
  FaultNeeds needs = FaultNeeds::kNothing;
  bool kernel_only = false;  // a named fault with no emulator mirror: for the simulated GPU's checkers
};

// A call of the backend interface (emu/backend.h) that runs this pass. `index_outputs` are outputs
// that later passes use as indices or counts: when they differ, the diff must stop.
struct CallSpec {
  std::string_view name;
  std::span<const std::string_view> index_outputs;
};

// A phase of a kernel that runs in several dispatches: the value of the push constant `phase`.
struct PhaseSpec {
  std::string_view name;
  std::uint32_t value;
};

struct PassSpec {
  PassId id;
  std::string_view name;
  std::string_view kernel;  // gpu/shaders/<kernel>.comp; the raster is a graphics pipeline (.vert/.frag)
  bool graphics;
  std::span<const PhaseSpec> phases;  // the kernel's kXPhaseY constants; empty: one dispatch, no phase
  std::uint32_t bindings;                     // storage-buffer bindings 0 .. bindings-1
  std::string_view push_type;                 // the push-constant block's struct in rayspace/contract.h
  std::uint32_t push_bytes;
  std::span<const CallSpec> calls;
  std::string_view thesis_phase;  // where --timings counts its time: ray_creation ... ; "" = other
  std::span<const FaultSpec> faults;
};

namespace pass_registry_detail {
using SV = std::string_view;
inline constexpr SV kRasterIdx[] = {"prim"};
inline constexpr SV kTrimIdx[] = {"offsets"};
inline constexpr SV kCompressIdx[] = {"chunk_key", "chunk_base", "chunk_size"};
inline constexpr SV kSortIdx[] = {"chunk_order"};
inline constexpr SV kDecompressIdx[] = {"ray_order"};
inline constexpr SV kTraverseIdx[] = {"values"};
inline constexpr SV kReduceIdx[] = {"pairs"};
inline constexpr SV kTraverseCompactIdx[] = {"pairs"};
inline constexpr SV kIntersectIdx[] = {"tests"};
inline constexpr SV kTreeSlotsIdx[] = {"flags", "cone", "item"};
inline constexpr SV kTreeExpandIdx[] = {"counts"};
inline constexpr SV kTreeStepIdx[] = {"next_cone", "next_item", "final_cone", "final_item"};
inline constexpr SV kTlListsIdx[] = {"escapes", "words", "lengths"};
inline constexpr SV kTlHeadsIdx[] = {"windows"};
inline constexpr SV kTlCellsIdx[] = {"windows"};
inline constexpr SV kGridCountIdx[] = {"counts", "spans"};
inline constexpr SV kGridEmitIdx[] = {"cells"};
inline constexpr SV kGridCellsIdx[] = {"first", "triangles"};
constexpr std::span<const SV> None() { return {}; }

inline constexpr CallSpec kRasterCalls[] = {{"raster", kRasterIdx}};
inline constexpr CallSpec kSurfacesCalls[] = {{"surfaces", None()}};
inline constexpr CallSpec kSurfacesHitsCalls[] = {{"surfaces.hits", None()}};
// One call generates every kind of ray; its input `kind` selects the pass, in registry order.
inline constexpr CallSpec kRaygenCalls[] = {{"raygen", None()}};
inline constexpr CallSpec kTrimCalls[] = {{"trim", kTrimIdx}};
inline constexpr CallSpec kHashCalls[] = {{"hash", None()}};
inline constexpr CallSpec kCompressCalls[] = {{"compress", kCompressIdx}};
inline constexpr CallSpec kSortCalls[] = {{"sort", kSortIdx}};
inline constexpr CallSpec kDecompressCalls[] = {{"decompress", kDecompressIdx}};
inline constexpr CallSpec kBuildCalls[] = {{"build.leaves", None()}, {"build.parents", None()}};
inline constexpr CallSpec kTraverseCalls[] = {
    {"traverse.objects", None()}, {"traverse.top", kTraverseIdx}, {"traverse.level", kTraverseIdx}};
inline constexpr CallSpec kReduceCalls[] = {{"reduce", kReduceIdx}};
inline constexpr CallSpec kTraverseCompactCalls[] = {{"traverse.compact.top", kTraverseCompactIdx},
                                                     {"traverse.compact.level", kTraverseCompactIdx}};
inline constexpr CallSpec kIntersectCalls[] = {{"intersect", kIntersectIdx}};
inline constexpr CallSpec kTreeRootsCalls[] = {{"tree.roots", kTreeSlotsIdx}};
inline constexpr CallSpec kTreeExpandCalls[] = {{"tree.expand", kTreeExpandIdx}};
inline constexpr CallSpec kTreeTestCalls[] = {{"tree.test", kTreeSlotsIdx}};
inline constexpr CallSpec kTreeStepCalls[] = {{"tree.step", kTreeStepIdx}};
inline constexpr CallSpec kIntersectTreeCalls[] = {{"intersect.tree", kIntersectIdx}};
inline constexpr CallSpec kTlListsCalls[] = {{"tl.lists", kTlListsIdx}};
inline constexpr CallSpec kTlHeadsCalls[] = {{"tl.heads", kTlHeadsIdx}};
inline constexpr CallSpec kTlCellsCalls[] = {{"tl.cells", kTlCellsIdx}};
inline constexpr CallSpec kTlTraceCalls[] = {{"tl.trace", None()}};
inline constexpr CallSpec kGridCountCalls[] = {{"grid.count", kGridCountIdx}};
inline constexpr CallSpec kGridEmitCalls[] = {{"grid.emit", kGridEmitIdx}};
inline constexpr CallSpec kGridCellsCalls[] = {{"grid.cells", kGridCellsIdx}};
inline constexpr CallSpec kGridTraceCalls[] = {{"grid.trace", None()}};
inline constexpr CallSpec kShadeCalls[] = {{"shade", None()}};
inline constexpr CallSpec kResolveCalls[] = {{"resolve", None()}};

#define RS_PHASE(P, X) {#X, layout::k##P##Phase##X}
inline constexpr PhaseSpec kTrimPhases[] = {RS_PHASE(Trim, BlockSums), RS_PHASE(Trim, ScanSums), RS_PHASE(Trim, Scatter)};
inline constexpr PhaseSpec kCompressPhases[] = {RS_PHASE(Compress, Heads), RS_PHASE(Compress, BlockSums),
                                                RS_PHASE(Compress, ScanSums), RS_PHASE(Compress, Chunks),
                                                RS_PHASE(Compress, Sizes)};
inline constexpr PhaseSpec kSortPhases[] = {RS_PHASE(Sort, Init), RS_PHASE(Sort, Histograms), RS_PHASE(Sort, BinScan),
                                            RS_PHASE(Sort, TotalScan), RS_PHASE(Sort, Scatter)};
inline constexpr PhaseSpec kDecompressPhases[] = {RS_PHASE(Decompress, Sizes), RS_PHASE(Decompress, BlockSums),
                                                  RS_PHASE(Decompress, ScanSums), RS_PHASE(Decompress, Starts),
                                                  RS_PHASE(Decompress, Rays)};
inline constexpr PhaseSpec kBuildPhases[] = {RS_PHASE(Build, Leaves), RS_PHASE(Build, Parents)};
inline constexpr PhaseSpec kTraversePhases[] = {RS_PHASE(Traverse, Top), RS_PHASE(Traverse, Level), RS_PHASE(Traverse, Objects)};
inline constexpr PhaseSpec kReducePhases[] = {RS_PHASE(Reduce, Local),    RS_PHASE(Reduce, BlockSums), RS_PHASE(Reduce, ScanSums),
                                              RS_PHASE(Reduce, Offsets),  RS_PHASE(Reduce, Concat),    RS_PHASE(Reduce, FlagSums),
                                              RS_PHASE(Reduce, Scatter)};
inline constexpr PhaseSpec kTraverseCompactPhases[] = {RS_PHASE(TraverseCompact, Top), RS_PHASE(TraverseCompact, Level),
                                                      RS_PHASE(TraverseCompact, Scan), RS_PHASE(TraverseCompact, Scatter),
                                                      RS_PHASE(TraverseCompact, Groups)};
inline constexpr PhaseSpec kTlListsPhases[] = {RS_PHASE(TlLists, Triangles), RS_PHASE(TlLists, Nodes), RS_PHASE(TlLists, Rank),
                                              RS_PHASE(TlLists, Place)};
inline constexpr PhaseSpec kGridCountPhases[] = {RS_PHASE(GridBuild, Count)};
inline constexpr PhaseSpec kGridEmitPhases[] = {RS_PHASE(GridBuild, BlockSums), RS_PHASE(GridBuild, ScanSums), RS_PHASE(GridBuild, Offsets),
                                                RS_PHASE(GridBuild, Emit)};
inline constexpr PhaseSpec kGridCellsPhases[] = {RS_PHASE(GridBuild, Gather), RS_PHASE(GridBuild, Cells), RS_PHASE(GridBuild, Min)};
inline constexpr PhaseSpec kTreeStepPhases[] = {RS_PHASE(TreeStep, Count), RS_PHASE(TreeStep, Scan), RS_PHASE(TreeStep, Scatter)};
#undef RS_PHASE

// What many GPUs compute where Vulkan permits it: the relaxed comparison accepts these.
#define RS_APPROX_DIV {layout::kFaultApproxDiv, "a / b computed as a * (1 / b), as a GPU may", "approx-div"}
#define RS_APPROX_SQRT {layout::kFaultApproxSqrt, "sqrt(x) computed as 1 / inversesqrt(x), as a GPU may", "approx-sqrt"}
inline constexpr FaultSpec kRasterFaults[] = {{1, "the depth is written without the 1/far scale"},
                                              {2, "every vertex half a pixel to the right (edge pixels only)"},
                                              {3, "the pixel's column steps along the rows and its row along the columns"},
                                              RS_APPROX_DIV};
inline constexpr FaultSpec kSurfacesFaults[] = {{1, "rows and columns swapped when the pixel index is split"},
                                                {2, "the view direction is left unnormalised"},
                                                {3, "the position is read from the next pixel's texel"},
                                                {4, "the material id is one past the triangle's"},
                                                RS_APPROX_DIV};
inline constexpr FaultSpec kSurfacesHitsFaults[] = {{1, "the hit point is taken at t from the ray's tmin, not its origin"},
                                                    {2, "the ray's weight is not carried"},
                                                    {3, "the pixel is taken from the surface the ray left"},
                                                    RS_APPROX_DIV, RS_APPROX_SQRT};
inline constexpr FaultSpec kRaygenShadowFaults[] = {{1, "the shadow ray runs all the way to the surface"},
                                                    {2, "the ray is credited to the next pixel"},
                                                    {3, "the last light of every surface is skipped"},
                                                    {4, "an area light's sample drawn at the next sample's point"},
                                                    {5, "a disk's or sphere's sample radius not square-rooted"},
                                                    {6, "the sampler's key ignores the primitive"},
                                                    RS_APPROX_DIV, RS_APPROX_SQRT};
inline constexpr FaultSpec kRaygenReflectionFaults[] = {{1, "the factor 2 of the mirror formula is lost"},
                                                        {2, "the normal term is added, not subtracted"},
                                                        {3, "the ray starts at tmin 0"}};
inline constexpr FaultSpec kRaygenRefractionFaults[] = {{1, "the index ratio is not inverted when the ray leaves"},
                                                        {2, "the normal is not turned to face a leaving ray"},
                                                        {3, "the ratio's square is lost under the root of Snell's law"},
                                                        RS_APPROX_SQRT};
// The faults of workgroup.glsl's WorkgroupInclusiveAdd, in every pass that calls it and whose emulated
// pass runs its mirror.
#define RS_WORKGROUP_FAULTS                                                                                      \
  {layout::kFaultDroppedBarrier, "the barrier between publishing and reading subgroup sums is dropped", "dropped-barrier"}, \
  {layout::kFaultDivergentBarrier, "that barrier is reached by half the workgroup only", "divergent-barrier"},           \
  {layout::kFaultSubgroup32, "the subgroup size is assumed to be 32", "subgroup-32"},                                    \
  {layout::kFaultSharedOffByOne, "subgroup sums are published one shared word too far", "shared-off-by-one"}
inline constexpr FaultSpec kTrimFaults[] = {
    {1, "an inclusive scan where an exclusive one belongs"},
    {2, "the carry between parts is dropped (--split-bytes)", {}, false, FaultNeeds::kSplit},
    {3, "a flagged slot's neighbour is gathered"},
    RS_WORKGROUP_FAULTS,
    {layout::kFaultWorkgroupOffset, "a workgroup starts at the next block's offset of the global scan", "workgroup-offset"},
    {layout::kFaultGlobalRace, "every invocation stores its workgroup's block sum, not the first alone", "global-race", false, FaultNeeds::kNothing, true},
    {layout::kFaultOutOfBounds, "a flag is loaded before the bounds check, past the stream's end", "out-of-bounds", false, FaultNeeds::kNothing,
     true},
    {layout::kFaultUndefinedValue, "the first workgroup's running offset is never set", "undefined-value", false, FaultNeeds::kNothing, true},
    {layout::kFaultLinearLanes, "the scan's slots are handed out by local index, as if lanes were local ids in order", "linear-lanes", false,
     FaultNeeds::kNothing, true},
    {layout::kFaultFarOutOfBounds, "a flag is loaded a block past its own, beyond the buffer and its guard words", "far-out-of-bounds",
     false, FaultNeeds::kNothing, true}};
inline constexpr FaultSpec kHashFaults[] = {{1, "the azimuth cell comes from the wrong coordinate pair"},
                                            {2, "the launch row is ignored (--max-groups)", {}, false, FaultNeeds::kRows},
                                            {3, "the direction's cells are interleaved azimuth first"},
                                            RS_APPROX_DIV, RS_APPROX_SQRT};
inline constexpr FaultSpec kCompressFaults[] = {{1, "the last chunk loses its last ray"},
                                                {2, "every chunk but the last reaches one ray into the next"},
                                                {3, "the chunk count is the last chunk's index"},
                                                RS_WORKGROUP_FAULTS};
inline constexpr FaultSpec kSortFaults[] = {{1, "a bin's position is not advanced in the top byte's pass"},
                                            {2, "an element counts itself among the earlier ones of its digit"},
                                            {3, "each digit starts at the next digit's base"},
                                            RS_WORKGROUP_FAULTS};
inline constexpr FaultSpec kDecompressFaults[] = {{1, "the chunk is looked up without the sorted permutation"},
                                                  {2, "the chunk sizes are read in chunk order, not sorted order"},
                                                  {3, "a chunk starts where it ends (the scan read as inclusive)"},
                                                  RS_WORKGROUP_FAULTS};
inline constexpr FaultSpec kBuildFaults[] = {{1, "the float containment checks of each step are skipped"},
                                             {2, "each ray is grown with its predecessor's origin"},
                                             {3, "a parent leaves out its last child"},
                                             {4, "a leaf drops its last ray"},
                                             RS_APPROX_DIV, RS_APPROX_SQRT};
inline constexpr FaultSpec kTraverseFaults[] = {{1, "the top level ignores the triangle sphere's radius"},
                                                {2, "a mask part's start is dropped (--split-bytes)", {}, false, FaultNeeds::kSplit},
                                                {3, "a level skips every parent's first child"},
                                                {4, "each top-level run leaves its last slot unwritten"},
                                                {layout::kFaultSqrtHigh, "every sqrt two ULP high, as a GPU may", "sqrt-high"}};
inline constexpr FaultSpec kReduceFaults[] = {{1, "the last element of every segment is dropped"},
                                              {2, "each scan block starts at the previous block's offset (--reduction scan)", {}, false,
                                               FaultNeeds::kScanReduction},
                                              {3, "each segment is copied from one value late"},
                                              RS_WORKGROUP_FAULTS};
#undef RS_WORKGROUP_FAULTS
// Mirrored by the emulated kernel (emu/src/traverse_compact_wg.cpp).
inline constexpr FaultSpec kTraverseCompactFaults[] = {
    {1, "each block's survivors land at the next block's offset (the block scan read as inclusive)", {}, true},
    {2, "the last survivor of every block is dropped", {}, true},
    {3, "every round of a block starts at the block's start (the carry between rounds is dropped)", {}, true},
    {4, "each block reports its survivors as its tests", {}, true},
    {5, "the top level's group cull with its margin at -1/2 (culls groups the cone test hits)", {}, true},
    {6, "below the top, a subgroup's pairs whose parents have as many children are taken to share them", {}, true},
    {7, "at the top, an invocation's triangles all taken to be of its first triangle's object (the Groups object word)", {}, true}};
inline constexpr FaultSpec kIntersectFaults[] = {{1, "tmin and tmax swapped in the range check"},
                                                 {2, "every paged load reads the first page (--split-bytes)", {}, false, FaultNeeds::kSplit},
                                                 {3, "a node's last ray is never tested"},
                                                 RS_APPROX_DIV,
                                                 {layout::kFaultUlp4, "the distance t is 4 ULP too far (beyond any device)", "ulp4"}};
inline constexpr FaultSpec kTreeRootsFaults[] = {{1, "the last root is never tested"},
                                                 {2, "a slot's node and root are taken in the other order (slot % nodes)"},
                                                 {3, "a hit is counted as a second test"}};
inline constexpr FaultSpec kTreeExpandFaults[] = {{1, "an object node's own triangles are not counted"},
                                                  {2, "a cone node's last child is not counted"},
                                                  {3, "the object side is refined wherever the item is a node"}};
inline constexpr FaultSpec kTreeTestFaults[] = {{1, "a final pair is flagged to go on"},
                                                {2, "each pair's candidates start one slot late"},
                                                {3, "a hit is counted as a second test"}};
inline constexpr FaultSpec kTreeStepFaults[] = {{1, "each block's survivors land at the next block's offset (the block scan read as inclusive)"},
                                                {2, "the last survivor of every block is dropped"},
                                                {3, "every round of a block starts at the block's start (the carry between rounds is dropped)"},
                                                {4, "the final pairs land among the next ones"}};
inline constexpr FaultSpec kIntersectTreeFaults[] = {{1, "a level-1 node's rays after its first are skipped"},
                                                     {2, "tmin and tmax swapped in the range check"},
                                                     {3, "each pair reports one test"}};
inline constexpr FaultSpec kTlListsFaults[] = {{1, "a sphere's escape is one element short (it lands on its subtree's last element)"},
                                              {2, "a triangle is ordered by its first vertex only"},
                                              {3, "every list is ordered along the first list's direction"},
                                              {4, "back-face culling drops the triangles the list's rays meet from the front"}};
inline constexpr FaultSpec kTlHeadsFaults[] = {{1, "the triangle's plane faces the other way (the side the rays reach is skipped)"},
                                              {2, "the facet planes of the opposite class"},
                                              {3, "a window's head one element past the first element kept"}};
inline constexpr FaultSpec kTlCellsFaults[] = {{1, "a cell's first side plane faces the other way"},
                                              {2, "each cell takes the planes of the next cell in x"},
                                              {3, "a window's tail one element short"}};
inline constexpr FaultSpec kTlTraceFaults[] = {{1, "a missed sphere's escape is followed one element short"},
                                              {2, "the sphere test's distance check is flipped"},
                                              {3, "a ray walks the list of the opposite direction"},
                                              {4, "one-sided triangles count when met from behind, not from the front"},
                                              {5, "a ray walks the window of the other side of its triangle"},
                                              {6, "an eye ray walks the window of the next cell"}};
inline constexpr FaultSpec kGridCountFaults[] = {{1, "a triangle's rectangle of cells loses its last column"},
                                                {2, "the least distance is taken to the triangle's first vertex, not its closest point"},
                                                {3, "the regular grid's cells stop one layer short along z"}};
inline constexpr FaultSpec kGridEmitFaults[] = {{1, "an inclusive scan where an exclusive one belongs (a triangle writes at the next one's offset)"},
                                                {2, "a reference's cell is the next one (one column off)"},
                                                {3, "a reference's rectangle has its u and v swapped"}};
inline constexpr FaultSpec kGridCellsFaults[] = {{1, "a cell's offset is its upper bound (every list starts one cell late)"},
                                                 {2, "a cell's least distance leaves out its last triangle"},
                                                 {3, "the references are gathered in emit order, not the sorted order"}};
inline constexpr FaultSpec kGridTraceFaults[] = {{1, "a shadow ray's perspective cell is one column off"},
                                                {2, "a cell's least distance is taken 1/64 too far (rays skip tests they need)"},
                                                {3, "the 3D walk skips the next slice whenever it steps along z"},
                                                {4, "the last triangle of every cell is never tested"},
                                                {5, "a 3D perspective walk skips the next depth slice when it steps away from the centre"},
                                                {6, "a 3D perspective walk's early exit takes t linear in the perspective fraction"}};
inline constexpr FaultSpec kShadeFaults[] = {{1, "the quadratic attenuation uses the distance, not its square"},
                                             {2, "the light vector points from the light to the surface"},
                                             {3, "the blue channel is never accumulated"},
                                             {4, "an area light's sample lit from the next sample's point"},
                                             {5, "an area light's samples not divided by their count"},
                                             RS_APPROX_DIV, RS_APPROX_SQRT};
inline constexpr FaultSpec kResolveFaults[] = {{1, "the gamma step is skipped"},
                                               {2, "the value is truncated, not rounded"},
                                               {3, "red and blue swapped"}};
#undef RS_APPROX_DIV
#undef RS_APPROX_SQRT
}  // namespace pass_registry_detail

#define RS_PUSH(T) #T, sizeof(layout::T)
// clang-format off
inline constexpr std::array<PassSpec, kPassCount> kPasses = {{
  // id                       name                 kernel               graphics phases                                   bindings                    push                        calls                                       thesis phase                 faults
  {PassId::kRaster,           "raster",            "raster",            true,  {},                                        5,                          "", 0,                      pass_registry_detail::kRasterCalls,        "",                          pass_registry_detail::kRasterFaults},
  {PassId::kSurfaces,         "surfaces",          "surfaces",          false, {},                                        layout::kSurfacesBindings,     RS_PUSH(SurfacesPush),      pass_registry_detail::kSurfacesCalls,      "",                          pass_registry_detail::kSurfacesFaults},
  {PassId::kSurfacesHits,     "surfaces.hits",     "surfaces_hits",     false, {},                                        layout::kSurfacesHitsBindings, RS_PUSH(SurfacesHitsPush),  pass_registry_detail::kSurfacesHitsCalls,  "",                          pass_registry_detail::kSurfacesHitsFaults},
  {PassId::kRaygenShadow,     "raygen.shadow",     "raygen_shadow",     false, {},                                        layout::kRaygenBindings,       RS_PUSH(RaygenShadowPush),  pass_registry_detail::kRaygenCalls,        "ray_creation",              pass_registry_detail::kRaygenShadowFaults},
  {PassId::kRaygenReflection, "raygen.reflection", "raygen_reflection", false, {},                                        layout::kRaygenBindings,       RS_PUSH(RaygenPush),        pass_registry_detail::kRaygenCalls,        "ray_creation",              pass_registry_detail::kRaygenReflectionFaults},
  {PassId::kRaygenRefraction, "raygen.refraction", "raygen_refraction", false, {},                                        layout::kRaygenBindings,       RS_PUSH(RaygenPush),        pass_registry_detail::kRaygenCalls,        "ray_creation",              pass_registry_detail::kRaygenRefractionFaults},
  {PassId::kTrim,             "trim",              "trim",              false, pass_registry_detail::kTrimPhases,        layout::kTrimBindings,         RS_PUSH(TrimPush),          pass_registry_detail::kTrimCalls,          "ray_creation",              pass_registry_detail::kTrimFaults},
  {PassId::kHash,             "hash",              "hash",              false, {},                                        layout::kHashBindings,         RS_PUSH(HashPush),          pass_registry_detail::kHashCalls,          "ray_compression",           pass_registry_detail::kHashFaults},
  {PassId::kCompress,         "compress",          "sort",              false, pass_registry_detail::kCompressPhases,    layout::kSortBindings,         RS_PUSH(SortPush),          pass_registry_detail::kCompressCalls,      "ray_compression",           pass_registry_detail::kCompressFaults},
  {PassId::kSort,             "sort",              "sort",              false, pass_registry_detail::kSortPhases,        layout::kSortBindings,         RS_PUSH(SortPush),          pass_registry_detail::kSortCalls,          "ray_sorting",               pass_registry_detail::kSortFaults},
  {PassId::kDecompress,       "decompress",        "sort",              false, pass_registry_detail::kDecompressPhases,  layout::kSortBindings,         RS_PUSH(SortPush),          pass_registry_detail::kDecompressCalls,    "ray_decompression",         pass_registry_detail::kDecompressFaults},
  {PassId::kBuild,            "build",             "build",             false, pass_registry_detail::kBuildPhases,       layout::kBuildBindings,        RS_PUSH(BuildPush),         pass_registry_detail::kBuildCalls,         "hierarchy_creation",        pass_registry_detail::kBuildFaults},
  {PassId::kTraverse,         "traverse",          "traverse",          false, pass_registry_detail::kTraversePhases,    layout::kTraverseBindings,     RS_PUSH(TraversePush),      pass_registry_detail::kTraverseCalls,      "hierarchy_traversal",       pass_registry_detail::kTraverseFaults},
  {PassId::kReduce,           "reduce",            "reduce",            false, pass_registry_detail::kReducePhases,      layout::kReduceBindings,       RS_PUSH(ReducePush),        pass_registry_detail::kReduceCalls,        "hierarchy_traversal",       pass_registry_detail::kReduceFaults},
  {PassId::kTraverseCompact,  "traverse.compact",  "traverse_compact",  false, pass_registry_detail::kTraverseCompactPhases, layout::kTraverseCompactBindings, RS_PUSH(TraverseCompactPush), pass_registry_detail::kTraverseCompactCalls, "hierarchy_traversal", pass_registry_detail::kTraverseCompactFaults},
  {PassId::kIntersect,        "intersect",         "intersect",         false, {},                                        layout::kIntersectBindings,    RS_PUSH(IntersectPush),     pass_registry_detail::kIntersectCalls,     "final_intersection_tests",  pass_registry_detail::kIntersectFaults},
  {PassId::kTreeRoots,        "tree.roots",        "tree_roots",        false, {},                                        layout::kTreeBindings,         RS_PUSH(TreePush),          pass_registry_detail::kTreeRootsCalls,     "hierarchy_traversal",       pass_registry_detail::kTreeRootsFaults},
  {PassId::kTreeExpand,       "tree.expand",       "tree_expand",       false, {},                                        layout::kTreeBindings,         RS_PUSH(TreePush),          pass_registry_detail::kTreeExpandCalls,    "hierarchy_traversal",       pass_registry_detail::kTreeExpandFaults},
  {PassId::kTreeTest,         "tree.test",         "tree_test",         false, {},                                        layout::kTreeBindings,         RS_PUSH(TreePush),          pass_registry_detail::kTreeTestCalls,      "hierarchy_traversal",       pass_registry_detail::kTreeTestFaults},
  {PassId::kTreeStep,         "tree.step",         "tree_step",         false, pass_registry_detail::kTreeStepPhases,    layout::kTreeBindings,         RS_PUSH(TreePush),          pass_registry_detail::kTreeStepCalls,      "hierarchy_traversal",       pass_registry_detail::kTreeStepFaults},
  {PassId::kIntersectTree,    "intersect.tree",    "intersect_tree",    false, {},                                        layout::kIntersectTreeBindings, RS_PUSH(IntersectTreePush), pass_registry_detail::kIntersectTreeCalls, "final_intersection_tests",  pass_registry_detail::kIntersectTreeFaults},
  {PassId::kTlLists,         "tl.lists",          "tl_lists",          false, pass_registry_detail::kTlListsPhases,     layout::kTlListsBindings,      RS_PUSH(TlListsPush),       pass_registry_detail::kTlListsCalls,       "hierarchy_creation",        pass_registry_detail::kTlListsFaults},
  {PassId::kTlHeads,          "tl.heads",          "tl_heads",          false, {},                                        layout::kTlHeadsBindings,      RS_PUSH(TlHeadsPush),       pass_registry_detail::kTlHeadsCalls,       "hierarchy_creation",        pass_registry_detail::kTlHeadsFaults},
  {PassId::kTlCells,          "tl.cells",          "tl_cells",          false, {},                                        layout::kTlCellsBindings,      RS_PUSH(TlCellsPush),       pass_registry_detail::kTlCellsCalls,       "hierarchy_creation",        pass_registry_detail::kTlCellsFaults},
  {PassId::kTlTrace,          "tl.trace",          "tl_trace",          false, {},                                        layout::kTlTraceBindings,      RS_PUSH(TlTracePush),       pass_registry_detail::kTlTraceCalls,       "hierarchy_traversal",       pass_registry_detail::kTlTraceFaults},
  {PassId::kGridCount,        "grid.count",        "grid_build",        false, pass_registry_detail::kGridCountPhases,   layout::kGridBuildBindings,    RS_PUSH(GridBuildPush),     pass_registry_detail::kGridCountCalls,     "hierarchy_creation",        pass_registry_detail::kGridCountFaults},
  {PassId::kGridEmit,         "grid.emit",         "grid_build",        false, pass_registry_detail::kGridEmitPhases,    layout::kGridBuildBindings,    RS_PUSH(GridBuildPush),     pass_registry_detail::kGridEmitCalls,      "hierarchy_creation",        pass_registry_detail::kGridEmitFaults},
  {PassId::kGridCells,        "grid.cells",        "grid_build",        false, pass_registry_detail::kGridCellsPhases,   layout::kGridBuildBindings,    RS_PUSH(GridBuildPush),     pass_registry_detail::kGridCellsCalls,     "hierarchy_creation",        pass_registry_detail::kGridCellsFaults},
  {PassId::kGridTrace,        "grid.trace",        "grid_trace",        false, {},                                        layout::kGridTraceBindings,    RS_PUSH(GridTracePush),     pass_registry_detail::kGridTraceCalls,     "hierarchy_traversal",       pass_registry_detail::kGridTraceFaults},
  {PassId::kShade,            "shade",             "shade",             false, {},                                        layout::kShadeBindings,        RS_PUSH(ShadePush),         pass_registry_detail::kShadeCalls,         "",                          pass_registry_detail::kShadeFaults},
  {PassId::kResolve,          "resolve",           "resolve",           false, {},                                        layout::kResolveBindings,      RS_PUSH(ElementwisePush),      pass_registry_detail::kResolveCalls,       "",                          pass_registry_detail::kResolveFaults},
}};
// clang-format on
#undef RS_PUSH

constexpr const PassSpec& Pass(PassId id) { return kPasses[static_cast<std::size_t>(id)]; }

// The registered pass of this name, or nothing.
constexpr std::optional<PassId> FindPass(std::string_view name) {
  for (const PassSpec& p : kPasses)
    if (p.name == name) return p.id;
  return std::nullopt;
}

// The first registered pass that lists a backend call (e.g. "resolve"), or nothing.
constexpr std::optional<PassId> PassOfCall(std::string_view call) {
  for (const PassSpec& p : kPasses)
    for (const CallSpec& c : p.calls)
      if (c.name == call) return p.id;
  return std::nullopt;
}

// The pass a frame label such as "traverse.L2.shadow.b0" or "raygen.shadow.b0" belongs to: the
// longest registered name that is the label or a dot-separated prefix of it.
constexpr std::optional<PassId> PassOfLabel(std::string_view label) {
  std::optional<PassId> best;
  std::size_t best_len = 0;
  for (const PassSpec& p : kPasses) {
    const std::size_t n = p.name.size();
    if (label.substr(0, n) == p.name && (label.size() == n || label[n] == '.') && n > best_len) {
      best = p.id;
      best_len = n;
    }
  }
  return best;
}

// The passes whose launch an option decides rather than the scene: `runs_with` says so to a person
// (the refusal of a --kernel the run never launched), `example` is the render options of one run that
// launches the pass on a scene with reflective and transparent materials (cli.kernel.reach runs each).
// The passes not listed run in every frame that has their rays.
struct PassReach {
  PassId id;
  std::string_view runs_with;
  std::string_view example;
};
inline constexpr PassReach kPassReach[] = {
    {PassId::kHash, "--algo crsh, rah or rah-quadtree", "--algo crsh"},
    {PassId::kCompress, "--algo crsh, rah or rah-quadtree", "--algo crsh"},
    {PassId::kSort, "--algo crsh, rah, rah-quadtree or grid", "--algo crsh"},
    {PassId::kDecompress, "--algo crsh, rah or rah-quadtree", "--algo crsh"},
    {PassId::kBuild, "--algo crsh, rah or rah-quadtree", "--algo crsh"},
    {PassId::kTraverse, "--algo crsh, rah or rah-quadtree and --path passes", "--algo crsh --path passes"},
    {PassId::kReduce, "--path passes and --algo crsh, rah or rah-quadtree", "--algo crsh --path passes"},
    {PassId::kTraverseCompact, "--path fused and --algo crsh, rah or rah-quadtree", "--algo crsh --path fused --objects flat"},
    {PassId::kIntersect, "--algo crsh, rah or rah-quadtree with the flat descent (--objects flat)", "--algo crsh --objects flat"},
    {PassId::kTreeRoots, "--objects tree --path passes", "--objects tree --path passes"},
    {PassId::kTreeExpand, "--objects tree --path passes", "--objects tree --path passes"},
    {PassId::kTreeTest, "--objects tree --path passes", "--objects tree --path passes"},
    {PassId::kIntersectTree, "--objects tree", "--objects tree"},
    {PassId::kTreeStep, "--objects tree --path fused", "--objects tree --path fused"},
    {PassId::kTlLists, "--algo tl", "--algo tl"},
    {PassId::kTlTrace, "--algo tl", "--algo tl"},
    {PassId::kTlHeads, "--algo tl --polygon-heads regular or simple", "--algo tl --polygon-heads regular"},
    {PassId::kTlCells, "--algo tl --primary tl --frustum-cull on", "--algo tl --primary tl --frustum-cull on"},
    {PassId::kGridCount, "--algo grid", "--algo grid"},
    {PassId::kGridEmit, "--algo grid", "--algo grid"},
    {PassId::kGridCells, "--algo grid", "--algo grid"},
    {PassId::kGridTrace, "--algo grid", "--algo grid"},
    {PassId::kRaygenReflection, "a reflective material", ""},
    {PassId::kRaygenRefraction, "a transparent material", ""},
    {PassId::kSurfacesHits, "a reflective or transparent material", ""},
};

// The reach of a pass, or nothing when every frame with its rays launches it.
constexpr const PassReach* ReachOf(PassId id) {
  for (const PassReach& r : kPassReach)
    if (r.id == id) return &r;
  return nullptr;
}

// A call listed by several passes is one per ray kind, in kind order.
static_assert(static_cast<int>(PassId::kRaygenReflection) - static_cast<int>(PassId::kRaygenShadow) ==
                  static_cast<int>(layout::kRayReflection - layout::kRayShadow) &&
              static_cast<int>(PassId::kRaygenRefraction) - static_cast<int>(PassId::kRaygenShadow) ==
                  static_cast<int>(layout::kRayRefraction - layout::kRayShadow) && layout::kRayShadow == 0);

// Registry invariants that hold at compile time: ids in order, names unique, a pass's own faults
// numbered 1..n and below the named faults' numbers (workgroup and device-like faults).
namespace pass_registry_detail {
constexpr bool Valid() {
  for (std::size_t i = 0; i < kPasses.size(); ++i) {
    if (static_cast<std::size_t>(kPasses[i].id) != i || kPasses[i].name.empty() || kPasses[i].kernel.empty()) return false;
    for (std::size_t j = 0; j < i; ++j)
      if (kPasses[j].name == kPasses[i].name) return false;
    for (std::size_t f = 0; f < kPasses[i].faults.size(); ++f) {
      const FaultSpec& fs = kPasses[i].faults[f];
      if (fs.name.empty() ? fs.number != f + 1 || fs.number >= layout::kFaultDroppedBarrier
                          : fs.number < layout::kFaultDroppedBarrier || fs.number > layout::kFaultSqrtHigh)
        return false;
    }
    if (!kPasses[i].graphics && (kPasses[i].push_bytes == 0 || kPasses[i].push_bytes > 128)) return false;
  }
  return true;
}
static_assert(Valid(), "pass registry: ids out of order, a duplicate name, faults misnumbered or a bad push block");
}  // namespace pass_registry_detail

}  // namespace rayspace
