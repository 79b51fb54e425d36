// Launch of the hash kernel (gpu/shaders/hash.comp): a sort key per ray.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

vk::Status VulkanPasses::Run(const emu::call::Hash& call, std::vector<std::uint32_t>& keys) {
  const std::span<const layout::Ray> rays = call.rays;
  const emu::HashConfig& h = call.hash;
  const std::uint32_t quad_width = call.quadtree_width, quad_depth = static_cast<std::uint32_t>(call.quadtree_depth);
  // The kernel reads the scene box from the frame constants; nothing else of them.
  layout::FrameConstants fc{};
  fc.scene_lo = glm::vec4(call.scene->lo, 0.0f);
  fc.scene_hi = glm::vec4(call.scene->hi, 0.0f);
  vk::Context& c = *ctx_;
  keys.assign(rays.size(), 0);
  Keep keep;
  const vk::Buffer* bf = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(rays.size(), PerPart(sizeof(layout::Ray)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *br = nullptr, *bk = nullptr;
    RS_TRY(keep.From(c, Slice(rays, i0, i1), br));
    RS_TRY(keep.Output(c, (i1 - i0) * 4, bk, keys.data() + i0));
    const layout::HashPush push{static_cast<std::uint32_t>(i1 - i0), h.light_bits, h.polar_bits, h.azimuth_bits, h.origin_bits,
                             h.direction_bits, quad_width, quad_depth, h.order};
    Bindings<layout::kHashBindings> b;
    b.Set(layout::kHashBindRays, br).Set(layout::kHashBindFrame, bf).Set(layout::kHashBindKeys, bk);
    return rec.Dispatch(K(PassId::kHash), b.All(), &push, sizeof push, push.n);
  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  return vk::Status::Ok();
}


}  // namespace rayspace::gpu_backend
