// Launch of the resolve kernel (gpu/shaders/resolve.comp): fixed point to 8-bit RGB.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

vk::Status VulkanPasses::Run(const emu::call::Resolve& call, std::vector<std::uint8_t>& out) {
  const gpu::FrameConstants& fc = call.frame;
  const std::span<const std::uint64_t> accum = call.accum;
  vk::Context& c = *ctx_;
  const std::size_t n = static_cast<std::size_t>(fc.dims.x) * fc.dims.y * 3;
  if (accum.size() != n) return vk::Status::Fail(fmt::format("resolve: {} accumulator channels for {} pixel channels", accum.size(), n));
  std::vector<std::uint32_t> wide(n);
  Keep keep;
  vk::Recorder rec(c);
  RS_TRY(ForParts(n, PerPart(sizeof(std::uint64_t)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *ba = nullptr, *brgb = nullptr;
    RS_TRY(keep.From(c, Slice(accum, i0, i1), ba));
    RS_TRY(keep.Output(c, (i1 - i0) * 4, brgb, wide.data() + i0));
    const gpu::ResolvePush push{static_cast<std::uint32_t>(i1 - i0)};
    Bindings<gpu::kResolveBindings> b;
    b.Set(gpu::kResolveBindAccum, ba).Set(gpu::kResolveBindRgb, brgb);
    return rec.Dispatch(K(PassId::kResolve), b.All(), &push, sizeof push, push.n);
  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(wide[i]);
  return vk::Status::Ok();
}


}  // namespace rayspace::gpu_backend
