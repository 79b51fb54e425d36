// Compress, sort and decompress (thesis §3.2.3-3.2.6, after Garanzha and Loop): equal keys collapse
// into chunks, chunks are radix sorted, then expanded back to rays. Mirrors gpu/shaders/sort.comp.
#include <algorithm>
#include <bit>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/output_checks.h"
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

namespace {

constexpr std::uint32_t kBins = 256;

// One LSD radix pass of sort.comp (8 bits at `shift`, src -> dst), phase for phase: per-block
// histograms in shared memory, a scan over blocks per bin, a scan of the bin totals, and the stable
// scatter, one workgroup per block.
class RadixPass {
 public:
  RadixPass(const KernelSite& site, In<std::uint32_t> keys, std::uint32_t shift, const std::uint32_t* src, std::uint32_t* dst)
      : site_(site), keys_(keys), shift_(shift), src_(src), dst_(dst), n_(static_cast<std::uint32_t>(keys.size())),
        blocks_((n_ + kBlock - 1) / kBlock), scratch_(kBins * blocks_ + kBins) {}

  void Run() {
    DispatchKernel(site_, "Histograms", blocks_, [&](wg::Workgroup& w) { Histogram(w); });
    const std::uint32_t per = layout::SortBinsPerGroup(blocks_, wg::LocalSize());
    DispatchKernel(site_, "BinScan", kBins / per, [&](wg::Workgroup& w) {  // scratch[bin * blocks + block]
      auto& tile = WorkgroupTile(w);
      if (per > 1) return ScanPackedBins(w, tile, per);
      const std::uint32_t total = WorkgroupScanInPlace(w, tile, &scratch_[w.id() * blocks_], blocks_, WorkgroupRank(w, tile), site_.fault);
      w.Phase([&](wg::Inv& i) {
        if (i.local_id == 0) scratch_[kBins * blocks_ + w.id()] = total;
      });
    });
    DispatchKernel(site_, "TotalScan", 1, [&](wg::Workgroup& w) {
      auto& tile = WorkgroupTile(w);
      WorkgroupScanInPlace(w, tile, &scratch_[kBins * blocks_], kBins, WorkgroupRank(w, tile), site_.fault);
    });
    DispatchKernel(site_, "Scatter", blocks_, [&](wg::Workgroup& w) { RankAndScatter(w); });
  }

 private:
  static constexpr std::uint32_t kBlock = layout::kScanBlock;
  std::uint32_t Digit(std::uint32_t i) const { return (keys_[src_[i]] >> shift_) & 255u; }

  void Histogram(wg::Workgroup& w) {
    auto& bins = w.Shared<std::uint32_t>(kBins, "bins");
    const std::uint32_t g = w.id(), end = std::min(n_, (g + 1) * kBlock), step = w.local_size();
    w.Phase([&](wg::Inv& i) {
      for (std::uint32_t b = i.local_id; b < kBins; b += step) bins[b] = 0u;
    });
    w.Barrier();
    w.Phase([&](wg::Inv& i) {  // counts: any order gives the same bits
      for (std::uint32_t k = g * kBlock + i.local_id; k < end; k += step) wg::AtomicAdd(bins[Digit(k)], 1u);
    });
    w.Barrier();
    w.Phase([&](wg::Inv& i) {
      for (std::uint32_t b = i.local_id; b < kBins; b += step) scratch_[b * blocks_ + g] = bins[b];
    });
  }

  // sort.comp's ScanPackedBins: `per` whole bins (per * blocks counts side by side) in one inclusive
  // scan of the workgroup; each bin's first element publishes the scan before the bin.
  void ScanPackedBins(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile, std::uint32_t per) {
    auto& bins = w.Shared<std::uint32_t>(kBins, "bins");
    const std::uint32_t count = per * blocks_, first = w.id() * count;
    const wg::Private<std::uint32_t> r = WorkgroupRank(w, tile);
    wg::Private<std::uint32_t> v = w.Private<std::uint32_t>(), total = w.Private<std::uint32_t>();
    w.Phase([&](wg::Inv& i) { v[i] = r[i] < count ? scratch_[first + r[i]] : 0u; });
    const wg::Private<std::uint32_t> inc = WorkgroupInclusiveAdd(w, tile, v, total, site_.fault);
    w.Phase([&](wg::Inv& i) {
      if (r[i] < count && r[i] % blocks_ == 0u) bins[r[i] / blocks_] = inc[i] - v[i];
    });
    w.Barrier();
    w.Phase([&](wg::Inv& i) {
      if (r[i] >= count) return;
      const std::uint32_t bin = r[i] / blocks_, base = bins[bin];
      scratch_[first + r[i]] = inc[i] - v[i] - base;
      if (r[i] % blocks_ + 1u == blocks_) scratch_[kBins * blocks_ + w.id() * per + bin] = inc[i] - base;
    });
  }

