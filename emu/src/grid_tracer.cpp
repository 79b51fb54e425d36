// The perspective grids as a frame's tracer (rayspace/emu/grid/tracer.h).
#include "rayspace/emu/grid/tracer.h"

#include <chrono>
#include <cstring>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/output_checks.h"

namespace rayspace::emu {
namespace {

class Grid final : public GridTracer {
 public:
  Grid(const SceneBuffers& scene, const grid::Options& options, HierarchyPasses& passes)
      : scene_(scene),
        options_(options),
        checked_(&passes != &EmuHierarchyPasses() ? CheckedHierarchyPasses(passes) : nullptr),
        passes_(checked_ ? *checked_ : passes) {
    // The render path on the emulator: cells' triangles in lanes (PassGridTraceLanes), the same
    // walks as the pass; a backend, or the pass wrapped (checks, planted faults), gets the pass.
    if (options_.lanes && &passes == &EmuHierarchyPasses()) lanes_ = PrepareGridLanes(scene.triangles);
  }

  std::string Name() const override { return "grid"; }
  void Describe(nlohmann::json& out) const override {
    out["algorithm"] = "grid";
    out["perspective_cells_per_face"] = options_.cells;
    out["regular_cells_longest_side"] = options_.regular;
    if (options_.regular_cells) out["regular_cells_target"] = options_.regular_cells;
    out["closed_models"] = options_.closed;
    out["secondary_grid"] = options_.secondary_perspective ? "perspective" : "regular";
    out["area_grid"] = options_.area_perspective ? fmt::format("{0}x{0}x{1}", options_.area_cells, options_.area_depth) : "regular";
    if (built_) {
      const glm::uvec4 d = grids_.volume_dims[0];
      out["regular_dims"] = {d.x, d.y, d.z};
      out["regular_cells_longest_side"] = std::max({d.x, d.y, d.z});
      out["perspective_cells"] = grids_.perspective_cells;
      out["perspective_triangle_refs"] = grids_.perspective_refs;
      out["regular_cells"] = grids_.regular_cells;
      out["regular_triangle_refs"] = grids_.regular_refs;
      if (grids_.volume_cells) {
        out["area_grid_cells"] = grids_.volume_cells;
        out["area_grid_triangle_refs"] = grids_.volume_refs;
      }
      out["build_ms"] = build_ms_;
    }
    out["backend"] = passes_.Name();
  }
  void BeginBatch(const BatchContext& ctx) override { ctx_ = ctx; }
  const std::vector<GridBatchStats>& Stats() const override { return stats_; }
  const GridArrays& Grids() const override { return grids_; }
  double BuildMs() const override { return build_ms_; }

  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    GridWalks w = Trace(rays, 0);
    hits = std::move(w.hits);
  }
  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) override {
    GridWalks w = Trace(rays, 1);
    occluded = std::move(w.occluded);
  }

