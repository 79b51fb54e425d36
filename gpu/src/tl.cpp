// Launches of the traversal-list kernels (`--algo tl`; gpu/shaders/tl_lists.comp, tl_trace.comp),
// each array in one binding (a call whose array outgrows it fails naming the pass).
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"
#include "rayspace/emu/tl/heads.h"

namespace rayspace::gpu_backend {
using namespace detail;

namespace {

// The packed lists a walk or a window pass reads, bound at the four consecutive bindings from `first`
// (first, escapes, words, vertices: the same in tl.heads, tl.cells and tl.trace).
template <std::uint32_t N, typename Call>
vk::Status InputLists(vk::Context& c, Keep& keep, Bindings<N>& b, std::uint32_t first, const Call& call) {
  RS_TRY(Input(c, keep, b, first, call.first));
  RS_TRY(Input(c, keep, b, first + 1, call.escapes));
  RS_TRY(Input(c, keep, b, first + 2, call.words));
  return Input(c, keep, b, first + 3, call.vertices);
}
static_assert(layout::kTlHeadsBindEscapes == layout::kTlHeadsBindFirst + 1 && layout::kTlHeadsBindVertices == layout::kTlHeadsBindFirst + 3 &&
              layout::kTlCellsBindEscapes == layout::kTlCellsBindFirst + 1 && layout::kTlCellsBindVertices == layout::kTlCellsBindFirst + 3 &&
              layout::kTlTraceBindEscapes == layout::kTlTraceBindFirst + 1 && layout::kTlTraceBindVertices == layout::kTlTraceBindFirst + 3 &&
              layout::kTlHeadsBindWords == layout::kTlHeadsBindFirst + 2 && layout::kTlCellsBindWords == layout::kTlCellsBindFirst + 2 &&
              layout::kTlTraceBindWords == layout::kTlTraceBindFirst + 2);

}  // namespace

// Four dispatches in one submit, each phase after the writes of the one before (kept counts,
// offsets, positions).
vk::Status VulkanPasses::Run(const emu::call::TlLists& call, emu::TlListArrays& out) {
  const emu::TlTreeView& t = call.tree;
  const std::size_t E = t.Elements(), total = call.directions.size() * E;
  Keep keep;
  Bindings<layout::kTlListsBindings> b;
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindLinks, t.tl_links));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindSpheres, t.tl_spheres));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindParents, t.tl_parents));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindSizes, t.tl_sizes));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindRoots, t.tl_roots));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindTriangles, t.tl_triangles));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindOwners, t.tl_owners));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindTriWords, t.tl_tri_words));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindVertices, t.tl_vertices));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlListsBindDirections, call.directions));
  out.escapes.assign(total, 0);
  out.words.assign(total, glm::uvec4(0));
  out.lengths.assign(call.directions.size(), 0);
  RS_TRY(Output(*ctx_, keep, b, layout::kTlListsBindRel, total * 4, nullptr));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlListsBindKept, call.directions.size() * t.Nodes() * 8, nullptr));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlListsBindLengths, out.lengths.size() * 4, out.lengths.data()));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlListsBindEscapes, total * 4, out.escapes.data()));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlListsBindWords, total * 16, out.words.data()));
  if (total == 0) return vk::Status::Ok();
  layout::TlListsPush push{};
  push.nodes = static_cast<std::uint32_t>(t.Nodes());
  push.refs = static_cast<std::uint32_t>(t.tl_triangles.size());
  push.lists = static_cast<std::uint32_t>(call.directions.size());
  push.roots = static_cast<std::uint32_t>(t.tl_roots.size());
  push.order = call.order;
  push.cull = call.cull;
  vk::Recorder rec(*ctx_);
  for (const std::uint32_t phase :
       {layout::kTlListsPhaseTriangles, layout::kTlListsPhaseNodes, layout::kTlListsPhaseRank, layout::kTlListsPhasePlace}) {
    push.phase = phase;
    RS_TRY(rec.Dispatch(K(PassId::kTlLists), b.All(), &push, sizeof push, static_cast<std::uint32_t>(total)));
  }
  RS_TRY(rec.Submit());
  return keep.CopyBack();
}

