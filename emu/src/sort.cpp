// Compress, sort and decompress (thesis §3.2.3-3.2.6, after Garanzha and Loop): equal keys collapse
// into chunks, chunks are radix sorted, then expanded back to rays. Mirrors gpu/shaders/sort.comp.
#include <algorithm>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

Chunks PassCompress(const call::Compress& in) {
  const In<std::uint32_t> keys = in.keys;
  const std::size_t n = keys.size();
  std::vector<std::uint32_t> head(n);
  ParallelFor(n, [&](std::size_t i) { head[i] = (i == 0 || keys[i] != keys[i - 1]) ? 1u : 0u; });
  std::uint32_t chunks = 0;
  const std::vector<std::uint32_t> index = ExclusiveScan(head, &chunks, KernelSite::Of("compress"));
  Chunks c;
  c.key.resize(chunks);
  c.base.resize(chunks);
  c.size.resize(chunks);
  ParallelFor(n, [&](std::size_t i) {
    if (!head[i]) return;
    const std::uint32_t k = index[i];
    c.key[k] = keys[i];
    c.base[k] = static_cast<std::uint32_t>(i);
  });
  ParallelFor(chunks, [&](std::size_t k) {  // a chunk ends where the next starts
    c.size[k] = (k + 1 < chunks ? c.base[k + 1] : static_cast<std::uint32_t>(n)) - c.base[k];
  });
  return c;
}

std::vector<std::uint32_t> PassSortChunks(const call::SortChunks& c) {
  const In<std::uint32_t> chunk_keys = c.chunk_key;
  const std::size_t n = chunk_keys.size();
  std::vector<std::uint32_t> idx(n), tmp(n);
  for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<std::uint32_t>(i);
  // LSD radix sort, 8 bits per pass: each pass is a stable counting sort, so the whole is stable.
  for (int shift = 0; shift < 32; shift += 8) {
    std::uint32_t count[257] = {};
    for (std::uint32_t i : idx) ++count[((chunk_keys[i] >> shift) & 0xFFu) + 1];
    for (int b = 0; b < 256; ++b) count[b + 1] += count[b];
    for (std::uint32_t i : idx) tmp[count[(chunk_keys[i] >> shift) & 0xFFu]++] = i;
    idx.swap(tmp);
  }
  return idx;
}

std::vector<std::uint32_t> PassDecompress(const call::Decompress& c) {
  const In<std::uint32_t> sorted = c.chunk_order;
  std::vector<std::uint32_t> sizes(sorted.size());
  ParallelFor(sorted.size(), [&](std::size_t j) { sizes[j] = c.chunk_size[sorted[j]]; });
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> start = ExclusiveScan(sizes, &total, KernelSite::Of("decompress"));
  std::vector<std::uint32_t> order(total);
  ParallelFor(sorted.size(), [&](std::size_t j) {
    const std::uint32_t base = c.chunk_base[sorted[j]];
    for (std::uint32_t k = 0; k < sizes[j]; ++k) order[start[j] + k] = base + k;
  });
  return order;
}

}  // namespace rayspace::emu
