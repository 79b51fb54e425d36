// Ray hashing and the compress / sort / decompress scheme (thesis §3.2.3-3.2.6, after Garanzha and
// Loop): equal keys collapse into chunks, chunks are radix sorted, then expanded back to rays.
#include <algorithm>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

// Cell index of f in [0, 1] with `bits` bits; NaN and out-of-range values clamp (and never reach a
// float -> uint conversion out of range, which differs between GPUs).
std::uint32_t Cell(float f, int bits) {
  const float cells = static_cast<float>(1u << bits);
  const float v = Min(Max(f * cells, 0.0f), cells - 1.0f);
  return static_cast<std::uint32_t>(v);
}

// Pseudo-angle of (x, y) in [0, 4): monotone in the azimuth like atan2, without trigonometry.
float DiamondAngle(float x, float y) {
  const float ax = std::fabs(x), ay = std::fabs(y), s = ax + ay;
  if (!(s > 0.0f)) return 0.0f;
  if (y >= 0.0f) return x >= 0.0f ? y / s : 1.0f + ax / s;
  return x < 0.0f ? 2.0f + ay / s : 3.0f + x / s;
}

// Spherical cells of a unit direction: cos(theta) = z for the polar angle, the pseudo-angle for phi,
// bit-interleaved (polar bit above azimuth bit) so that sorted neighbours are close in both angles.
std::uint32_t DirectionKey(glm::vec3 d, int polar_bits, int azimuth_bits) {
  const std::uint32_t p = Cell((d.z + 1.0f) * 0.5f, polar_bits);
  const std::uint32_t a = Cell(DiamondAngle(d.x, d.y) * 0.25f, azimuth_bits);
  std::uint32_t key = 0;
  for (int b = std::max(polar_bits, azimuth_bits) - 1; b >= 0; --b) {
    if (b < polar_bits) key = (key << 1) | ((p >> b) & 1u);
    if (b < azimuth_bits) key = (key << 1) | ((a >> b) & 1u);
  }
  return key;
}

std::uint32_t Interleave3(std::uint32_t x, std::uint32_t y, std::uint32_t z, int bits) {
  std::uint32_t m = 0;
  for (int b = bits - 1; b >= 0; --b) m = (m << 3) | (((x >> b) & 1u) << 2) | (((y >> b) & 1u) << 1) | ((z >> b) & 1u);
  return m;
}

}  // namespace

std::vector<std::uint32_t> PassHash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, const HashConfig& h) {
  RS_CHECK(h.light_bits + h.polar_bits + h.azimuth_bits <= 32);
  RS_CHECK(3 * h.origin_bits + 2 * h.direction_bits <= 32);
  std::vector<std::uint32_t> keys(rays.size());
  const glm::vec3 lo = scene.lo, ext = scene.hi - scene.lo;
  ParallelFor(rays.size(), [&](std::size_t i) {
    const gpu::Ray& r = rays[i];
    const glm::vec3 d = Normalize(Xyz(r.direction_tmax));
    if (r.info.z == gpu::kRayShadow) {
      const std::uint32_t light = std::min(r.info.w, (1u << h.light_bits) - 1u);  // more lights share the last value
      keys[i] = (light << (h.polar_bits + h.azimuth_bits)) | DirectionKey(d, h.polar_bits, h.azimuth_bits);
    } else {
      const glm::vec3 o = Xyz(r.origin_tmin);
      const std::uint32_t cx = Cell((o.x - lo.x) / ext.x, h.origin_bits), cy = Cell((o.y - lo.y) / ext.y, h.origin_bits),
                          cz = Cell((o.z - lo.z) / ext.z, h.origin_bits);
      keys[i] = (Interleave3(cx, cy, cz, h.origin_bits) << (2 * h.direction_bits)) |
                DirectionKey(d, h.direction_bits, h.direction_bits);
    }
  });
  return keys;
}

Chunks PassCompress(const std::vector<std::uint32_t>& keys) {
  const std::size_t n = keys.size();
  std::vector<std::uint32_t> head(n);
  ParallelFor(n, [&](std::size_t i) { head[i] = (i == 0 || keys[i] != keys[i - 1]) ? 1u : 0u; });
  std::uint32_t chunks = 0;
  const std::vector<std::uint32_t> index = ExclusiveScan(head, &chunks);
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

std::vector<std::uint32_t> PassSortChunks(const std::vector<std::uint32_t>& chunk_keys) {
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

std::vector<std::uint32_t> PassDecompress(const Chunks& chunks, const std::vector<std::uint32_t>& sorted) {
  std::vector<std::uint32_t> sizes(sorted.size());
  ParallelFor(sorted.size(), [&](std::size_t j) { sizes[j] = chunks.size[sorted[j]]; });
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> start = ExclusiveScan(sizes, &total);
  std::vector<std::uint32_t> order(total);
  ParallelFor(sorted.size(), [&](std::size_t j) {
    const std::uint32_t base = chunks.base[sorted[j]];
    for (std::uint32_t k = 0; k < sizes[j]; ++k) order[start[j] + k] = base + k;
  });
  return order;
}

std::vector<std::uint32_t> ReduceScan(const std::vector<std::uint8_t>& flags, const std::vector<std::uint32_t>& values) {
  std::vector<std::uint32_t> f(flags.begin(), flags.end());
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> off = ExclusiveScan(f, &total);
  std::vector<std::uint32_t> out(total);
  ParallelFor(flags.size(), [&](std::size_t i) {
    if (flags[i]) out[off[i]] = values[i];
  });
  return out;
}

std::vector<std::uint32_t> ReduceHierarchical(const std::vector<std::uint8_t>& flags,
                                              const std::vector<std::uint32_t>& values, int component) {
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
  const std::vector<std::uint32_t> off = ExclusiveScan(counts, &total);
  std::vector<std::uint32_t> out(total);
  ParallelFor(comps, [&](std::size_t c) {
    for (std::uint32_t k = 0; k < counts[c]; ++k) out[off[c] + k] = local[c * s + k];
  });
  return out;
}

}  // namespace rayspace::emu
