// Launches of the reduce kernel (gpu/shaders/reduce.comp): Roger et al.'s hierarchical stream
// reduction or the scan-based one, over parts that fit one binding.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

namespace {

// One stream reduction in reduce.comp: hierarchical with components of s slots (phases 0-4), or
// scan-based (phases 10, 2, 11) when `scan`.
vk::Status RunReduce(vk::Context& c, const vk::Kernel& k, std::span<const std::uint32_t> flags,
                     std::span<const std::uint32_t> values, std::uint32_t s, bool scan, std::vector<std::uint32_t>& out) {
  const std::uint32_t n = static_cast<std::uint32_t>(flags.size());
  const std::uint32_t comps = scan ? 0 : (n + s - 1) / s, blocks = Blocks(scan ? n : comps);
  vk::Buffer bf, bv, bl, bc, bs, bo;
  RS_TRY(MakeFrom(c, flags, bf));
  RS_TRY(MakeFrom(c, values, bv));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(scan ? 1 : n, 1) * 4, bl));      // per-component values
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(comps, 1) * 4, bc));              // per-component counts
  RS_TRY(c.CreateBuffer((blocks + 1) * 4, bs));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * 4, bo));
  Bindings<layout::kReduceBindings> b;
  b.Set(layout::kReduceBindFlags, &bf).Set(layout::kReduceBindValues, &bv).Set(layout::kReduceBindLocal, &bl);
  b.Set(layout::kReduceBindCounts, &bc).Set(layout::kReduceBindSums, &bs).Set(layout::kReduceBindOut, &bo);
  static constexpr std::uint32_t kHierPhases[5] = {layout::kReducePhaseLocal, layout::kReducePhaseBlockSums, layout::kReducePhaseScanSums,
                                                   layout::kReducePhaseOffsets, layout::kReducePhaseConcat};
  static constexpr std::uint32_t kScanPhases[3] = {layout::kReducePhaseFlagSums, layout::kReducePhaseScanSums, layout::kReducePhaseScatter};
  const std::span<const std::uint32_t> phases = scan ? std::span<const std::uint32_t>(kScanPhases) : std::span<const std::uint32_t>(kHierPhases);
  vk::Recorder rec(c);
  for (std::uint32_t phase : phases) {
    const layout::ReducePush push{n, phase, scan ? 1u : s, comps, blocks};
    if (phase == layout::kReducePhaseLocal || phase == layout::kReducePhaseConcat) {
      // a subgroup per component, at most kReduceStrideGroups workgroups; the kernel strides over the rest
      const std::uint64_t per_group = (k.local_size() + c.subgroup_size() - 1) / c.subgroup_size();  // SubgroupSlots()
      const std::uint64_t groups = std::min<std::uint64_t>(layout::kReduceStrideGroups, (comps + per_group - 1) / per_group);
      RS_TRY(rec.DispatchGroups(k, b.All(), &push, sizeof push, groups));
    } else {  // a workgroup per block, or one for the scan of the block sums
      RS_TRY(rec.DispatchGroups(k, b.All(), &push, sizeof push, phase == layout::kReducePhaseScanSums ? 1 : blocks));
    }
  }
  RS_TRY(rec.Submit());
  std::vector<std::uint32_t> sums;
  RS_TRY(bs.Download(blocks + 1, sums));
  const std::uint32_t total = sums[blocks];
  if (total > n) return vk::Status::Fail(fmt::format("reduce kernel reported {} of {} slots", total, n));
  RS_TRY(bo.Download(total, out));
  return vk::Status::Ok();
}

}  // namespace

// Order-preserving compaction composes: reducing consecutive parts and concatenating their outputs
// gives the whole stream's result, so big streams are reduced in parts that fit the split size
// (hierarchical parts end on component boundaries).
vk::Status VulkanPasses::ReduceInParts(std::span<const std::uint8_t> flags, std::span<const std::uint32_t> values,
                                       std::uint32_t s, bool scan, std::vector<std::uint32_t>& out) {
  out.clear();
  std::vector<std::uint32_t> wide, part;  // reused by the parts: the kernel reads 32-bit flags
  const std::size_t n = flags.size(), per = scan ? StreamPerPart(4) : std::max<std::size_t>(1, StreamPerPart(4) / s) * s;
  std::size_t p0 = 0;
  do {
    const std::size_t len = std::min(n - p0, per);
    if (p0 != 0) ++extra_dispatches_;
    wide.assign(flags.begin() + static_cast<std::ptrdiff_t>(p0), flags.begin() + static_cast<std::ptrdiff_t>(p0 + len));
    RS_TRY(RunReduce(*ctx_, K(PassId::kReduce), wide, values.subspan(p0, len), s, scan, part));
    out.insert(out.end(), part.begin(), part.end());
    p0 += len;
  } while (p0 < n);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Run(const emu::call::Reduce& call, std::vector<std::uint32_t>& out) {
  const std::span<const std::uint8_t> flags = call.flags;
  if (call.reduction == emu::Reduction::kHierarchical)
    return ReduceInParts(flags, call.values, static_cast<std::uint32_t>(call.component), false, out);
  return ReduceInParts(flags, call.values, 1, true, out);
}

}  // namespace rayspace::gpu_backend
