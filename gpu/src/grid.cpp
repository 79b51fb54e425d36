// Launch of the grid kernel (`--algo grid`; gpu/shaders/grid_trace.comp), each array in one binding
// (a call whose array outgrows it fails naming the pass).
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

namespace {

template <std::uint32_t N, typename T>
vk::Status GridInput(vk::Context& c, Keep& keep, Bindings<N>& b, std::uint32_t binding, std::span<const T> v) {
  const vk::Buffer* x = nullptr;
  RS_TRY(keep.From(c, v, x));
  b.Set(binding, x);
  return vk::Status::Ok();
}

template <std::uint32_t N>
vk::Status GridOutput(vk::Context& c, Keep& keep, Bindings<N>& b, std::uint32_t binding, std::size_t bytes, void* dst) {
  const vk::Buffer* x = nullptr;
  RS_TRY(keep.Output(c, bytes, x, dst));
  RS_TRY(const_cast<vk::Buffer*>(x)->Zero());
  b.Set(binding, x);
  return vk::Status::Ok();
}

}  // namespace

vk::Status VulkanPasses::Run(const emu::call::GridTrace& call, emu::GridWalks& out) {
  const std::size_t n = call.rays.size();
  Keep keep;
  Bindings<layout::kGridTraceBindings> b;
  // The regular grid's box and cells as the kernel's one GridVolume.
  const layout::GridVolume volume{call.volume[0], call.volume[1], call.volume[2], call.volume[3], call.volume_dims[0]};
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindFirst, call.first));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindTriangles, call.cell_triangles));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindMinDist, call.min_dist));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindLights, call.light_grids));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindOrigins, call.origins));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindVolume, std::span<const layout::GridVolume>(&volume, 1)));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindSceneTris, call.triangles));
  RS_TRY(GridInput(*ctx_, keep, b, layout::kGridTraceBindRays, call.rays));
  out = {};
  if (call.shadow)
    out.occluded.assign(n, 0);
  else
    out.hits.assign(n, 0);
  out.steps.assign(n, 0);
  out.tests.assign(n, 0);
  RS_TRY(GridOutput(*ctx_, keep, b, layout::kGridTraceBindHits, call.shadow ? 0 : n * 8, call.shadow ? nullptr : out.hits.data()));
  RS_TRY(GridOutput(*ctx_, keep, b, layout::kGridTraceBindOccluded, call.shadow ? n * 4 : 0, call.shadow ? out.occluded.data() : nullptr));
  RS_TRY(GridOutput(*ctx_, keep, b, layout::kGridTraceBindSteps, n * 4, out.steps.data()));
  RS_TRY(GridOutput(*ctx_, keep, b, layout::kGridTraceBindTests, n * 4, out.tests.data()));
  if (n == 0) return vk::Status::Ok();
  const layout::GridTracePush push{static_cast<std::uint32_t>(n), call.shadow, static_cast<std::uint32_t>(call.light_grids.size()),
                                   call.closed};
  RS_TRY(RunKernel(*ctx_, K(PassId::kGridTrace), b.All(), &push, sizeof push, push.count));
  return keep.CopyBack();
}

}  // namespace rayspace::gpu_backend