  // sort.comp's RankAndScatter: each element of a step marks its bit in its digit's row and ranks
  // itself by the marked bits before it; the last of each digit advances that digit's bin.
  void RankAndScatter(wg::Workgroup& w) {
    // sort.comp's kMarkWords: a bit per element of a step, the step at most the local size.
    const std::uint32_t kWords = (std::min(w.local_size(), layout::kSortRankStep) + 31u) / 32u;
    auto& bins = w.Shared<std::uint32_t>(kBins, "bins");
    auto& marks = w.Shared<std::uint32_t>(kBins * kWords, "marks");
    const std::uint32_t g = w.id(), end = std::min(n_, (g + 1) * kBlock), size = w.local_size();
    const std::uint32_t step = std::min(size, layout::kSortRankStep);
    wg::Private<std::uint32_t> digit = w.Private<std::uint32_t>(), before = w.Private<std::uint32_t>();
    wg::Private<bool> last = w.Private<bool>();
    w.Phase([&](wg::Inv& i) {
      for (std::uint32_t b = i.local_id; b < kBins; b += size) bins[b] = 0u;
      for (std::uint32_t b = i.local_id; b < kBins * kWords; b += size) marks[b] = 0u;
    });
    w.Barrier();
    const auto mine = [&](const wg::Inv& i, std::uint32_t c0) { return i.local_id < step && c0 + i.local_id < end; };
    const auto bit = [](const wg::Inv& i) { return 1u << (i.local_id & 31u); };
    for (std::uint32_t c0 = g * kBlock; c0 < end; c0 += step) {
      w.Phase([&](wg::Inv& i) {
        if (!mine(i, c0)) return;
        digit[i] = Digit(c0 + i.local_id);
        wg::AtomicOr(marks[digit[i] * kWords + (i.local_id >> 5)], bit(i));
      });
      w.Barrier();
      w.Phase([&](wg::Inv& i) {
        if (!mine(i, c0)) return;
        const std::uint32_t word = i.local_id >> 5, d = digit[i], row = d * kWords;
        before[i] = 0;
        for (std::uint32_t k = 0; k < word; ++k) before[i] += static_cast<std::uint32_t>(std::popcount(std::uint32_t{marks[row + k]}));
        const std::uint32_t own = marks[row + word];
        before[i] += static_cast<std::uint32_t>(std::popcount(own & (bit(i) - 1u)));
        last[i] = (own & ~(bit(i) | (bit(i) - 1u))) == 0u;
        for (std::uint32_t k = word + 1; k < kWords; ++k) last[i] = last[i] && marks[row + k] == 0u;
        const std::uint32_t at = scratch_[kBins * blocks_ + d] + scratch_[d * blocks_ + g] + bins[d] + before[i];
        // Only a fault in the scans (the checker off, or one it cannot see) moves a position past the
        // output: the frame stops there, as no memory outside the buffer is the kernel's to write.
        if (at >= n_) throw DeviceOutputError(fmt::format("{}.Scatter: element {} sent to position {} of {}", site_.pass, c0 + i.local_id, at, n_));
        dst_[at] = src_[c0 + i.local_id];
      });
      w.Barrier();
      w.Phase([&](wg::Inv& i) {
        if (!mine(i, c0)) return;
        wg::AtomicAnd(marks[digit[i] * kWords + (i.local_id >> 5)], ~bit(i));
        if (last[i]) bins[digit[i]] += before[i] + 1u;
      });
    }
  }

  KernelSite site_;
  In<std::uint32_t> keys_;
  std::uint32_t shift_;
  const std::uint32_t* src_;
  std::uint32_t* dst_;
  std::uint32_t n_, blocks_;
  std::vector<std::uint32_t> scratch_;
};

}  // namespace

std::vector<std::uint32_t> PassSortChunks(const call::SortChunks& c) {
  // LSD radix sort, 8 bits per pass: each pass is a stable counting sort, so the whole is stable.
  const std::size_t n = c.chunk_key.size();
  std::vector<std::uint32_t> a(n), b(n);
  ParallelFor(n, [&](std::size_t i) { a[i] = static_cast<std::uint32_t>(i); });  // kSortPhaseInit
  const KernelSite site = KernelSite::Of("sort");
  for (std::uint32_t shift = 0; shift < 32; shift += 8) {
    RadixPass(site, c.chunk_key, shift, a.data(), b.data()).Run();
    a.swap(b);
  }
  return a;
}

std::vector<std::uint32_t> SortChunksHost(const call::SortChunks& c) {
  const std::size_t n = c.chunk_key.size();
  std::vector<std::uint32_t> a(n), b(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = static_cast<std::uint32_t>(i);
  constexpr std::uint32_t kBits = 11, kDigits = 1u << kBits;
  for (std::uint32_t shift = 0; shift < 32; shift += kBits) {
    std::vector<std::uint32_t> count(kDigits + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++count[((c.chunk_key[i] >> shift) & (kDigits - 1)) + 1];
    if (n == 0 || *std::max_element(count.begin(), count.end()) == n) continue;  // one digit: order unchanged
    for (std::uint32_t d = 0; d < kDigits; ++d) count[d + 1] += count[d];
    for (std::size_t i = 0; i < n; ++i) b[count[(c.chunk_key[a[i]] >> shift) & (kDigits - 1)]++] = a[i];
    a.swap(b);
  }
  return a;
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
