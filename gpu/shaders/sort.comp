#version 460
// Chunk compression, radix sort and decompression (thesis §3.2.4-3.2.6) in phases selected by a
// push constant; mirrors emu PassCompress, PassSortChunks and PassDecompress. Element-wise phases run
// one invocation per element; the others one workgroup per block of kScanBlock elements, per bin, or
// one workgroup for a scan of block sums or bin totals (gpu/shaders/workgroup.glsl). Every loop is
// bounded: lavapipe stops any loop after 65,535 iterations.
#include "common.glsl"
#include "workgroup.glsl"

layout(std430, binding = kSortBindKeys) readonly buffer Keys { uint keys[]; };
layout(std430, binding = kSortBindChunkKey) buffer ChunkKey { uint chunk_key[]; };
layout(std430, binding = kSortBindChunkBase) buffer ChunkBase { uint chunk_base[]; };
layout(std430, binding = kSortBindChunkSize) buffer ChunkSize { uint chunk_size[]; };
layout(std430, binding = kSortBindSorted) buffer Sorted { uint sorted[]; };   // chunk indices, 2 x chunks (ping-pong)
layout(std430, binding = kSortBindOrder) buffer Order { uint order[]; };     // ray order (n)
layout(std430, binding = kSortBindCount) buffer Count { uint count[]; };     // [0] number of chunks
layout(std430, binding = kSortBindScratch) buffer Scratch { uint scratch[]; };
layout(std430, binding = kSortBindSums) buffer Sums { uint sums[]; };       // per block, plus a total
layout(push_constant) uniform Block { SortPush pc; };

shared uint bins[256];
// Per digit, a bit per element of the scatter's step (at most kSortRankStep): sized by the local size.
const uint kMarkWords = ((kLocalSize < kSortRankStep ? kLocalSize : kSortRankStep) + 31u) / 32u;
shared uint marks[256u * kMarkWords];

// The radix pass's stable scatter of block g: kSortRankStep elements at a time (fewer when the
// workgroup is smaller) in element order. Each element sets its bit in its digit's marks; its rank
// among the step's earlier elements of that digit is the count of marked bits before its own, at most
// kMarkWords words read; `bins` carries each digit's count over the block's earlier steps, and the
// last element of each digit in the step advances it, so every bin has one writer. The positions are
// the stable counting sort's whatever the workgroup size.
void RankAndScatter(uint g, uint n, uint blocks) {
  const uint l = gl_LocalInvocationID.x, step = min(kLocalSize, kSortRankStep);
  for (uint b = l; b < 256u; b += kLocalSize) bins[b] = 0u;
  for (uint b = l; b < 256u * kMarkWords; b += kLocalSize) marks[b] = 0u;
  barrier();  // bins and marks cleared
  const uint end = min(n, (g + 1u) * kScanBlock), word = l >> 5u, bit = 1u << (l & 31u);
  for (uint c0 = g * kScanBlock; c0 < end; c0 += step) {
    const bool mine = l < step && c0 + l < end;
    const uint c = mine ? sorted[pc.src + c0 + l] : 0u;
    const uint digit = mine ? (chunk_key[c] >> pc.shift) & 255u : 0u, row = digit * kMarkWords;
    if (mine) atomicOr(marks[row + word], bit);
    barrier();  // the step's marks and the previous step's bins are visible
    uint before = 0u;
    bool last = true;
    if (mine) {
      for (uint w = 0u; w < word; ++w) before += uint(bitCount(marks[row + w]));
      const uint own = marks[row + word];
      // Fault 2 (sort): an element counts itself among the earlier ones of its digit.
      before += uint(bitCount(own & (kFault == 2u ? bit | (bit - 1u) : bit - 1u)));
      last = (own & ~(bit | (bit - 1u))) == 0u;
      for (uint w = word + 1u; w < kMarkWords; ++w) last = last && marks[row + w] == 0u;
      // Fault 3 (sort): each digit starts at the next digit's base (the total scan read as inclusive).
      const uint base_digit = kFault == 3u ? min(digit + 1u, 255u) : digit;
      sorted[pc.dst + scratch[256u * blocks + base_digit] + scratch[digit * blocks + g] + bins[digit] + before] = c;
    }
    barrier();  // every bin and mark read before they change
    if (mine) {
      atomicAnd(marks[row + word], ~bit);  // atomics: the next step's marks may share the word
      // Fault 1 (sort): a bin's running position is not advanced in the top byte's pass.
      if (last && !(kFault == 1u && pc.shift == 24u)) bins[digit] += before + 1u;
    }
  }
}

