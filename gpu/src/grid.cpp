// Launches of the grid kernels (`--algo grid`): the build (gpu/shaders/grid_build.comp: grid.count,
// grid.emit, grid.cells) and the walk (gpu/shaders/grid_trace.comp), each array in one binding (a call
// whose array outgrows it fails naming the pass).
#include <numeric>

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

namespace {

// One grid's bindings: every phase of the kernel declares all of them.
struct GridBuildBindings {
  Keep keep;
  Bindings<layout::kGridBuildBindings> b;
  layout::GridBuildGrid grid{};
};

vk::Status BindGrid(vk::Context& c, GridBuildBindings& g, std::span<const glm::vec4> params, std::span<const glm::uvec4> shape,
                    std::string_view pass) {
  if (!c.float64())
    return vk::Status::Fail(fmt::format("{}: the device lacks shaderFloat64 or shaderSignedZeroInfNanPreserveFloat64, which the grids' "
                                        "build needs (rayspace devices); run --algo grid on the emulator",
                                        pass));
  if (params.size() == 4 && shape.size() == 2) g.grid = emu::grid::FromDescriptor(params, shape);
  return Input(c, g.keep, g.b, layout::kGridBuildBindGrid, std::span<const layout::GridBuildGrid>(&g.grid, 1));
}

// Placeholders for every binding the call did not set (the kernel declares all of them).
vk::Status Unused(vk::Context& c, GridBuildBindings& g) {
  for (std::uint32_t b = 0; b < layout::kGridBuildBindings; ++b)
    if (!g.b.Has(b)) RS_TRY(Output(c, g.keep, g.b, b, 4, nullptr));
  return vk::Status::Ok();
}

template <typename T>
vk::Status Out(vk::Context& c, GridBuildBindings& g, std::uint32_t binding, std::vector<T>& v) {
  return Output(c, g.keep, g.b, binding, v.size() * sizeof(T), v.empty() ? nullptr : v.data());
}

}  // namespace

vk::Status VulkanPasses::Run(const emu::call::GridCount& call, emu::GridCounts& out) {
  const std::size_t n = call.triangles.size();
  GridBuildBindings g;
  RS_TRY(BindGrid(*ctx_, g, call.grid, call.shape, call.kName));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindTriangles, call.triangles));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindSlices, call.slices));
  const bool perspective = g.grid.shape.x == layout::kGridKindPerspective;
  out = {};
  out.counts.assign(n, 0);
  out.spans.assign(n * layout::kGridFaces, glm::uvec4(0u));
  if (perspective) out.dist.assign(n, 0.0f), out.span_boxes.assign(n * layout::kGridFaces, glm::vec4(0.0f));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindCounts, out.counts));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindDist, out.dist));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindSpans, out.spans));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindSpanBoxes, out.span_boxes));
  RS_TRY(Unused(*ctx_, g));
  if (n == 0) return vk::Status::Ok();
  const layout::GridBuildPush push{layout::kGridBuildPhaseCount, static_cast<std::uint32_t>(n), 0u, 0u};
  RS_TRY(RunKernel(*ctx_, K(PassId::kGridCount), g.b.All(), &push, sizeof push, push.count));
  return g.keep.CopyBack();
}

