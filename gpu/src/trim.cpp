// Launch of the trim kernel (gpu/shaders/trim.comp): order-preserving compaction of ray slots.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

// A stream larger than one binding is trimmed in consecutive parts, one submit each: the part's
// offsets start at the flagged count of the parts before it (read back from the GPU), and the dense
// rays of the parts are concatenated, which is what order-preserving compaction of the whole gives.
vk::Status VulkanPasses::Run(const emu::call::Trim& call, emu::Trimmed& out) {
  const emu::call::Trim& in = call;
  vk::Context& c = *ctx_;
  out.offsets.assign(in.flags.size(), 0);
  out.rays.clear();
  std::uint32_t carry = 0;
  return ForParts(in.flags.size(), PerPart(sizeof(layout::Ray)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>(i1 - i0), blocks = Blocks(n);
    vk::Buffer bflags, bsums, boff, bsparse, bdense;
    RS_TRY(MakeFrom(c, Slice(in.flags, i0, i1), bflags));
    RS_TRY(c.CreateBuffer((blocks + 1) * sizeof(std::uint32_t), bsums));
    RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * sizeof(std::uint32_t), boff));
    RS_TRY(MakeFrom(c, Slice(in.rays, i0, i1), bsparse));
    RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * sizeof(layout::Ray), bdense));  // upper bound; the scan gives the count
    Bindings<layout::kTrimBindings> b;
    b.Set(layout::kTrimBindFlags, &bflags).Set(layout::kTrimBindSums, &bsums).Set(layout::kTrimBindOffsets, &boff);
    b.Set(layout::kTrimBindSparse, &bsparse).Set(layout::kTrimBindDense, &bdense);
    vk::Recorder rec(c);
    // One submit for the three dispatches.
    for (std::uint32_t phase : {layout::kTrimPhaseBlockSums, layout::kTrimPhaseScanSums, layout::kTrimPhaseScatter}) {
      const layout::TrimPush push{n, phase, carry};
      // One workgroup per block of kScanBlock slots; the scan of the block sums is one workgroup.
      RS_TRY(rec.DispatchGroups(K(PassId::kTrim), b.All(), &push, sizeof push, phase == layout::kTrimPhaseScanSums ? 1 : blocks));
    }
    RS_TRY(rec.Submit());
    std::vector<std::uint32_t> sums;
    RS_TRY(bsums.Download(blocks + 1, sums));
    const std::uint32_t total = sums[blocks];
    if (total > n) return vk::Status::Fail(fmt::format("trim kernel reported {} rays out of {} slots", total, n));
    if (n) RS_TRY(boff.Read(out.offsets.data() + i0, std::size_t{n} * 4));
    const std::size_t at = out.rays.size();
    out.rays.resize(at + total);
    if (total) RS_TRY(bdense.Read(out.rays.data() + at, std::size_t{total} * sizeof(layout::Ray)));
    carry += total;
    return vk::Status::Ok();
  });
}


}  // namespace rayspace::gpu_backend