// The bins per workgroup of the bin scan (rayspace/contract.h's SortBinsPerGroup, which the host
// sizes the launch by): one while a bin's blocks fill half a workgroup, else as many whole bins (a
// power of two, so they divide 256) as one pass of the workgroup holds. With few blocks a workgroup per
// bin would leave most invocations idle through every barrier, 256 workgroups per radix pass; packed,
// a frame of a few blocks scans in 256 / per workgroups of one step each.
uint SortBinsPerGroup(uint blocks) {
  uint per = 1u;
  for (uint k = 0u; k < 8u && blocks > 0u && 2u * per * blocks <= kLocalSize; ++k) per *= 2u;
  return per;
}

// Bins g * per .. (g + 1) * per - 1 in one pass of the workgroup: their per * blocks counts lie side by
// side (bin-major), so one inclusive scan over the workgroup covers them; the first element of each bin
// publishes the scan before its bin in `bins`, and every element subtracts its bin's, which leaves each
// bin's own exclusive scan. The last element of a bin writes the bin's total.
void ScanPackedBins(uint g, uint per, uint blocks) {
  const uint r = WorkgroupRank(), count = per * blocks, first = g * count;
  const uint v = r < count ? scratch[first + r] : 0u;
  uint total;
  const uint inclusive = WorkgroupInclusiveAdd(v, total);
  const uint bin = r / blocks, j = r - bin * blocks;
  if (r < count && j == 0u) bins[bin] = inclusive - v;
  barrier();  // every bin's start published
  if (r < count) {
    const uint base = bins[bin];
    scratch[first + r] = inclusive - v - base;
    if (j + 1u == blocks) scratch[256u * blocks + g * per + bin] = inclusive - base;
  }
}

