#include "shadow_bench.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bench_run.h"
#include "rayspace/frame/command_util.h"
#include "rayspace/frame/memory_estimate.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/error.h"
#include "rayspace/json_text.h"
#include "rayspace/output_file.h"
#include "rayspace/parallel.h"
#include "rayspace/refs/embree_tracer.h"
#include "rayspace/scene.h"

namespace rayspace::app {
namespace {

template <typename F>
double TimeMs(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The shadow rays of bounce 0 (every light's), as the frame makes them; traced once by Embree.
std::vector<layout::Ray> FirstShadowRays(const Scene& scene, const SceneBuffers& buffers, int width, int height, Tracer& embree) {
  std::vector<layout::Ray> rays;
  emu::FrameOptions fo;
  fo.width = width;
  fo.height = height;
  Scene one = scene;
  one.max_depth = 0;  // primary hits only: their shadow rays are the batch measured
  emu::RenderFrame(one, buffers, embree, fo, [&](const emu::Batch& b) {
    if (b.kind == layout::kRayShadow && b.bounce == 0) rays = *b.rays;
  });
  return rays;
}

struct Row {
  std::string scene;
  std::size_t triangles = 0, rays = 0, differing = 0, skipped = 0, unoccluded = 0;
  double build_ms = 0, grid_ms = 0, lanes_ms = 0, embree_ms = 0, tests_per_ray = 0;
  double GridRate() const { return grid_ms > 0 ? rays / grid_ms / 1e3 : 0; }
  double LanesRate() const { return lanes_ms > 0 ? rays / lanes_ms / 1e3 : 0; }
  double EmbreeRate() const { return embree_ms > 0 ? rays / embree_ms / 1e3 : 0; }
};

Row Measure(const ShadowBenchArgs& args, const std::string& path, int width, int height) {
  LoadOptions lo;
  lo.data_root = args.data;
  const Scene scene = LoadScene(path, lo);
  // The shadow rays of one frame and its grids; estimated as a render of that frame.
  CheckFitsMachine(EstimateFrameMemory(scene, width, height, {}), width, height, "--size",
                   fmt::format("the shadow bench of {}", path).c_str());
  bool point = false;
  for (const LightDesc& l : scene.lights) point |= !l.IsArea();
  if (!point) ThrowInput("{}: no point light (hard shadows need one)", path);
  const SceneBuffers buffers = FlattenScene(scene);
  const std::unique_ptr<Tracer> embree = refs::MakeEmbreeTracer(buffers, ThreadCount());
  const std::vector<layout::Ray> rays = FirstShadowRays(scene, buffers, width, height, *embree);
  Row row;
  row.scene = scene.name;
  row.triangles = buffers.triangles.size();
  row.rays = rays.size();
  std::vector<double> build, grid, lanes, emb;
  emu::GridWalks w, wl;
  std::vector<std::uint32_t> occ;
  // Set up once per scene, as the render path does (the triangles' plane normals in lane order).
  const emu::GridLanes setup = emu::PrepareGridLanes(buffers.triangles);
  for (int rep = 0; rep < args.repetitions; ++rep) {
    emu::GridArrays g;
    build.push_back(TimeMs([&] { g = emu::grid::Build(buffers, {args.grid_cells, 1, args.closed_models}); }));
    const emu::call::GridTrace call{.first = g.first, .cell_triangles = g.triangles, .min_dist = g.min_dist, .boxes = g.boxes,
                                    .light_grids = g.light_grids, .origins = g.origins, .volume = g.volume, .volume_dims = g.volume_dims,
                                    .triangles = buffers.triangles, .rays = rays, .shadow = 1, .closed = args.closed_models ? 1u : 0u};
    grid.push_back(TimeMs([&] { w = emu::PassGridTrace(call); }));
    lanes.push_back(TimeMs([&] { wl = emu::PassGridTraceLanes(call, setup); }));
    emb.push_back(TimeMs([&] { embree->Occluded(rays, occ); }));
  }
  // The render path must walk as the pass does; a bench that timed a different answer would mislead.
  RS_CHECK_MSG(wl.occluded == w.occluded && wl.steps == w.steps && wl.tests == w.tests, "{}: grid.trace's lanes differ from the pass",
               path);
  row.build_ms = Median(build);
  row.grid_ms = Median(grid);
  row.lanes_ms = Median(lanes);
  row.embree_ms = Median(emb);
  std::uint64_t tests = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    row.differing += w.occluded[i] != occ[i];
    tests += w.tests[i];
    if (!w.occluded[i]) {
      ++row.unoccluded;
      row.skipped += w.tests[i] == 0;
    }
  }
  row.tests_per_ray = rays.empty() ? 0 : static_cast<double>(tests) / rays.size();
  return row;
}

}  // namespace

ExitCode RunShadowBench(const ShadowBenchArgs& args) {
  int width = 0, height = 0;
  ParseSize(args.size, width, height, "--size");
  OutputFile json = args.json.empty() ? OutputFile() : OutputFile(args.json, OutputOptions{"the JSON file", true, true, {}});
  const ScopedSettings threads([&](Settings& s) { s.threads = args.threads > 0 ? args.threads : s.threads; });
  std::vector<Row> rows;
  for (const std::string& s : args.scenes) rows.push_back(Measure(args, s, width, height));
  std::printf("rayspace shadow-bench: hard shadows, %s, %d threads, median of %d; grid %ux%u cells per face%s\n", args.size.c_str(),
              ThreadCount(), args.repetitions, args.grid_cells, args.grid_cells, args.closed_models ? ", --closed-models" : "");
  std::printf("rayspace shadow-bench: lanes: %s\n", emu::cone::IsaName(emu::cone::BestIsa()));
  std::printf("  %-14s %9s %9s %10s %10s %10s %11s %10s %11s %9s %9s %9s %9s\n", "scene", "triangles", "rays", "build ms", "pass ms",
              "lanes ms", "lanes Mr/s", "embree ms", "embree Mr/s", "pass", "lanes", "tests/ray", "no test");
  nlohmann::json j = nlohmann::json::array();
  for (const Row& r : rows) {
    const double ratio = r.EmbreeRate() > 0 ? r.GridRate() / r.EmbreeRate() : 0;
    const double lanes_ratio = r.EmbreeRate() > 0 ? r.LanesRate() / r.EmbreeRate() : 0;
    std::printf("  %-14s %9zu %9zu %10.1f %10.1f %10.1f %11.2f %10.1f %11.2f %8.2fx %8.2fx %9.2f %8.1f%%\n", r.scene.c_str(), r.triangles,
                r.rays, r.build_ms, r.grid_ms, r.lanes_ms, r.LanesRate(), r.embree_ms, r.EmbreeRate(), ratio, lanes_ratio, r.tests_per_ray,
                r.unoccluded ? 100.0 * r.skipped / r.unoccluded : 0.0);
    if (r.differing)
      std::printf("  %-14s %zu of %zu shadow answers differ from Embree's%s\n", "", r.differing, r.rays,
                  args.closed_models ? " (--closed-models changes shadows on purpose)" : "");
    j.push_back({{"scene", r.scene}, {"triangles", r.triangles}, {"rays", r.rays}, {"build_ms", r.build_ms}, {"grid_ms", r.grid_ms},
                 {"lanes_ms", r.lanes_ms}, {"embree_ms", r.embree_ms}, {"grid_rays_per_s", r.GridRate() * 1e6},
                 {"lanes_rays_per_s", r.LanesRate() * 1e6}, {"lanes_ratio", lanes_ratio}, {"embree_rays_per_s", r.EmbreeRate() * 1e6},
                 {"ratio", ratio}, {"tests_per_ray", r.tests_per_ray}, {"differing", r.differing},
                 {"unoccluded_without_tests", r.unoccluded ? static_cast<double>(r.skipped) / r.unoccluded : 0.0}});
  }
  std::printf("  pass, lanes: grid.trace's rays/s over Embree's, tracing alone (the build is its own column), ray by ray (the\n"
              "  pass diff compares) and with each cell's triangles in SIMD lanes (render's path: the same walks, checked here);\n"
              "  no test: the share of the unoccluded rays that needed no triangle test (the cell's least distance)\n");
  if (!json.empty())
    json.Commit(JsonText({{"size", args.size}, {"threads", ThreadCount()}, {"repetitions", args.repetitions}, {"grid_cells", args.grid_cells},
                          {"closed_models", args.closed_models}, {"scenes", j}}));
  return ExitCode::kOk;
}

}  // namespace rayspace::app
