#include "rayspace/frame/frame_args.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/scene.h"

#ifdef RAYSPACE_HAVE_VULKAN
#include "rayspace/gpu/requirements.h"
#endif

namespace rayspace::app {

std::vector<std::string> AlgorithmNames() {
  std::vector<std::string> names;
  for (const Algorithm& a : kAlgorithms) names.emplace_back(a.name);
  return names;
}

const Algorithm* FindAlgorithm(std::string_view name) {
  for (const Algorithm& a : kAlgorithms)
    if (a.name == name) return &a;
  return nullptr;
}


// One top node and one triangle can leave subdivision^(levels-1) pairs at level 1, and a block that
// small is never split further: a smaller capacity would fail mid-frame, so it is refused first.
void CheckPairCapacity(std::size_t capacity, int subdivision, int levels) {
  std::size_t need = 1;
  for (int L = 1; L < levels && need <= capacity; ++L) need *= static_cast<std::size_t>(subdivision);
  if (capacity < need)
    ThrowInput("--pair-capacity {}: too small for subdivision {} with {} levels; give at least {} (subdivision^(levels-1))",
               capacity, subdivision, levels, need);
}

void ValidateFrameArgs(const FrameArgs& args) {
  OneSided(args);
  emu::FrameOptions scratch;
  ApplyPrimary(args, scratch);
  // rah-quadtree and --levels auto take their levels from the image size, known with the scene.
  if (args.Hierarchy() && args.algo != "rah-quadtree" && !args.depth_auto) CheckPairCapacity(args.pair_capacity, args.subdivision, args.depth);
}

emu::HierarchyConfig MakeHierarchyConfig(const FrameArgs& args, int width, int height, emu::HierarchyPasses* passes) {
  emu::HierarchyConfig hc;
  hc.algorithm = args.algo == "crsh" ? emu::Algorithm::kCrsh
                 : args.algo == "rah" ? emu::Algorithm::kRah
                                      : emu::Algorithm::kRahQuadtree;
  hc.subdivision = args.subdivision;
  hc.depth = args.depth_auto ? emu::AutoLevels(static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height), hc.subdivision)
                             : args.depth;
  if (hc.algorithm == emu::Algorithm::kRahQuadtree) {
    // Roger et al.: 2x2 tiles up to the whole image, depth log2 of the image size.
    hc.subdivision = 4;
    if (!args.depth_given || args.depth_auto) hc.depth = static_cast<int>(std::ceil(std::log2(std::max(width, height))));
    hc.depth = std::max(hc.depth, 1);
  }
  CheckPairCapacity(args.pair_capacity, hc.subdivision, hc.depth);
  hc.reduction = args.reduction == "scan" ? emu::Reduction::kScan : emu::Reduction::kHierarchical;
  hc.component_size = args.component_size;
  hc.pair_capacity = args.pair_capacity;
  hc.object_tree = args.objects == "tree";
  // auto runs the tree where it exists: on the emulator's own passes (docs/object-tree.md, "Which one").
  if (args.objects == "auto" && passes == nullptr) {
    hc.auto_tree_spread = emu::kAutoTreeSpread;
    hc.auto_tree_triangles = emu::kAutoTreeTriangles;
  }
  hc.object_tree_options.leaf_triangles = args.tree_leaf;
  hc.object_tree_options.big_fraction = args.tree_big;
  hc.image_width = width;
  hc.image_height = height;
  hc.passes = passes;
  ApplyFaithful(args.faithful, hc);
  return hc;
}

std::string ParseGridArea(const std::string& text, emu::grid::Options& o) {
  if (text == "regular") {
    o.area_perspective = false;
    return {};
  }
  unsigned a = 0, b = 0, d = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%ux%ux%u%c", &a, &b, &d, &tail) != 3)
    return fmt::format("'{}' is neither NxNxD (cells per face side, twice, then depth slices) nor 'regular'", text);
  if (a != b) return fmt::format("'{}': a face's cells must be square ({} x {})", text, a, b);
  if (a < 1 || a > 1024 || d < 1 || d > layout::kGridMaxSlices)
    return fmt::format("'{}': cells per side must lie in [1, 1024] and slices in [1, {}]", text, layout::kGridMaxSlices);
  // A grid's cell lists cost about 28 bytes a cell before any reference: 2^24 cells (~0.5 GB) at most.
  if (std::uint64_t{layout::kGridFaces} * a * a * d > (std::uint64_t{1} << 24))
    return fmt::format("'{}': {} cells in six faces, more than 2^24", text, std::uint64_t{layout::kGridFaces} * a * a * d);
  o.area_perspective = true;
  o.area_cells = a;
  o.area_depth = d;
  return {};
}

emu::grid::Options MakeGridOptions(const FrameArgs& args) {
  emu::grid::Options o{args.grid_cells, args.grid_regular, args.closed_models};
  o.area_near = args.grid_area_near;
  o.regular_cells = args.grid_regular_cells;
  o.secondary_perspective = args.grid_secondary == "perspective";
  const std::string e = ParseGridArea(args.grid_area, o);
  RS_CHECK_MSG(e.empty(), "--grid-area: {}", e);  // the option's validator has already refused it
  return o;
}

emu::tl::Options MakeTlOptions(const FrameArgs& args) {
  emu::tl::Options o;
  o.lists = args.lists;
  o.order = args.node_order == "latest-last" ? emu::tl::Order::kLatestLast : emu::tl::Order::kEarliestFirst;
  o.tree.leaf_triangles = args.tree_leaf;
  if (args.tree_big_given) o.tree.big_fraction = args.tree_big;
  o.cull = args.backface_cull == "on";
  o.cells = args.frustum_cull == "on";
  o.heads = args.polygon_heads == "regular" ? layout::kTlHeadsRegular
            : args.polygon_heads == "simple" ? layout::kTlHeadsSimple
                                             : layout::kTlHeadsOff;
  return o;
}

void ApplyPrimary(const FrameArgs& args, emu::FrameOptions& fo) {
  if (args.primary != "raster" && args.algo != args.primary)
    ThrowInput("--primary {0}: only --algo {0} traces eye rays this way (--algo {1} traces secondary rays only)", args.primary, args.algo);
  if (args.frustum_cull == "on" && args.primary != "tl") ThrowInput("--frustum-cull on: needs --primary tl (the eye rays it culls for)");
  fo.trace_primary = args.primary != "raster";
}

bool OneSided(const FrameArgs& args) {
  if (args.backface_cull != "on") return false;
  if (args.algo != "tl")
    ThrowInput("--backface-cull on: only --algo tl traces one-sided triangles (--algo {} meets both sides)", args.algo);
  return true;
}

}  // namespace rayspace::app
