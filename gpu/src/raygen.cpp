// Launches of the three raygen kernels (gpu/shaders/raygen_*.comp): sparse ray slots with head flags.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

// Element-wise passes run over consecutive parts of their per-element buffers, each part within one
// binding, all parts in one submit; outputs are copied back part by part.
vk::Status VulkanPasses::RaygenShadow(const emu::call::Raygen& call, emu::SparseRays& out) {
  const layout::FrameConstants& fc = call.frame;
  const std::span<const layout::Surface> surfaces = call.surfaces;
  const SceneBuffers& scene = *call.scene;
  vk::Context& c = *ctx_;
  const std::size_t lights = scene.lights.size(), per = ShadowSlots(scene.lights), slots = surfaces.size() * per;
  if (per * sizeof(layout::Ray) > SplitBytes())
    return vk::Status::Fail(fmt::format("{} light samples: one surface's {} bytes of shadow-ray slots exceed one binding of {} bytes",
                                        per, per * sizeof(layout::Ray), SplitBytes()));
  out.rays.assign(slots, layout::Ray{});
  out.flags.assign(slots, 0);
  Keep keep;
  const vk::Buffer *bl = nullptr, *bf = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::Light>(scene.lights), bl));
  RS_TRY(keep.From(c, std::span<const layout::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(surfaces.size(), PerPart(std::max(sizeof(layout::Surface), per * sizeof(layout::Ray))), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bs = nullptr, *br = nullptr, *bflags = nullptr;
                    RS_TRY(keep.From(c, Slice(surfaces, i0, i1), bs));
                    RS_TRY(keep.Output(c, (i1 - i0) * per * sizeof(layout::Ray), br, out.rays.data() + i0 * per));
                    RS_TRY(keep.Output(c, (i1 - i0) * per * 4, bflags, out.flags.data() + i0 * per));
                    const layout::RaygenShadowPush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(lights), call.shadow_rule,
                                                           static_cast<std::uint32_t>(per)};
                    Bindings<layout::kRaygenBindings> b;
                    b.Set(layout::kRaygenBindSurfaces, bs).Set(layout::kRaygenBindLightsOrMaterials, bl).Set(layout::kRaygenBindFrame, bf);
                    b.Set(layout::kRaygenBindRays, br).Set(layout::kRaygenBindFlags, bflags);
                    return rec.Dispatch(K(PassId::kRaygenShadow), b.All(), &push, sizeof push, push.surface_count);
                  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  return vk::Status::Ok();
}

// One ray slot per surface (reflection and refraction share their buffers and launch).
vk::Status VulkanPasses::RaygenSurface(const vk::Kernel& kernel, const emu::call::Raygen& call, emu::SparseRays& out) {
  const layout::FrameConstants& fc = call.frame;
  const std::span<const layout::Surface> surfaces = call.surfaces;
  const SceneBuffers& scene = *call.scene;
  vk::Context& c = *ctx_;
  out.rays.assign(surfaces.size(), layout::Ray{});
  out.flags.assign(surfaces.size(), 0);
  Keep keep;
  const vk::Buffer *bm = nullptr, *bf = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::Material>(scene.materials), bm));
  RS_TRY(keep.From(c, std::span<const layout::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(surfaces.size(), PerPart(sizeof(layout::Surface)), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bs = nullptr, *br = nullptr, *bflags = nullptr;
                    RS_TRY(keep.From(c, Slice(surfaces, i0, i1), bs));
                    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(layout::Ray), br, out.rays.data() + i0));
                    RS_TRY(keep.Output(c, (i1 - i0) * 4, bflags, out.flags.data() + i0));
                    const layout::RaygenPush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(i0)};
                    Bindings<layout::kRaygenBindings> b;
                    b.Set(layout::kRaygenBindSurfaces, bs).Set(layout::kRaygenBindLightsOrMaterials, bm).Set(layout::kRaygenBindFrame, bf);
                    b.Set(layout::kRaygenBindRays, br).Set(layout::kRaygenBindFlags, bflags);
                    return rec.Dispatch(kernel, b.All(), &push, sizeof push, push.surface_count);
                  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Run(const emu::call::Raygen& c, emu::SparseRays& out) {
  switch (c.kind) {
    case layout::kRayShadow: return RaygenShadow(c, out);
    case layout::kRayReflection: return RaygenSurface(K(PassId::kRaygenReflection), c, out);
    case layout::kRayRefraction: return RaygenSurface(K(PassId::kRaygenRefraction), c, out);
  }
  return vk::Status::Fail(fmt::format("raygen: {} is not a ray kind", c.kind));
}

}  // namespace rayspace::gpu_backend