 private:
  // The grids depend on the scene and its lights alone: built on the host before the first batch
  // (a frame with nothing to trace builds none), timed as the sub-pass "grid.build".
  void Build(const layout::FrameConstants* eye_frame = nullptr) {
    const auto t0 = std::chrono::steady_clock::now();
    // --grid-secondary perspective: the 3D grid about the frame's eye.
    const glm::vec3 secondary_eye = ctx_.frame ? Xyz(ctx_.frame->eye) : glm::vec3(0.0f);
    const glm::vec3* secondary = options_.secondary_perspective && ctx_.frame ? &secondary_eye : nullptr;
    secondary_eye_ = secondary_eye;
    if (eye_frame) {
      // The eye's grid: cells of about 100 x 100 pixels (grid::EyeCells) from the frame's pixel steps.
      const layout::FrameConstants& f = *eye_frame;
      const glm::dvec3 centre = glm::dvec3(Xyz(f.pixel_origin)) + glm::dvec3(Xyz(f.pixel_dx)) * (0.5 * f.dims.x) +
                                glm::dvec3(Xyz(f.pixel_dy)) * (0.5 * f.dims.y);
      const double tan_half = glm::length(glm::dvec3(Xyz(f.pixel_dy))) * 0.5 * f.dims.y / glm::length(centre);
      const glm::vec3 eye = Xyz(f.eye);
      eye_frame_ = f;
      grids_ = BuildGrids(grid::Plan(scene_, options_, &eye, grid::EyeCells(f.dims.y, tan_half), secondary));
    } else {
      grids_ = BuildGrids(grid::Plan(scene_, options_, nullptr, 0, secondary));
    }
    build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    built_ = true;
    // The eye's grid timed apart ("grid.build.eye"), "grid.build" the rest: the lights', the regular
    // grid and the 3D grids.
    if (ctx_.subpasses && grids_.eye != layout::kGridNoLight) {
      const std::size_t n = grids_.light_grids[grids_.eye].y, eye_cells = layout::kGridFaces * n * n;
      ctx_.subpasses->push_back({"grid.build", build_ms_ - eye_build_ms_, grids_.first.size() - 1 - eye_cells});
      ctx_.subpasses->push_back({"grid.build.eye", eye_build_ms_, eye_cells});
    } else if (ctx_.subpasses) {
      ctx_.subpasses->push_back({"grid.build", build_ms_, grids_.first.size() - 1});
    }
  }
  // The render path on the emulator bins on the host (grid::Build's functions, in parallel runs);
  // a backend, `diff` and --path passes run the build's passes, grid by grid: grid.count, grid.emit,
  // the sort by cell, grid.cells. Both give the same arrays (tests/grid_build_test.cpp).
  GridArrays BuildGrids(grid::GridPlan plan) {
    eye_build_ms_ = 0;
    if (lanes_) return grid::Build(scene_, std::move(plan), &eye_build_ms_);
    return BuildWithPasses(scene_, std::move(plan), passes_, &eye_build_ms_);
  }
  GridWalks Trace(const std::vector<layout::Ray>& rays, std::uint32_t shadow) {
    // Eye rays (--primary grid) go through the eye's grid, built again whenever the camera changes.
    const bool primary = ctx_.kind == layout::kRayPrimary && ctx_.frame;
    if (primary && (grids_.eye == layout::kGridNoLight || std::memcmp(&eye_frame_, ctx_.frame, sizeof eye_frame_) != 0))
      Build(ctx_.frame);
    // The eye's 3D grid, once a frame's eye is known, again whenever it moves.
    const bool stale = options_.secondary_perspective && ctx_.frame &&
                       (grids_.secondary == layout::kGridNoLight || Xyz(ctx_.frame->eye) != secondary_eye_);
    if (!built_ || stale) Build(grids_.eye != layout::kGridNoLight ? &eye_frame_ : nullptr);
    const std::string label = "grid.trace." + ctx_.name;
    passes_.Label(label);
    const auto t0 = std::chrono::steady_clock::now();
    const call::GridTrace call{.first = grids_.first,
                                     .cell_triangles = grids_.triangles,
                                     .min_dist = grids_.min_dist,
                                     .boxes = grids_.boxes,
                                     .light_grids = grids_.light_grids,
                                     .origins = grids_.origins,
                                     .volume = grids_.volume,
                                     .volume_dims = grids_.volume_dims,
                                     .slices = grids_.slices,
                                     .triangles = scene_.triangles,
                                     .rays = rays,
                                     .shadow = shadow,
                                     .closed = options_.closed ? 1u : 0u,
                                     .eye = grids_.eye,
                                     .secondary = grids_.secondary};
    GridWalks w = lanes_ ? PassGridTraceLanes(call, *lanes_) : passes_.GridTrace(call);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ctx_.subpasses) ctx_.subpasses->push_back({label, ms, rays.size()});
    if (ctx_.digest) {
      if (shadow)
        ctx_.digest->Add(label, "occluded", w.occluded);
      else
        ctx_.digest->Add(label, "hits", w.hits);
      ctx_.digest->Add(label, "steps", w.steps);
      ctx_.digest->Add(label, "tests", w.tests);
    }
    Count(rays, shadow, w);
    return w;
  }
  void Count(const std::vector<layout::Ray>& rays, std::uint32_t shadow, const GridWalks& w) {
    GridBatchStats s;
    s.name = ctx_.name;
    s.kind = ctx_.kind;
    s.rays = rays.size();
    s.has_core_steps = w.core_steps.size() == rays.size();
    for (std::size_t i = 0; i < rays.size(); ++i) {
      s.steps += w.steps[i];
      s.tests += w.tests[i];
      if (shadow && rays[i].info.z == layout::kRayShadow && rays[i].info.w < scene_.lights.size() &&
          scene_.lights[rays[i].info.w].sampling.x != layout::kLightPoint) {
        ++s.area_rays;
        s.area_steps += w.steps[i];
        if (i < w.core_steps.size()) s.area_core_steps += w.core_steps[i];
        s.area_tests += w.tests[i];
        s.volume_rays += grid::VolumeGridOf(rays[i], true, grids_.light_grids, grids_.secondary) != layout::kGridNoLight;
        continue;
      }
      if (!shadow && grid::VolumeGridOf(rays[i], false, grids_.light_grids, grids_.secondary) != layout::kGridNoLight) {
        ++s.volume_rays;
        continue;
      }
      if (grid::PerspectiveGridOf(rays[i], shadow != 0u, grids_.light_grids, grids_.origins, grids_.eye) == layout::kGridNoLight) continue;
      ++s.perspective_rays;
      if (!shadow || w.occluded[i]) continue;
      ++s.unoccluded_perspective_rays;
      s.skipped_rays += w.tests[i] == 0u;
    }
    stats_.push_back(std::move(s));
  }

  const SceneBuffers& scene_;
  grid::Options options_;
  std::unique_ptr<HierarchyPasses> checked_;  // a backend's outputs checked (emu/output_checks.h)
  HierarchyPasses& passes_;
  std::optional<GridLanes> lanes_;
  GridArrays grids_;
  layout::FrameConstants eye_frame_{};  // the frame the eye's grid was built for
  glm::vec3 secondary_eye_{0.0f};       // the eye the 3D grid for reflection and refraction rays is about
  double build_ms_ = 0.0;
  double eye_build_ms_ = 0.0;  // of build_ms_, the eye's grid
  bool built_ = false;
  BatchContext ctx_;
  std::vector<GridBatchStats> stats_;
};

}  // namespace

