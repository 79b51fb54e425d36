// `--algo tl`: a frame's rays traced through Toczek et al.'s traversal lists. The tree is built on
// the host once per scene (tl::PrepareTree); the lists are the pass tl.lists, run once when the frame
// prepares, and each batch is one tl.trace call, both on the backend the frame runs (the emulator or
// the Vulkan kernels), so `diff` compares them as any other pass.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/emu/tracer.h"

namespace rayspace::emu {

// One batch's walks: per ray kind, and per list the rays that walked it and what they tested.
struct TlBatchStats {
  std::string name;  // e.g. "shadow.b0"
  std::uint32_t kind = 0;
  std::uint64_t rays = 0, spheres = 0, triangles = 0;
  std::vector<std::uint64_t> list_rays, list_spheres, list_triangles;  // per list
  // Per 32 consecutive rays of the batch (a SIMT warp), the elements tested by its longest walk,
  // counted once for each of its rays: the steps a warp takes until its last ray ends.
  std::uint64_t warp_steps = 0;
  // The list entries the walks passed (TlWalks::entries); has_entries: the walks counted them (the
  // emulator's pass does, a backend's kernel does not).
  std::uint64_t entries = 0;
  bool has_entries = false;
};

inline constexpr std::size_t kTlWarpRays = 32;
// Per kTlWarpRays consecutive rays, the most elements (spheres + triangles) one of them tested,
// times the warp's rays; summed over the batch (TlBatchStats::warp_steps).
std::uint64_t WarpSteps(std::span<const std::uint32_t> spheres, std::span<const std::uint32_t> triangles);

// The lists' shape: the tree's nodes and triangle references, K, the bytes of every array
// (tl::Lists::Bytes), and per list its elements and the triangle references culling dropped from
// it (all zero until the lists are built).
struct TlShape {
  std::uint32_t lists = 0, nodes = 0, triangle_refs = 0;
  std::uint64_t bytes = 0;
  bool culled = false;
  std::uint32_t heads = 0;  // layout::kTlHeads*: per-polygon windows of the lists
  std::uint64_t window_bytes = 0;  // tl.heads' windows (0 without heads)
  std::vector<std::uint32_t> list_elements, list_culled;
};

class TlTracer : public Tracer {
 public:
  virtual const std::vector<TlBatchStats>& Stats() const = 0;
  virtual TlShape Shape() const = 0;
};

// `passes` null: the emulator's.
std::unique_ptr<TlTracer> MakeTlTracer(const SceneBuffers& scene, const tl::Options& options, HierarchyPasses* passes = nullptr);

}  // namespace rayspace::emu
