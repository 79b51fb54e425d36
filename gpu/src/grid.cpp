// Launch of the grid kernel (`--algo grid`; gpu/shaders/grid_trace.comp), each array in one binding
// (a call whose array outgrows it fails naming the pass).
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;


vk::Status VulkanPasses::Run(const emu::call::GridTrace& call, emu::GridWalks& out) {
  const std::size_t n = call.rays.size();
  Keep keep;
  Bindings<layout::kGridTraceBindings> b;
  // The regular grid's box and cells as the kernel's one GridVolume.
  const layout::GridVolume volume{call.volume[0], call.volume[1], call.volume[2], call.volume[3], call.volume_dims[0]};
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindFirst, call.first));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindTriangles, call.cell_triangles));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindMinDist, call.min_dist));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindBoxes, call.boxes));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindSlices, call.slices));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindLights, call.light_grids));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindOrigins, call.origins));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindVolume, std::span<const layout::GridVolume>(&volume, 1)));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindSceneTris, call.triangles));
  RS_TRY(Input(*ctx_, keep, b, layout::kGridTraceBindRays, call.rays));
  out = {};
  if (call.shadow)
    out.occluded.assign(n, 0);
  else
    out.hits.assign(n, 0);
  out.steps.assign(n, 0);
  out.tests.assign(n, 0);
  RS_TRY(Output(*ctx_, keep, b, layout::kGridTraceBindHits, call.shadow ? 0 : n * 8, call.shadow ? nullptr : out.hits.data()));
  RS_TRY(Output(*ctx_, keep, b, layout::kGridTraceBindOccluded, call.shadow ? n * 4 : 0, call.shadow ? out.occluded.data() : nullptr));
  RS_TRY(Output(*ctx_, keep, b, layout::kGridTraceBindSteps, n * 4, out.steps.data()));
  RS_TRY(Output(*ctx_, keep, b, layout::kGridTraceBindTests, n * 4, out.tests.data()));
  if (n == 0) return vk::Status::Ok();
  const layout::GridTracePush push{static_cast<std::uint32_t>(n), call.shadow, static_cast<std::uint32_t>(call.light_grids.size()),
                                   call.closed, call.eye, call.secondary};
  RS_TRY(RunKernel(*ctx_, K(PassId::kGridTrace), b.All(), &push, sizeof push, push.count));
  return keep.CopyBack();
}

}  // namespace rayspace::gpu_backend
