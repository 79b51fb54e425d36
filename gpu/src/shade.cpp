// Launch of the shade kernel (gpu/shaders/shade.comp): lighting added into the fixed-point accumulator.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

vk::Status VulkanPasses::Run(const emu::call::Shade& call, std::monostate&) {
  const std::span<const layout::Surface> surfaces = call.surfaces;
  const std::span<const std::uint32_t> shadow_flags = call.shadow_flags, shadow_offsets = call.shadow_offsets,
                                       occluded = call.occluded;
  const SceneBuffers& scene = *call.scene;
  std::vector<std::uint64_t>& accum = *call.accum;
  vk::Context& c = *ctx_;
  const std::size_t lights = scene.lights.size(), slots = ShadowSlots(scene.lights);
  Keep keep;
  const vk::Buffer *bm = nullptr, *bl = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::Material>(scene.materials), bm));
  RS_TRY(keep.From(c, std::span<const layout::Light>(scene.lights), bl));
  // Occlusion is read by dense shadow ray and the accumulator added to by pixel, in any order.
  Paged occ, acc;
  RS_TRY(MakePaged(c, std::span<const std::uint32_t>(occluded), "shade: occlusion flags", occ, paged_arrays_));
  RS_TRY(MakePaged(c, std::span<const std::uint64_t>(accum), "shade: colour accumulator", acc, paged_arrays_));
  vk::Recorder rec(c);
  RS_TRY(ForParts(surfaces.size(), PerPart(std::max(sizeof(layout::Surface), slots * 4)), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bs = nullptr, *bfl = nullptr, *boff = nullptr;
                    RS_TRY(keep.From(c, Slice(surfaces, i0, i1), bs));
                    RS_TRY(keep.From(c, Slice(shadow_flags, i0 * slots, i1 * slots), bfl));
                    RS_TRY(keep.From(c, Slice(shadow_offsets, i0 * slots, i1 * slots), boff));
                    const layout::ShadePush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(lights), occ.page,
                                              acc.page, static_cast<std::uint32_t>(slots)};
                    Bindings<layout::kShadeBindings> b;
                    b.Set(layout::kShadeBindSurfaces, bs).Set(layout::kShadeBindShadowFlags, bfl).Set(layout::kShadeBindShadowOffsets, boff);
                    b.Set(layout::kShadeBindMaterials, bm).Set(layout::kShadeBindLights, bl);
                    b.Set(layout::kShadeBindOccluded, occ).Set(layout::kShadeBindAccum, acc);
                    return rec.Dispatch(K(PassId::kShade), b.All(), &push, sizeof push, push.surface_count);
                  }));
  RS_TRY(rec.Submit());
  RS_TRY(acc.Read(std::span<std::uint64_t>(accum)));
  return vk::Status::Ok();
}


}  // namespace rayspace::gpu_backend
