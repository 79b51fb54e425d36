#version 460
// Chunk compression, radix sort and decompression (thesis §3.2.4-3.2.6) in phases selected by a
// push constant; mirrors emu PassCompress, PassSortChunks and PassDecompress. Every loop is bounded
// by a block of 4096 elements, 256 bins or the block count: lavapipe stops any loop after 65,535
// iterations (observed: a single-invocation compress saturated at 65,535 chunks).
#include "common.glsl"

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

void ScanSums(uint blocks) {  // exclusive scan of sums[0..blocks), total in sums[blocks]
  uint run = 0u;
  for (uint b = 0u; b < blocks; ++b) {
    const uint s = sums[b];
    sums[b] = run;
    run += s;
  }
  sums[blocks] = run;
}

void main() {
  const uint t = GlobalIndex();
  const uint n = pc.n, blocks = pc.blocks;
  switch (pc.phase) {
    // ---- compress over n keys: head flags, block sums, scan, chunk key/base, chunk sizes ----
    case kCompressPhaseHeads:
      if (t < n) scratch[t] = (t == 0u || keys[t] != keys[t - 1u]) ? 1u : 0u;
      break;
    case kCompressPhaseBlockSums:
      if (t < blocks) {
        uint s = 0u;
        for (uint i = t * kScanBlock; i < min(n, (t + 1u) * kScanBlock); ++i) s += scratch[i];
        sums[t] = s;
      }
      break;
    case kCompressPhaseScanSums:
      if (t == 0u) {
        ScanSums(blocks);
        count[0] = sums[blocks];
      }
      break;
    case kCompressPhaseChunks:
      if (t < blocks) {
        uint k = sums[t];
        for (uint i = t * kScanBlock; i < min(n, (t + 1u) * kScanBlock); ++i) {
          if (scratch[i] != 0u) {
            chunk_key[k] = keys[i];
            chunk_base[k] = i;
            ++k;
          }
        }
      }
      break;
    case kCompressPhaseSizes: {
      const uint chunks = count[0];
      // Fault 1 (compress): the last chunk loses its last ray.
      const uint end = kFault == 1u ? n - 1u : n;
      if (t < chunks) chunk_size[t] = (t + 1u < chunks ? chunk_base[t + 1u] : end) - chunk_base[t];
      break;
    }
    // ---- one LSD radix pass over n chunks (8 bits at `shift`), sorted[src..] -> sorted[dst..] ----
    case kSortPhaseInit:
      if (t < n) sorted[t] = t;
      break;
    case kSortPhaseHistograms:  // per-block histograms, bin-major: scratch[bin * blocks + block]
      if (t < blocks) {
        uint hist[256];
        for (uint b = 0u; b < 256u; ++b) hist[b] = 0u;
        for (uint i = t * kScanBlock; i < min(n, (t + 1u) * kScanBlock); ++i) ++hist[(chunk_key[sorted[pc.src + i]] >> pc.shift) & 255u];
        for (uint b = 0u; b < 256u; ++b) scratch[b * blocks + t] = hist[b];
      }
      break;
    case kSortPhaseBinScan:  // per bin: exclusive scan over blocks, bin total to scratch[256 * blocks + bin]
      if (t < 256u) {
        uint run = 0u;
        for (uint b = 0u; b < blocks; ++b) {
          const uint h = scratch[t * blocks + b];
          scratch[t * blocks + b] = run;
          run += h;
        }
        scratch[256u * blocks + t] = run;
      }
      break;
    case kSortPhaseTotalScan:  // exclusive scan of the bin totals
      if (t == 0u) {
        uint run = 0u;
        for (uint b = 0u; b < 256u; ++b) {
          const uint h = scratch[256u * blocks + b];
          scratch[256u * blocks + b] = run;
          run += h;
        }
      }
      break;
    case kSortPhaseScatter:  // stable scatter, one block per invocation in element order
      if (t < blocks) {
        uint local[256];
        for (uint b = 0u; b < 256u; ++b) local[b] = 0u;
        for (uint i = t * kScanBlock; i < min(n, (t + 1u) * kScanBlock); ++i) {
          const uint c = sorted[pc.src + i];
          const uint bin = (chunk_key[c] >> pc.shift) & 255u;
          sorted[pc.dst + scratch[256u * blocks + bin] + scratch[bin * blocks + t] + local[bin]] = c;
          // Fault 1 (sort): a bin's running position is not advanced in the top byte's pass.
          if (!(kFault == 1u && pc.shift == 24u)) ++local[bin];
        }
      }
      break;
    // ---- decompress: sizes in sorted order, scan, then every ray finds its chunk ----
    case kDecompressPhaseSizes:  // n = chunks here
      if (t < n) scratch[t] = chunk_size[sorted[t]];
      break;
    case kDecompressPhaseBlockSums:
      if (t < blocks) {
        uint s = 0u;
        for (uint i = t * kScanBlock; i < min(n, (t + 1u) * kScanBlock); ++i) s += scratch[i];
        sums[t] = s;
      }
      break;
    case kDecompressPhaseScanSums:
      if (t == 0u) ScanSums(blocks);
      break;
    case kDecompressPhaseStarts:  // chunk starts into scratch[n + j]
      if (t < blocks) {
        uint s = sums[t];
        for (uint i = t * kScanBlock; i < min(n, (t + 1u) * kScanBlock); ++i) {
          scratch[n + i] = s;
          s += scratch[i];
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
