#include "reproduce_frame.h"

#include <mutex>

#include "rayspace/frame/render_frame.h"
#include "rayspace/parallel.h"
#include "rayspace/settings.h"
#include "frame_options.h"

namespace rayspace::reproduce {
namespace {

app::RenderArgs Args(const Config& c) {
  app::RenderArgs args;
  args.algo = c.algo;
  if (c.tl()) {
    args.lists = c.lists;
    args.node_order = c.node_order;
    args.backface_cull = c.cull ? "on" : "off";
    args.polygon_heads = c.heads.empty() ? "off" : c.heads;
    args.primary = c.primary ? "tl" : "raster";
    args.frustum_cull = c.frustum ? "on" : "off";
  } else if (c.grid()) {
    if (!c.grid_area.empty()) args.grid_area = c.grid_area;
    args.grid_regular_cells = c.grid_regular_cells;
    args.primary = c.primary ? "grid" : "raster";
  } else if (c.embree()) {
    args.primary = c.primary ? "embree" : "raster";
  } else if (!c.quadtree()) {
    args.subdivision = c.subdivision;
    args.depth = c.levels;
    args.depth_given = true;
  }
  args.bounces = c.bounces;
  args.objects = "flat";  // the thesis's: every triangle of every object a top node's sphere may meet
  args.no_oracle = true;
  args.backend = "emu";
  if (!c.faithful.empty()) args.faithful = app::FaithfulFromPreset(c.faithful);
  if (!c.switches.empty()) args.faithful = app::FaithfulFromWords(c.switches);
  args.faithful.one_object = args.faithful.one_object || c.one_object;
  if (!c.path.empty()) args.path = c.path;
  return args;
}

// Per ray type, what the top level tests when every top node meets every triangle.
void TopNodes(const std::vector<emu::BatchStats>& batches, const Config& c, Counts& counts) {
  for (const emu::BatchStats& b : batches) {
    if (b.levels.empty()) continue;
    std::uint64_t per_top = 1;
    for (std::size_t L = 0; L < b.levels.size(); ++L) per_top *= static_cast<std::uint64_t>(c.quadtree() ? 4 : c.subdivision);
    counts.types[emu::RayKindName(b.kind)].top_nodes_x_triangles += (b.rays + per_top - 1) / per_top * b.triangles;
  }
}

Counts ToCounts(const app::Statistics& s, const Config& c) {
  Counts counts;
  counts.total = s.total;
  counts.brute_force = s.brute_force;
  for (const auto& [kind, t] : s.types) {
    TypeCounts& tc = counts.types[emu::RayKindName(kind)];
    for (const emu::LevelStats& l : t.levels) tc.levels.push_back({l.intersections, l.hits});
    tc.final_tests = t.final_tests;
    tc.rays = t.rays;
    tc.brute_force = t.brute_force;
    tc.total = t.Total();
  }
  TopNodes(s.batches, c, counts);
  return counts;
}

// The backend setup configures process-wide emulated-kernel settings: one job at a time.
std::mutex g_backend_mutex;

}  // namespace

FrameOutput RenderConfig(const Config& c, const Scene& scene, const SceneBuffers& buffers) {
  const app::RenderArgs args = Args(c);
  // A configuration with its own thread count (hunt-mark's scaling) runs with it; the others with the run's.
  const ScopedSettings threads([&](Settings& s) { s.threads = c.threads > 0 ? c.threads : s.threads; });
  emu::FrameOptions fo;
  fo.width = c.width;
  fo.height = c.height;
  app::ApplyFaithful(args.faithful, fo);
  app::ApplyPrimary(args, fo);
  std::unique_ptr<app::Backend> backend;
  {
    std::lock_guard<std::mutex> lock(g_backend_mutex);
    backend = std::make_unique<app::Backend>(app::MakeRenderBackend(args));
    app::CheckFrameFits(*backend, c.width, c.height, ShadowSlotsPerSurface(scene.lights), buffers.triangles.size());
  }
  const std::unique_ptr<app::RenderedFrame> f = app::RenderOnBackend(args, scene, buffers, fo, *backend);
  FrameOutput out;
  out.counts = ToCounts(f->stats, c);
  for (const std::uint64_t n : f->result.rays[layout::kRayShadow]) out.shadow_rays += n;
  for (const std::uint64_t n : f->result.unoccluded_shadow_rays) out.unoccluded_shadow_rays += n;
  f->stats.ToJson(out.statistics);
  nlohmann::json phases = nlohmann::json::array();
  for (const app::Phase& p : f->phases) phases.push_back({{"phase", p.name}, {"ms", p.ms}});
  // Every pass that ran, by its own name: roger's timings group them into Roger's four phases.
  nlohmann::json passes = nlohmann::json::array();
  for (const emu::PassRecord& p : f->result.passes)
    if (p.ran) passes.push_back({{"pass", p.name}, {"ms", p.ms}});
  out.timings = {{"frame_ms", f->result.total_ms}, {"phases", phases}, {"passes", passes}, {"threads", ThreadCount()}};
  // The grids' build time is a time: with the timings, out of the reproducible statistics.
  if (out.statistics.contains("grids")) {
    out.timings["grid_build_ms"] = out.statistics["grids"].value("build_ms", 0.0);
    out.statistics["grids"].erase("build_ms");
    // The regular grid's shape (--grid-regular-cells chooses it from the scene's box).
    if (f->tracer.contains("regular_dims")) out.statistics["grids"]["regular_dims"] = f->tracer["regular_dims"];
  }
  return out;
}

}  // namespace rayspace::reproduce