void main() {
  const uint t = GlobalIndex(), g = WorkGroupIndex(), l = gl_LocalInvocationID.x;
  const uint n = pc.n, blocks = pc.blocks;
  uint total;
  switch (pc.phase) {
    // ---- compress over n keys: head flags, block sums, scan, chunk key/base, chunk sizes ----
    case kCompressPhaseHeads:
      if (t < n) scratch[t] = (t == 0u || keys[t] != keys[t - 1u]) ? 1u : 0u;
      break;
    case kCompressPhaseBlockSums:  // one workgroup per block
      if (g < blocks) {
        WORKGROUP_SUM(scratch, g * kScanBlock, min(n, (g + 1u) * kScanBlock), total);
        if (l == 0u) sums[g] = total;
      }
      break;
    case kCompressPhaseScanSums:  // one workgroup
      if (g == 0u) {
        WORKGROUP_SCAN_IN_PLACE(sums, 0u, blocks, WorkgroupRank(), total);
        if (l == 0u) {
          sums[blocks] = total;
          // Fault 3 (compress): the chunk count is the last chunk's index, not the count.
          count[0] = kFault == 3u ? total - 1u : total;
        }
      }
      break;
    case kCompressPhaseChunks:  // one workgroup per block: heads find their chunk index by a scan
      if (g < blocks) {
        uint k = sums[g];
        const uint end = min(n, (g + 1u) * kScanBlock), r = WorkgroupRank();
        for (uint c0 = g * kScanBlock; c0 < end; c0 += kLocalSize) {
          const uint i = c0 + r;
          const uint head = i < end ? scratch[i] : 0u;
          const uint at = k + (WorkgroupInclusiveAdd(head, total) - head);
          if (head != 0u) {
            chunk_key[at] = keys[i];
            chunk_base[at] = i;
          }
          k += total;
        }
      }
      break;
    case kCompressPhaseSizes: {
      const uint chunks = count[0];
      // Fault 1 (compress): the last chunk loses its last ray.
      const uint end = kFault == 1u ? n - 1u : n;
      // Fault 2 (compress): every chunk but the last reaches one ray into the next (an off-by-one bound).
      const uint over = kFault == 2u ? 1u : 0u;
      if (t < chunks) chunk_size[t] = (t + 1u < chunks ? chunk_base[t + 1u] + over : end) - chunk_base[t];
      break;
    }
    // ---- one LSD radix pass over n chunks (8 bits at `shift`), sorted[src..] -> sorted[dst..] ----
    case kSortPhaseInit:
      if (t < n) sorted[t] = t;
      break;
    case kSortPhaseHistograms:  // one workgroup per block, a shared histogram; bin-major: scratch[bin * blocks + block]
      if (g < blocks) {
        for (uint b = l; b < 256u; b += kLocalSize) bins[b] = 0u;
        barrier();
        const uint end = min(n, (g + 1u) * kScanBlock);
        for (uint i = g * kScanBlock + l; i < end; i += kLocalSize)
          atomicAdd(bins[(chunk_key[sorted[pc.src + i]] >> pc.shift) & 255u], 1u);  // counts: any order
        barrier();
        for (uint b = l; b < 256u; b += kLocalSize) scratch[b * blocks + g] = bins[b];
      }
      break;
    case kSortPhaseBinScan: {  // per bin: exclusive scan over blocks, total to scratch[256 * blocks + bin]
      const uint per = SortBinsPerGroup(blocks);
      if (g < 256u / per) {
        if (per == 1u) {
          WORKGROUP_SCAN_IN_PLACE(scratch, g * blocks, blocks, WorkgroupRank(), total);
          if (l == 0u) scratch[256u * blocks + g] = total;
        } else {
          ScanPackedBins(g, per, blocks);
        }
      }
      break;
    }
    case kSortPhaseTotalScan:  // one workgroup: exclusive scan of the bin totals
      if (g == 0u) WORKGROUP_SCAN_IN_PLACE(scratch, 256u * blocks, 256u, WorkgroupRank(), total);
      break;
    case kSortPhaseScatter:  // stable scatter, one workgroup per block (see RankAndScatter)
      if (g < blocks) RankAndScatter(g, n, blocks);
      break;
    // ---- decompress: sizes in sorted order, scan, then every ray finds its chunk ----
    case kDecompressPhaseSizes:  // n = chunks here
      // Fault 2 (decompress): the sizes are read in chunk order, not sorted order.
      if (t < n) scratch[t] = chunk_size[kFault == 2u ? t : sorted[t]];
      break;
    case kDecompressPhaseBlockSums:  // one workgroup per block
      if (g < blocks) {
        WORKGROUP_SUM(scratch, g * kScanBlock, min(n, (g + 1u) * kScanBlock), total);
        if (l == 0u) sums[g] = total;
      }
      break;
    case kDecompressPhaseScanSums:  // one workgroup
      if (g == 0u) {
        WORKGROUP_SCAN_IN_PLACE(sums, 0u, blocks, WorkgroupRank(), total);
        if (l == 0u) sums[blocks] = total;
      }
      break;
    case kDecompressPhaseStarts:  // one workgroup per block: chunk starts into scratch[n + j]
      if (g < blocks) {
        uint run = sums[g];
        const uint end = min(n, (g + 1u) * kScanBlock), r = WorkgroupRank();
        for (uint c0 = g * kScanBlock; c0 < end; c0 += kLocalSize) {
          const uint i = c0 + r;
          const uint size = i < end ? scratch[i] : 0u;
          const uint start = run + (WorkgroupInclusiveAdd(size, total) - size);
          // Fault 3 (decompress): a chunk starts where it ends (the scan read as inclusive).
          if (i < end) scratch[n + i] = kFault == 3u ? start + size : start;
          run += total;
        }
      }
      break;
    case kDecompressPhaseRays: {  // one invocation per ray; pc.shift carries the ray count here
      const uint rays = pc.shift;
      if (t >= rays || n == 0u) break;
      uint lo = 0u, hi = n - 1u;  // last chunk whose start <= t
      while (lo < hi) {
        const uint mid = (lo + hi + 1u) >> 1;
        if (scratch[n + mid] <= t) lo = mid;
        else hi = mid - 1u;
      }
      // Fault 1 (decompress): the chunk is looked up without the sorted permutation.
      const uint c = kFault == 1u ? lo : sorted[lo], k = t - scratch[n + lo];
      order[t] = chunk_base[c] + k;
      break;
    }
    default:
      break;
  }
}
