// The options `render` and `diff` share (the frame, its tracer, the Vulkan device): one struct with one
// set of defaults, registered on both commands by one function, so that the two cannot drift apart.
#pragma once
#include <map>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rayspace/frame/backend_setup.h"
#include "rayspace/frame/faithful_args.h"
#include "rayspace/frame/kernel_model.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/tl/tl.h"

namespace rayspace::app {

// The hierarchy's defaults are the emulator's own (emu::HierarchyConfig), so the command line, tests and
// benchmarks build the same frame.
inline const emu::HierarchyConfig kHierarchyDefaults{};

// Every tracer --algo names, once: the option's allowed values, which of them trace with the
// hierarchy, and the configurations `rayspace bench` runs by default all come from this list.
struct Algorithm {
  std::string_view name;
  bool hierarchy;  // traces with the ray-space hierarchy (MakeHierarchyConfig knows it)
};
inline constexpr Algorithm kAlgorithms[] = {
    {"crsh", true}, {"rah", true}, {"rah-quadtree", true}, {"tl", false}, {"grid", false}, {"brute", false}, {"embree", false},
};
// kAlgorithms' names, in order.
std::vector<std::string> AlgorithmNames();
// The entry of kAlgorithms named `name`, or nullptr.
const Algorithm* FindAlgorithm(std::string_view name);

struct FrameArgs {
  std::string algo = "crsh";
  int subdivision = kHierarchyDefaults.subdivision, depth = kHierarchyDefaults.depth;
  bool depth_given = false;  // --levels was given (rah-quadtree otherwise derives it from the image size)
  bool depth_auto = false;   // --levels auto: from the image's pixels (emu::AutoLevels)
  int bounces = -1;          // --bounces: the scene's max_depth unless given
  std::string reduction = "hierarchical";
  std::string objects = "auto";  // --objects flat|tree|auto
  std::uint32_t lists = emu::tl::Options{}.lists;  // --lists (--algo tl)
  std::string node_order = "earliest-first";      // --node-order (--algo tl)
  std::string backface_cull = "off";              // --backface-cull (--algo tl)
  std::string polygon_heads = "off";              // --polygon-heads (--algo tl)
  std::string primary = "raster";                 // --primary raster|tl
  std::string frustum_cull = "off";               // --frustum-cull (--primary tl)
  std::uint32_t grid_cells = emu::grid::Options{}.cells;      // --grid-cells (--algo grid)
  std::uint32_t grid_regular = emu::grid::Options{}.regular;  // --grid-regular (--algo grid)
  std::uint64_t grid_regular_cells = 0;                       // --grid-regular-cells (0: not given)
  bool closed_models = false;                                  // --closed-models (--algo grid)
  std::string grid_area = "200x200x4";                         // --grid-area NxNxD|regular (--algo grid)
  std::uint32_t grid_area_near = emu::grid::Options{}.area_near;  // --grid-area-near (--algo grid)
  std::string grid_secondary = "regular";                           // --grid-secondary (--algo grid)
  std::uint32_t tree_leaf = ObjectTreeOptions{}.leaf_triangles;  // --tree-leaf
  float tree_big = ObjectTreeOptions{}.big_fraction;             // --tree-big
  bool tree_big_given = false;  // --tree-big was given (--algo tl otherwise keeps its own default)
  int component_size = kHierarchyDefaults.component_size;
  std::size_t pair_capacity = kHierarchyDefaults.pair_capacity;
  std::string size, data;
  int device = -1;  // -1: the first non-CPU device, else lavapipe
  std::map<std::string, std::uint64_t> device_lacks;  // --device-lacks (test use)
  std::size_t split_bytes = 0;
  std::uint32_t max_groups = 0;
  KernelFiles kernels;  // --kernel PASS=FILE (Vulkan): user kernels in place of built-in ones
  KernelModelArgs model;  // --schedule, --check-workgroups (the emulated workgroup kernels)
  FaithfulArgs faithful;  // the thesis's hierarchy as printed, its rays and objects

  TestLimits Limits() const { return {split_bytes, max_groups}; }
  // Whether --algo traces with the hierarchy (crsh, rah and rah-quadtree do; brute and embree do not).
  bool Hierarchy() const {
    const Algorithm* a = FindAlgorithm(algo);
    return a && a->hierarchy;
  }
};

// The traversal lists' options (--algo tl): --lists, --node-order, --backface-cull, --polygon-heads,
// --tree-leaf and --tree-big.
emu::tl::Options MakeTlOptions(const FrameArgs& args);
// --grid-area's value into `o`; an error naming the value, or empty.
std::string ParseGridArea(const std::string& text, emu::grid::Options& o);
// The grids' options (--algo grid): --grid-cells and --grid-regular.
emu::grid::Options MakeGridOptions(const FrameArgs& args);
// Whether the frame's triangles are one-sided (SceneBuffers::one_sided): --backface-cull on, which
// only --algo tl traces (InputError for another tracer, which would answer two-sided).
bool OneSided(const FrameArgs& args);
// --primary tl (eye rays traced beside the raster, --algo tl only) and --frustum-cull on (their
// per-cell heads, --primary tl only) into the frame's options; InputError otherwise.
void ApplyPrimary(const FrameArgs& args, emu::FrameOptions& fo);


// Refuses a pair capacity below subdivision^(levels-1), the most pairs one node and one triangle reach.
void CheckPairCapacity(std::size_t capacity, int subdivision, int levels);

// Every check of the options that needs neither the scene nor the device, at once (InputError naming
// the first that fails): the command line runs it right after parsing, before any work. The engines
// check again where they use the options, for callers that never parsed a command line.
void ValidateFrameArgs(const FrameArgs& args);

// The hierarchy tracer's configuration for a frame of width x height, for a hierarchy --algo.
emu::HierarchyConfig MakeHierarchyConfig(const FrameArgs& args, int width, int height, emu::HierarchyPasses* passes);

}  // namespace rayspace::app
