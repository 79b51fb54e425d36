// Order-preserving compaction: exclusive scan of the head flags, then scatter (thesis §3.2.3). Mirrors
// gpu/shaders/trim.comp: reduce-then-scan over blocks, one workgroup a block (emu/workgroup_ops.h).
#include "rayspace/contract.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/workgroup_ops.h"

namespace rayspace::emu {

std::vector<std::uint32_t> ExclusiveScan(In<std::uint32_t> in, std::uint32_t* total, const KernelSite& site) {
  std::vector<std::uint32_t> out(in.size());
  const std::uint32_t sum = ReduceThenScan(
      site, in.size(), [&](std::size_t i) { return in[i]; }, [&](std::size_t i, std::uint32_t s) { out[i] = s; });
  if (total) *total = sum;
  return out;
}

Trimmed PassTrim(const call::Trim& c) {
  Trimmed t;
  const In<std::uint32_t> flags = c.flags;
  t.offsets.resize(flags.size());
  ReduceThenScan(
      KernelSite::Of("trim"), flags.size(), [&](std::size_t i) { return flags[i]; },
      [&](std::size_t i, std::uint32_t s) {
        t.offsets[i] = s;
        // A dense index past the stream (only a planted wrong offset makes one) is not stored. The
        // device enables no robust buffer access: there the store lands in the buffer's guard words,
        // which fail the call (docs/gpu.md, "Guard words"); here the wrong offsets differ already.
        if (flags[i] && s < t.rays.size()) t.rays[s] = c.rays[i];
      },
      [&](std::uint32_t count) { t.rays.resize(count); });
  return t;
}

}  // namespace rayspace::emu
