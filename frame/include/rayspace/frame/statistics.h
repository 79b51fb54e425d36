// Intersection statistics counted as the CRSH thesis counts them (docs/hierarchy.md, "Statistics"):
// per ray type and level the node-sphere tests (intersections), survivors (hits) and misses; final
// ray-triangle tests (with --leaf-test ray-sphere, the leaf sphere tests before them); total = every
// level's intersections + leaf sphere tests + final tests (+ the rays' own tests with
// --objects tree, where a level's intersections are its cones' tests against object nodes and
// triangle spheres); brute force = rays x triangles, per ray type (the thesis's per-type shares divide
// by the type's own) and for the whole frame.
#pragma once
#include <cstdio>
#include <map>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/grid/tracer.h"
#include "rayspace/emu/tl/tracer.h"

namespace rayspace::app {

struct Statistics {
  bool hierarchy = false;
  int depth = 0;
  // Per ray type: per level (index L-1) summed over bounces, final tests, rays, brute force.
  struct PerType {
    std::vector<emu::LevelStats> levels;
    std::uint64_t final_tests = 0, rays = 0, brute_force = 0, object_sphere_tests = 0;
    std::uint64_t leaf_sphere_tests = 0;  // --leaf-test ray-sphere
    std::uint64_t tl_sphere_tests = 0;    // --algo tl (final_tests: its triangle tests)
    // --algo tl: the steps of 32-ray warps charged to each of their rays, and the list entries the
    // walks passed (unknown when some batch's walks did not count them: a backend's kernel).
    std::uint64_t tl_warp_steps = 0, tl_entries = 0;
    bool tl_entries_unknown = false;
    // --algo grid (final_tests: its triangle tests): cells visited; point-light shadow rays through a
    // perspective grid, those of them not occluded, and those no triangle test was needed for.
    std::uint64_t grid_steps = 0, grid_perspective_rays = 0, grid_unoccluded_perspective_rays = 0, grid_skipped_rays = 0;
    std::uint64_t grid_area_rays = 0, grid_area_steps = 0, grid_area_tests = 0, grid_volume_rays = 0;
    // Of grid_area_steps, those in the lights' core cubes; unknown when some batch's walks did not
    // count them (a backend's kernel).
    std::uint64_t grid_area_core_steps = 0;
    bool grid_area_core_unknown = false;
    emu::LevelStats ray_level;  // --objects tree
    // Every test of this ray type: its levels, its rays' own (--objects tree) and its final tests.
    std::uint64_t Total() const;
  };
  std::map<std::uint32_t, PerType> types;
  std::vector<emu::BatchStats> batches;
  std::uint64_t total = 0, brute_force = 0, object_sphere_tests = 0, leaf_sphere_tests = 0;
  // False for --algo embree: Embree's BVH does not report its tests, so there is no count to give
  // (total is then the brute force only as an upper bound, and is not printed as tests).
  bool tests_counted = true;
  // --objects tree: every test again by its object side (per depth of the tested node; triangle spheres).
  bool object_tree = false;
  std::vector<emu::LevelStats> object_levels;
  emu::LevelStats object_triangles;

  // --algo tl: the lists' shape and per list the walks of the rays that chose it.
  struct TlList {
    std::uint64_t rays = 0, spheres = 0, triangles = 0;
  };
  bool tl = false;
  emu::TlShape tl_shape;
  std::vector<TlList> tl_lists;
  // --algo grid: the grids' host build time.
  bool grid = false;
  double grid_build_ms = 0.0;

  void ToJson(nlohmann::json& j) const;
  void Print(std::FILE* out) const;
};

// Decimals that show a share in percent with three significant digits, two from 1 % up (at most
// nine): a level's share of 69K triangles' brute force can be 0.0003 %, which two decimals show as 0.00.
int ShareDecimals(double percent);

Statistics CollectStatistics(const std::vector<emu::BatchStats>& batches);
// --algo tl: per ray type the sphere and triangle elements its walks tested (each a test).
Statistics TlStatistics(const emu::TlTracer& tracer, std::size_t triangles);
// --algo grid: per ray type the triangles its walks tested, and the cells they visited.
Statistics GridStatistics(const emu::GridTracer& tracer, std::size_t triangles);
// Brute force: every ray against every triangle, no levels.
Statistics BruteStatistics(const emu::FrameResult& frame, std::size_t triangles);

}  // namespace rayspace::app
