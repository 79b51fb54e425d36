#include "rayspace/frame/render_frame.h"

#include <chrono>

#include "rayspace/frame/kernel_model.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/refs/embree_tracer.h"

namespace rayspace::app {

void WarnOpenModels(const Scene& scene, const SceneBuffers& buffers) {
  std::vector<std::size_t> open_edges;
  const std::vector<bool> closed = emu::grid::ClosedObjects(buffers, &open_edges);
  for (std::size_t i = 0; i < closed.size() && i < scene.objects.size(); ++i)
    if (!closed[i])
      std::fprintf(stderr, "rayspace: warning: --closed-models: object %zu '%s' is not closed (its surfaces have %zu edges not shared by exactly two triangles); its shadows may be wrong\n",
                   i, scene.objects[i].name.c_str(), open_edges[i]);
}

namespace {

Tracers MakeTracers(const RenderArgs& args, const Scene& scene, const SceneBuffers& buffers, const emu::FrameOptions& fo,
                    const Backend& backend) {
  const emu::DirectMode mode = args.direct == "exhaustive" ? emu::DirectMode::kExhaustive
                               : args.direct == "bvh"      ? emu::DirectMode::kBvh
                                                           : emu::DirectMode::kAuto;
  // Build only the tracers this run uses: the frame's, and the oracle's unless --no-oracle.
  Tracers t;
  const bool embree_frames = args.algo == "embree";
  if (args.algo == "brute" || (embree_frames && !args.no_oracle)) t.direct = emu::MakeDirectTracer(buffers, mode);
  if (embree_frames || !args.no_oracle) t.embree = refs::MakeEmbreeTracer(buffers, ThreadCount());
  if (args.Hierarchy()) {
    emu::HierarchyConfig cfg = MakeHierarchyConfig(args, fo.width, fo.height, backend.hierarchy);
    cfg.fused = UsesFusedPath(args);
    t.hierarchy = emu::MakeHierarchyTracer(buffers, cfg);
  }
  if (args.algo == "tl") t.tl = emu::MakeTlTracer(buffers, MakeTlOptions(args), backend.hierarchy);
  if (args.algo == "grid") {
    CheckGridBuild(backend);
    emu::grid::Options go = MakeGridOptions(args);
    go.lanes = UsesFusedPath(args);
    t.grid = emu::MakeGridTracer(buffers, go, backend.hierarchy);
  }
  if (args.algo == "grid" && args.closed_models) WarnOpenModels(scene, buffers);
  t.frame = t.hierarchy ? t.hierarchy.get()
            : t.tl      ? t.tl.get()
            : t.grid    ? t.grid.get()
            : embree_frames ? t.embree.get()
                            : t.direct.get();
  t.oracle = embree_frames ? t.direct.get() : t.embree.get();
  return t;
}

// The frame, each traced batch re-traced by the oracle when there is one; adds its time to oracle_ms.
emu::FrameResult RenderChecked(const Scene& scene, const SceneBuffers& buffers, Tracer& frame_tracer, const emu::FrameOptions& fo,
                               refs::Oracle* oracle, double& oracle_ms) {
  emu::BatchObserver observer;
  if (oracle) {
    observer = [&](const emu::Batch& b) {
      const auto t0 = std::chrono::steady_clock::now();
      oracle->Check(b);
      oracle_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    };
  }
  return emu::RenderFrame(scene, buffers, frame_tracer, fo, observer);
}

}  // namespace

// The fused path runs each level as one traverse.compact pass, on any backend (the emulator adds
// host shortcuts for the sort and the final tests). Checking or reordering the emulated workgroups
// (--check-workgroups, --schedule) is about the passes' workgroup kernels (the reduction's among
// them), so `auto` keeps the passes then; `fused` with them runs traverse.compact's workgroup mirror.
bool UsesFusedPath(const RenderArgs& args) {
  return args.path == "fused" || (args.path == "auto" && !RequestsWorkgroupModel(args.model));
}

MemoryUse RenderMemoryUse(const RenderArgs& args) {
  return {.copies = args.backend == "vulkan" ? kVulkanCopies : 1,
          .slot_copies = args.Hierarchy() && !UsesFusedPath(args) ? 1 : 0,
          .subdivision = args.subdivision,
          .pair_capacity = args.pair_capacity,
          .levels = args.depth_auto ? 0 : args.depth,
          .object_mask = args.algo == "crsh",
          // auto takes the tree on the emulator only (frame_args.cpp, MakeHierarchyConfig)
          .object_tree = args.Hierarchy() && (args.objects == "tree" || (args.objects == "auto" && args.backend == "emu"))};
}

Backend MakeRenderBackend(const RenderArgs& args) {
  // The simulated GPU takes --schedule too, as in diff: the order of its workgroups and subgroups.
  const sim::DeviceConfig simulated = SimulatedConfig(args.backend, args.subgroup_size, args.model.schedule, args.sim_checks,
                                                      args.device_model, args.subgroup_layout, args.step_limit);
  return MakeBackend(args.backend, args.device, 64, {}, args.Limits(), args.kernels, simulated);
}

std::unique_ptr<RenderedFrame> RenderOnBackend(const RenderArgs& args, const Scene& scene, const SceneBuffers& buffers,
                                               emu::FrameOptions fo, const Backend& backend) {
  const ScopedSettings model = EmulatedKernels(args.model, 64, backend.subgroup_size, {});
  fo.passes = backend.frame;
  auto f = std::make_unique<RenderedFrame>();
  f->tracers = MakeTracers(args, scene, buffers, fo, backend);
  if (!args.no_oracle) f->oracle.emplace(*f->tracers.oracle, buffers);
  if (f->oracle && args.algo == "grid" && args.closed_models) f->oracle->ExpectShadowChanges("--closed-models");
  f->result = RenderChecked(scene, buffers, *f->tracers.frame, fo, f->oracle ? &*f->oracle : nullptr, f->oracle_ms);
  f->tracers.frame->Describe(f->tracer);
  f->stats = f->tracers.hierarchy ? CollectStatistics(f->tracers.hierarchy->Stats())
             : f->tracers.tl      ? TlStatistics(*f->tracers.tl, buffers.triangles.size())
             : f->tracers.grid    ? GridStatistics(*f->tracers.grid, buffers.triangles.size())
                                  : BruteStatistics(f->result, buffers.triangles.size());
  if (args.algo == "embree") f->stats.tests_counted = false;
  f->phases = Phases(f->result.passes, f->result.total_ms, f->oracle_ms);
  return f;
}

}  // namespace rayspace::app
