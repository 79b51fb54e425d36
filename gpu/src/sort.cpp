// Launches of the sort kernel (gpu/shaders/sort.comp) in its three passes: compress equal keys into
// chunks, radix sort the chunk keys, decompress chunks back into a ray order.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

namespace {

// Buffers of the sort kernel (see gpu/shaders/sort.comp for their roles).
struct SortBuffers {
  vk::Buffer keys, key, base, size, sorted, order, count, scratch, sums;
};

vk::Status MakeSortBuffers(vk::Context& c, std::size_t n, std::size_t chunks, SortBuffers& b) {
  const std::size_t w = std::max<std::size_t>(n, 1) * 4, cw = std::max<std::size_t>(chunks, 1) * 4;
  const std::size_t blocks = std::max<std::size_t>(Blocks(std::max(n, chunks)), 1);
  RS_TRY(c.CreateBuffer(w, b.keys));
  RS_TRY(c.CreateBuffer(cw, b.key));
  RS_TRY(c.CreateBuffer(cw, b.base));
  RS_TRY(c.CreateBuffer(cw, b.size));
  RS_TRY(c.CreateBuffer(2 * cw, b.sorted));
  RS_TRY(c.CreateBuffer(w, b.order));
  RS_TRY(c.CreateBuffer(4, b.count));
  RS_TRY(c.CreateBuffer((2 * std::max(n, chunks) + 256 * blocks + 256 + 16) * 4, b.scratch));
  RS_TRY(c.CreateBuffer((blocks + 1) * 4, b.sums));
  return vk::Status::Ok();
}

// A launch of the sort kernel: one invocation per element, or (Groups) one workgroup per block, bin
// or scan.
struct SortLaunch {
  std::uint64_t count;
  bool groups;
};
SortLaunch Elements(std::uint32_t n) { return {n, false}; }
SortLaunch Groups(std::uint64_t g) { return {g, true}; }

vk::Status Phase(vk::Recorder& rec, const vk::Kernel& k, SortBuffers& sb, layout::SortPush push, SortLaunch launch) {
  Bindings<layout::kSortBindings> b;
  b.Set(layout::kSortBindKeys, &sb.keys).Set(layout::kSortBindChunkKey, &sb.key).Set(layout::kSortBindChunkBase, &sb.base);
  b.Set(layout::kSortBindChunkSize, &sb.size).Set(layout::kSortBindSorted, &sb.sorted).Set(layout::kSortBindOrder, &sb.order);
  b.Set(layout::kSortBindCount, &sb.count).Set(layout::kSortBindScratch, &sb.scratch).Set(layout::kSortBindSums, &sb.sums);
  return launch.groups ? rec.DispatchGroups(k, b.All(), &push, sizeof push, launch.count)
                       : rec.Dispatch(k, b.All(), &push, sizeof push, static_cast<std::uint32_t>(launch.count));
}

}  // namespace

