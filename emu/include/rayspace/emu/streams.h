// The buffers passes hand each other: the G-buffer, sparse and trimmed ray arrays, ray-order chunks,
// traversal pair slots, and the two small configurations passes read (hash layout, reduction kind).
//
// Each struct lists its fields once with RS_FIELDS (rayspace/emu/fields.h) so that the diff, the
// saved input sets and `replay` move them as named buffers without restating them.
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/emu/fields.h"
#include "rayspace/emu/uninit_vector.h"
#include "rayspace/contract.h"
#include "rayspace/layout.h"

namespace rayspace::emu {

// ---- raster: MRT G-buffer ------------------------------------------------------------------------
struct GBuffer {
  int width = 0, height = 0;
  std::vector<glm::vec4> diffuse;   // rgb diffuse, a reflectivity
  std::vector<glm::vec4> specular;  // rgb specular, a shininess
  std::vector<glm::vec4> position;  // xyz world position, w 1 when covered
  std::vector<glm::vec4> normal;    // xyz shading normal, w transparency
  std::vector<std::uint32_t> prim;  // primitive id, kNoPrim when empty
  std::vector<float> depth;         // the depth attachment (1.0 clear value)
  RS_FIELDS(width, height, diffuse, specular, position, normal, prim, depth)
};

// ---- raygen: sparse ray arrays with head flags -----------------------------------------------------
struct SparseRays {
  std::vector<layout::Ray> rays;        // one slot per (surface[, light])
  std::vector<std::uint32_t> flags;  // 1 where the slot holds a ray
  RS_FIELDS(rays, flags)
};

// ---- trim: order-preserving compaction -------------------------------------------------------------
struct Trimmed {
  std::vector<layout::Ray> rays;          // dense, in slot order
  std::vector<std::uint32_t> offsets;  // exclusive scan of flags: dense index of slot i when flags[i]
  RS_FIELDS(rays, offsets)
};

// ---- ray order: runs of equal hash keys ---------------------------------------------------------------
struct Chunks {
  std::vector<std::uint32_t> key, base, size;
  RS_NAMED_FIELDS("chunk_key, chunk_base, chunk_size", key, base, size)
};

// ---- traversal: one slot per (node, triangle) candidate ------------------------------------------------
// Pairs are packed (node id - level base) << layout::kPairTriangleBits | (triangle - b0) (rayspace/contract.h).
struct PairSlots {
  std::vector<std::uint8_t> flags;    // 1 where the slot's pair survives the cone-sphere test
  std::vector<std::uint32_t> values;  // the packed pair of each slot
  std::vector<std::uint8_t> tested;   // top level: 1 where a test ran; lower levels: children per pair
  RS_FIELDS(flags, values, tested)
};

// A level tested and compacted in one pass (traverse.compact): the surviving slots' values in slot
// order, what PairSlots followed by a reduction give, and the number of tests run. `tested` is a
// one-element buffer in a buffer set, so the diff compares it (verify/call_codec.h).
struct Compacted {
  // Unzeroed, so the fused path fills it from its blocks in parallel, faulting its pages in on every
  // thread instead of zeroing them on one first.
  UninitVector<std::uint32_t> pairs;
  std::uint64_t tested = 0;
  RS_FIELDS(pairs, tested)
};

enum class Reduction : std::uint32_t { kHierarchical = 0, kScan = 1 };

struct HashConfig {
  int light_bits = 4;      // shadow keys: light index in the high bits
  int polar_bits = 14;     // shadow keys: cos(theta) cells
  int azimuth_bits = 14;   // shadow keys: azimuth cells (pseudo-angle, no trigonometry)
  int origin_bits = 6;     // reflection/refraction: cells per axis of the scene box (x3, interleaved)
  int direction_bits = 7;  // reflection/refraction: cells per direction coordinate (x2)
  // Both keys' direction part: layout::kHashOrderInterleaved or kHashOrderPolarFirst (--hash-order).
  std::uint32_t order = layout::kHashOrderInterleaved;
  RS_FIELDS(light_bits, polar_bits, azimuth_bits, origin_bits, direction_bits, order)
};

}  // namespace rayspace::emu
