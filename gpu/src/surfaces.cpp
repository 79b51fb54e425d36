// Launches of the surfaces kernels (gpu/shaders/surfaces.comp, surfaces_hits.comp): shading points
// from the G-buffer or from ray hits.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

vk::Status VulkanPasses::Run(const emu::call::SurfacesFromGBuffer& call, std::vector<layout::Surface>& out) {
  const layout::FrameConstants& fc = call.frame;
  const SceneBuffers& scene = *call.scene;
  const auto& g = call;
  vk::Context& c = *ctx_;
  out.assign(g.prim.size(), layout::Surface{});
  Keep keep;
  const vk::Buffer *binfo = nullptr, *bf = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::TriangleInfo>(scene.info), binfo));
  RS_TRY(keep.From(c, std::span<const layout::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(g.prim.size(), PerPart(sizeof(layout::Surface)), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bp = nullptr, *bn = nullptr, *bprim = nullptr, *bs = nullptr;
                    RS_TRY(keep.From(c, Slice(g.position, i0, i1), bp));
                    RS_TRY(keep.From(c, Slice(g.normal, i0, i1), bn));
                    RS_TRY(keep.From(c, Slice(g.prim, i0, i1), bprim));
                    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(layout::Surface), bs, out.data() + i0));
                    const layout::SurfacesPush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(i0)};
                    Bindings<layout::kSurfacesBindings> b;
                    b.Set(layout::kSurfacesBindPosition, bp).Set(layout::kSurfacesBindNormal, bn).Set(layout::kSurfacesBindPrim, bprim);
                    b.Set(layout::kSurfacesBindInfo, binfo).Set(layout::kSurfacesBindFrame, bf).Set(layout::kSurfacesBindSurfaces, bs);
                    return rec.Dispatch(K(PassId::kSurfaces), b.All(), &push, sizeof push, push.pixels);
                  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Run(const emu::call::SurfacesFromHits& call, std::vector<layout::Surface>& out) {
  const std::span<const layout::Ray> rays = call.rays;
  const std::span<const std::uint64_t> hits = call.hits;
  const SceneBuffers& scene = *call.scene;
  vk::Context& c = *ctx_;
  out.assign(rays.size(), layout::Surface{});
  Keep keep;
  const vk::Buffer *bt = nullptr, *bn = nullptr, *bi = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::Triangle>(scene.triangles), bt));
  RS_TRY(keep.From(c, std::span<const layout::TriangleNormals>(scene.normals), bn));
  RS_TRY(keep.From(c, std::span<const layout::TriangleInfo>(scene.info), bi));
  vk::Recorder rec(c);
  RS_TRY(ForParts(rays.size(), PerPart(sizeof(layout::Surface)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *br = nullptr, *bh = nullptr, *bs = nullptr;
    RS_TRY(keep.From(c, Slice(rays, i0, i1), br));
    RS_TRY(keep.From(c, Slice(hits, i0, i1), bh));
    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(layout::Surface), bs, out.data() + i0));
    const std::uint32_t n = static_cast<std::uint32_t>(i1 - i0);
    const layout::SurfacesHitsPush push{n};
    Bindings<layout::kSurfacesHitsBindings> b;
    b.Set(layout::kSurfacesHitsBindRays, br).Set(layout::kSurfacesHitsBindHits, bh).Set(layout::kSurfacesHitsBindTriangles, bt);
    b.Set(layout::kSurfacesHitsBindNormals, bn).Set(layout::kSurfacesHitsBindInfo, bi).Set(layout::kSurfacesHitsBindSurfaces, bs);
    return rec.Dispatch(K(PassId::kSurfacesHits), b.All(), &push, sizeof push, n);
  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  return vk::Status::Ok();
}


}  // namespace rayspace::gpu_backend