vk::Status VulkanPasses::Run(const emu::call::Compress& call, emu::Chunks& out) {
  const std::span<const std::uint32_t> keys = call.keys;
  const std::uint32_t n = static_cast<std::uint32_t>(keys.size()), blocks = Blocks(n);
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, n, n, b));
  if (n) RS_TRY(b.keys.Upload(keys));
  vk::Recorder rec(*ctx_);
  const vk::Kernel& k = K(PassId::kCompress);
  RS_TRY(Phase(rec, k, b, {n, layout::kCompressPhaseHeads, 0, 0, 0, blocks}, Elements(n)));
  RS_TRY(Phase(rec, k, b, {n, layout::kCompressPhaseBlockSums, 0, 0, 0, blocks}, Groups(blocks)));
  RS_TRY(Phase(rec, k, b, {n, layout::kCompressPhaseScanSums, 0, 0, 0, blocks}, Groups(1)));
  RS_TRY(Phase(rec, k, b, {n, layout::kCompressPhaseChunks, 0, 0, 0, blocks}, Groups(blocks)));
  RS_TRY(Phase(rec, k, b, {n, layout::kCompressPhaseSizes, 0, 0, 0, blocks}, Elements(n)));
  RS_TRY(rec.Submit());
  std::vector<std::uint32_t> count;
  RS_TRY(b.count.Download(1, count));
  const std::uint32_t chunks = count[0];
  if (chunks > n) return vk::Status::Fail(fmt::format("compress kernel reported {} chunks for {} keys", chunks, n));
  RS_TRY(b.key.Download(chunks, out.key));
  RS_TRY(b.base.Download(chunks, out.base));
  RS_TRY(b.size.Download(chunks, out.size));
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Run(const emu::call::SortChunks& call, std::vector<std::uint32_t>& sorted) {
  const std::span<const std::uint32_t> chunk_keys = call.chunk_key;
  const std::uint32_t chunks = static_cast<std::uint32_t>(chunk_keys.size()), blocks = Blocks(chunks);
  if (blocks > 65535) return vk::Status::Fail(fmt::format("sort: {} chunks exceed the kernel's limit", chunks));
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, 1, chunks, b));
  if (chunks) RS_TRY(b.key.Upload(chunk_keys));
  vk::Recorder rec(*ctx_);
  const vk::Kernel& k = K(PassId::kSort);
  RS_TRY(Phase(rec, k, b, {chunks, layout::kSortPhaseInit, 0, 0, 0, blocks}, Elements(chunks)));
  const std::uint32_t bins_per_group = layout::SortBinsPerGroup(blocks, k.local_size());
  std::uint32_t src = 0, dst = chunks;
  for (std::uint32_t shift = 0; shift < 32; shift += 8) {
    RS_TRY(Phase(rec, k, b, {chunks, layout::kSortPhaseHistograms, shift, src, dst, blocks}, Groups(blocks)));
    RS_TRY(Phase(rec, k, b, {chunks, layout::kSortPhaseBinScan, shift, src, dst, blocks}, Groups(256 / bins_per_group)));
    RS_TRY(Phase(rec, k, b, {chunks, layout::kSortPhaseTotalScan, shift, src, dst, blocks}, Groups(1)));
    RS_TRY(Phase(rec, k, b, {chunks, layout::kSortPhaseScatter, shift, src, dst, blocks}, Groups(blocks)));
    std::swap(src, dst);
  }
  RS_TRY(rec.Submit());
  RS_TRY(b.sorted.Download(chunks, sorted));  // four passes end in the first half
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Run(const emu::call::Decompress& call, std::vector<std::uint32_t>& order) {
  const std::span<const std::uint32_t> sorted = call.chunk_order;
  const struct {
    std::span<const std::uint32_t> key, base, size;
  } chunks{call.chunk_key, call.chunk_base, call.chunk_size};
  std::uint64_t n = 0;
  for (std::uint32_t s : chunks.size) n += s;
  const std::uint32_t count = static_cast<std::uint32_t>(chunks.key.size()), blocks = Blocks(count);
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, n, count, b));
  if (count) {
    RS_TRY(b.key.Upload(chunks.key));
    RS_TRY(b.base.Upload(chunks.base));
    RS_TRY(b.size.Upload(chunks.size));
    RS_TRY(b.sorted.Upload(sorted));
  }
  const std::uint32_t rays = static_cast<std::uint32_t>(n);
  vk::Recorder rec(*ctx_);
  const vk::Kernel& k = K(PassId::kDecompress);
  RS_TRY(Phase(rec, k, b, {count, layout::kDecompressPhaseSizes, rays, 0, 0, blocks}, Elements(count)));
  RS_TRY(Phase(rec, k, b, {count, layout::kDecompressPhaseBlockSums, rays, 0, 0, blocks}, Groups(blocks)));
  RS_TRY(Phase(rec, k, b, {count, layout::kDecompressPhaseScanSums, rays, 0, 0, blocks}, Groups(1)));
  RS_TRY(Phase(rec, k, b, {count, layout::kDecompressPhaseStarts, rays, 0, 0, blocks}, Groups(blocks)));
  RS_TRY(Phase(rec, k, b, {count, layout::kDecompressPhaseRays, rays, 0, 0, blocks}, Elements(rays)));
  RS_TRY(rec.Submit());
  RS_TRY(b.order.Download(n, order));
  return vk::Status::Ok();
}


}  // namespace rayspace::gpu_backend
