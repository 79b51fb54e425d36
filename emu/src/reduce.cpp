// Stream reduction of (flag, value) slots: Roger et al.'s hierarchical reduction (components of s
// slots reduced on their own, then concatenated) or a plain scan. Mirrors gpu/shaders/reduce.comp.
#include <algorithm>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

std::vector<std::uint32_t> ReduceScan(In<std::uint8_t> flags, In<std::uint32_t> values) {
  std::vector<std::uint32_t> f(flags.begin(), flags.end());
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> off = ExclusiveScan(f, &total, KernelSite::Of("reduce"));
  std::vector<std::uint32_t> out(total);
  ParallelFor(flags.size(), [&](std::size_t i) {
    if (flags[i]) out[off[i]] = values[i];
  });
  return out;
}

std::vector<std::uint32_t> ReduceHierarchical(In<std::uint8_t> flags, In<std::uint32_t> values, int component) {
  // Roger et al. §4.1: reduce each component of s slots on its own, then concatenate the segments
  // at offsets given by a scan of the per-component counts.
  const std::size_t n = flags.size(), s = static_cast<std::size_t>(component);
  const std::size_t comps = (n + s - 1) / s;
  std::vector<std::uint32_t> local(n), counts(comps);
  ParallelFor(comps, [&](std::size_t c) {
    std::uint32_t k = 0;
    for (std::size_t i = c * s; i < std::min(n, (c + 1) * s); ++i)
      if (flags[i]) local[c * s + k++] = values[i];
    counts[c] = k;
  });
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> off = ExclusiveScan(counts, &total, KernelSite::Of("reduce"));
  std::vector<std::uint32_t> out(total);
  ParallelFor(comps, [&](std::size_t c) {
    for (std::uint32_t k = 0; k < counts[c]; ++k) out[off[c] + k] = local[c * s + k];
  });
  return out;
}

std::vector<std::uint32_t> PassReduce(const call::Reduce& c) {
  return c.reduction == Reduction::kHierarchical ? ReduceHierarchical(c.flags, c.values, c.component)
                                                 : ReduceScan(c.flags, c.values);
}

}  // namespace rayspace::emu