// One invocation per (triangle, case, list) window.
vk::Status VulkanPasses::Run(const emu::call::TlHeads& call, emu::TlWindows& out) {
  const std::size_t lists = call.first.empty() ? 0 : call.first.size() - 1, total = call.tri_words.size() * layout::kTlCases * lists;
  Keep keep;
  Bindings<layout::kTlHeadsBindings> b;
  RS_TRY(InputLists(*ctx_, keep, b, layout::kTlHeadsBindFirst, call));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlHeadsBindTriWords, call.tri_words));
  out.windows.assign(2 * total, 0u);
  RS_TRY(Output(*ctx_, keep, b, layout::kTlHeadsBindWindows, total * 8, out.windows.data()));
  if (total == 0) return vk::Status::Ok();
  layout::TlHeadsPush push{};
  push.lists = static_cast<std::uint32_t>(lists);
  push.triangles = static_cast<std::uint32_t>(call.tri_words.size());
  push.mode = call.mode;
  push.margin = call.margin;
  RS_TRY(RunKernel(*ctx_, K(PassId::kTlHeads), b.All(), &push, sizeof push, static_cast<std::uint32_t>(total)));
  return keep.CopyBack();
}

// One invocation per (cell, list) window.
vk::Status VulkanPasses::Run(const emu::call::TlCells& call, emu::TlWindows& out) {
  const std::size_t lists = call.first.empty() ? 0 : call.first.size() - 1, cells = emu::tl::CellCount(call.frame),
                    total = cells * lists;
  Keep keep;
  Bindings<layout::kTlCellsBindings> b;
  RS_TRY(InputLists(*ctx_, keep, b, layout::kTlCellsBindFirst, call));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlCellsBindFrame, std::span<const layout::FrameConstants>(&call.frame, 1)));
  out.windows.assign(2 * total, 0u);
  RS_TRY(Output(*ctx_, keep, b, layout::kTlCellsBindWindows, total * 8, out.windows.data()));
  if (total == 0) return vk::Status::Ok();
  layout::TlCellsPush push{};
  push.lists = static_cast<std::uint32_t>(lists);
  push.cells_x = emu::tl::CellsX(call.frame);
  push.cells = static_cast<std::uint32_t>(cells);
  push.margin = call.margin;
  RS_TRY(RunKernel(*ctx_, K(PassId::kTlCells), b.All(), &push, sizeof push, static_cast<std::uint32_t>(total)));
  return keep.CopyBack();
}

vk::Status VulkanPasses::Run(const emu::call::TlTrace& call, emu::TlWalks& out) {
  const std::size_t n = call.rays.size();
  Keep keep;
  Bindings<layout::kTlTraceBindings> b;
  RS_TRY(InputLists(*ctx_, keep, b, layout::kTlTraceBindFirst, call));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlTraceBindRays, call.rays));
  out = {};
  if (call.shadow)
    out.occluded.assign(n, 0);
  else
    out.hits.assign(n, 0);
  out.spheres.assign(n, 0);
  out.triangles.assign(n, 0);
  RS_TRY(Output(*ctx_, keep, b, layout::kTlTraceBindHits, call.shadow ? 0 : n * 8, call.shadow ? nullptr : out.hits.data()));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlTraceBindOccluded, call.shadow ? n * 4 : 0, call.shadow ? out.occluded.data() : nullptr));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlTraceBindSpheres, n * 4, out.spheres.data()));
  RS_TRY(Output(*ctx_, keep, b, layout::kTlTraceBindTriangles, n * 4, out.triangles.data()));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlTraceBindTriWords, call.tri_words));
  RS_TRY(Input(*ctx_, keep, b, layout::kTlTraceBindWindows, call.windows));
  if (n == 0) return vk::Status::Ok();
  layout::TlTracePush push{};
  push.count = static_cast<std::uint32_t>(n);
  push.lists = static_cast<std::uint32_t>(call.first.size() - 1);
  push.shadow = call.shadow;
  push.cull = call.cull;
  push.heads = call.heads;
  push.triangles = static_cast<std::uint32_t>(call.heads == layout::kTlHeadsCells ? call.windows.size() / (2 * push.lists)
                                                                                  : call.tri_words.size());
  RS_TRY(RunKernel(*ctx_, K(PassId::kTlTrace), b.All(), &push, sizeof push, push.count));
  return keep.CopyBack();
}

}  // namespace rayspace::gpu_backend
