// `--algo grid`: a frame's rays through Hunt and Mark's perspective grids (docs/grids.md). The grids
// are built on the host once per scene (grid::Build); each batch is one grid.trace call on the backend
// the frame runs (the emulator or the Vulkan kernel), so `diff` compares it as any other pass.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/tracer.h"

namespace rayspace::emu {

// One batch through the grids: its rays, those that went through a perspective grid (point-light
// shadow rays, eye rays) and a 3D perspective grid (area-light shadow rays), those of them not occluded and of these the ones whose cell's least distance spared
// every test, the cells visited and the triangles tested.
struct GridBatchStats {
  std::string name;  // e.g. "shadow.b0"
  std::uint32_t kind = 0;
  std::uint64_t rays = 0, perspective_rays = 0, skipped_rays = 0, unoccluded_perspective_rays = 0, steps = 0, tests = 0;
  // Area-light shadow rays, their cells and tests, and how many of them went through a 3D
  // perspective grid (all, unless --grid-area regular).
  std::uint64_t area_rays = 0, area_steps = 0, area_tests = 0, volume_rays = 0;
  // Of area_steps, those in the lights' core cubes (the regular grid's cells); has_core_steps: the
  // walks counted them (the emulator's pass does; a backend's kernel does not report them).
  std::uint64_t area_core_steps = 0;
  bool has_core_steps = false;
};

class GridTracer : public Tracer {
 public:
  virtual const std::vector<GridBatchStats>& Stats() const = 0;
  // The grids' sizes (zero until built) and the host build's time.
  virtual const GridArrays& Grids() const = 0;
  virtual double BuildMs() const = 0;
};

// `passes` null: the emulator's.
// A plan's grids built by the build's passes on `passes`, grid by grid: grid.count, grid.emit, the
// sort by cell, grid.cells (labelled so; what `diff` compares). The same arrays as grid::Build.
GridArrays BuildWithPasses(const SceneBuffers& scene, grid::GridPlan plan, HierarchyPasses& passes, double* eye_ms = nullptr);

std::unique_ptr<GridTracer> MakeGridTracer(const SceneBuffers& scene, const grid::Options& options, HierarchyPasses* passes = nullptr);

}  // namespace rayspace::emu