GridArrays BuildWithPasses(const SceneBuffers& scene, grid::GridPlan plan, HierarchyPasses& passes, double* eye_ms) {
  for (std::size_t k = 0; k < plan.grids.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const grid::GridDescriptor d = grid::Describe(plan.grids[k]);
    passes.Label("grid.count");
    const GridCounts counts = passes.GridCount({.triangles = scene.triangles, .grid = d.params, .shape = d.shape, .slices = plan.arrays.slices});
    passes.Label("grid.emit");
    const GridRefs refs =
        passes.GridEmit({.grid = d.params, .shape = d.shape, .counts = counts.counts, .spans = counts.spans, .span_boxes = counts.span_boxes});
    passes.Label("grid.sort");
    const std::vector<std::uint32_t> order = passes.SortChunks({.chunk_key = refs.cells});
    passes.Label("grid.cells");
    const GridLists lists = passes.GridCells({.cells = refs.cells,
                                              .triangles = refs.triangles,
                                              .boxes = refs.boxes,
                                              .order = order,
                                              .dist = counts.dist,
                                              .cell_count = static_cast<std::uint32_t>(plan.cells[k])});
    grid::AppendLists(plan.arrays, plan.grids[k], plan.cells[k], lists);
    if (eye_ms && k == plan.eye_grid) *eye_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  grid::FinishLists(plan.arrays);
  return std::move(plan.arrays);
}

std::unique_ptr<GridTracer> MakeGridTracer(const SceneBuffers& scene, const grid::Options& options, HierarchyPasses* passes) {
  return std::make_unique<Grid>(scene, options, passes ? *passes : EmuHierarchyPasses());
}

}  // namespace rayspace::emu
