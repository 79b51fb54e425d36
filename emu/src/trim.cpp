// Order-preserving compaction: exclusive scan of the head flags, then scatter (thesis §3.2.3).
#include "rayspace/contract.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::vector<std::uint32_t> ExclusiveScan(In<std::uint32_t> in, std::uint32_t* total) {
  // Three phases over fixed-size blocks, as a GPU scan does: block sums, scan of the sums, block scan.
  constexpr std::size_t kBlock = layout::kScanBlock;
  const std::size_t n = in.size(), blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::uint32_t> sums(blocks, 0), out(n);
  ParallelFor(blocks, [&](std::size_t b) {
    std::uint32_t s = 0;
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) s += in[i];
    sums[b] = s;
  });
  std::uint32_t run = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::uint32_t s = sums[b];
    sums[b] = run;
    run += s;
  }
  ParallelFor(blocks, [&](std::size_t b) {
    std::uint32_t s = sums[b];
    for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
      out[i] = s;
      s += in[i];
    }
  });
  if (total) *total = run;
  return out;
}

Trimmed PassTrim(const call::Trim& c) {
  Trimmed t;
  std::uint32_t count = 0;
  t.offsets = ExclusiveScan(c.flags, &count);
  t.rays.resize(count);
  ParallelFor(c.flags.size(), [&](std::size_t i) {
    if (c.flags[i]) t.rays[t.offsets[i]] = c.rays[i];
  });
  return t;
}

}  // namespace rayspace::emu