vk::Status VulkanPasses::Run(const emu::call::GridEmit& call, emu::GridRefs& out) {
  const std::size_t n = call.counts.size();
  GridBuildBindings g;
  RS_TRY(BindGrid(*ctx_, g, call.grid, call.shape, call.kName));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindCounts, call.counts));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindSpans, call.spans));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindSpanBoxes, call.span_boxes));
  const std::size_t total = std::accumulate(call.counts.begin(), call.counts.end(), std::size_t{0});
  const std::uint32_t blocks = Blocks(n);
  out = {};
  out.offsets.assign(n, 0);
  out.cells.assign(total, 0);
  out.triangles.assign(total, 0);
  if (g.grid.shape.x == layout::kGridKindPerspective) out.boxes.assign(total, glm::vec4(0.0f));
  RS_TRY(Output(*ctx_, g.keep, g.b, layout::kGridBuildBindSums, (std::size_t{blocks} + 1) * 4, nullptr));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindOffsets, out.offsets));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindCells, out.cells));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindRefTris, out.triangles));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindBoxes, out.boxes));
  RS_TRY(Unused(*ctx_, g));
  if (n == 0) return vk::Status::Ok();
  vk::Recorder rec(*ctx_);
  // One submit: block sums, their scan (one workgroup), the offsets (one workgroup per block), then
  // one invocation per reference.
  for (const std::uint32_t phase : {layout::kGridBuildPhaseBlockSums, layout::kGridBuildPhaseScanSums, layout::kGridBuildPhaseOffsets}) {
    const layout::GridBuildPush push{phase, static_cast<std::uint32_t>(n), blocks, static_cast<std::uint32_t>(total)};
    RS_TRY(rec.DispatchGroups(K(PassId::kGridEmit), g.b.All(), &push, sizeof push, phase == layout::kGridBuildPhaseScanSums ? 1 : blocks));
  }
  const layout::GridBuildPush emit{layout::kGridBuildPhaseEmit, static_cast<std::uint32_t>(n), blocks, static_cast<std::uint32_t>(total)};
  if (total) RS_TRY(rec.Dispatch(K(PassId::kGridEmit), g.b.All(), &emit, sizeof emit, emit.refs));
  RS_TRY(rec.Submit());
  return g.keep.CopyBack();
}

vk::Status VulkanPasses::Run(const emu::call::GridCells& call, emu::GridLists& out) {
  const std::size_t refs = call.cells.size();
  GridBuildBindings g;
  RS_TRY(BindGrid(*ctx_, g, {}, {}, call.kName));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindCells, call.cells));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindRefTris, call.triangles));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindBoxes, call.boxes));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindOrder, call.order));
  RS_TRY(Input(*ctx_, g.keep, g.b, layout::kGridBuildBindDist, call.dist));
  const bool boxes = !call.boxes.empty(), dist = !call.dist.empty();
  out = {};
  out.first.assign(std::size_t{call.cell_count} + 1, 0);
  out.triangles.assign(refs, 0);
  if (boxes) out.boxes.assign(refs, glm::vec4(0.0f));
  if (dist) out.min_dist.assign(call.cell_count, 0.0f);
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindFirst, out.first));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindListTris, out.triangles));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindListBoxes, out.boxes));
  RS_TRY(Out(*ctx_, g, layout::kGridBuildBindMinDist, out.min_dist));
  RS_TRY(Unused(*ctx_, g));
  vk::Recorder rec(*ctx_);
  // One submit: the gather (one invocation per reference), the cells (one per cell and the total),
  // then the least distances (one per reference).
  const auto r = static_cast<std::uint32_t>(refs);
  const layout::GridBuildPush gather{layout::kGridBuildPhaseGather, r, boxes ? 1u : 0u, r};
  if (refs) RS_TRY(rec.Dispatch(K(PassId::kGridCells), g.b.All(), &gather, sizeof gather, gather.count));
  const layout::GridBuildPush cells{layout::kGridBuildPhaseCells, call.cell_count, dist ? 1u : 0u, r};
  RS_TRY(rec.Dispatch(K(PassId::kGridCells), g.b.All(), &cells, sizeof cells, call.cell_count + 1));
  const layout::GridBuildPush least{layout::kGridBuildPhaseMin, r, 1u, r};
  if (refs && dist) RS_TRY(rec.Dispatch(K(PassId::kGridCells), g.b.All(), &least, sizeof least, least.count));
  RS_TRY(rec.Submit());
  return g.keep.CopyBack();
}

}  // namespace rayspace::gpu_backend
