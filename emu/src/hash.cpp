// The hash pass: a 32-bit sort key per ray (docs/hierarchy.md, "Hash keys"), and Roger et al.'s
// screen quadtree key. Mirrors gpu/shaders/hash.comp.
#include <algorithm>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/hash_math.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
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

// Spherical cells of a unit direction: cos(theta) = z for the polar angle, the pseudo-angle for phi;
// bit-interleaved (polar bit above azimuth bit) so that sorted neighbours are close in both angles, or
// polar first as the thesis prints it (layout::kHashOrderPolarFirst).
std::uint32_t DirectionKey(glm::vec3 d, int polar_bits, int azimuth_bits, std::uint32_t order) {
  const std::uint32_t p = Cell(PolarArgument(d.z), polar_bits);
  const std::uint32_t a = Cell(DiamondAngle(d.x, d.y) * 0.25f, azimuth_bits);
  if (order == layout::kHashOrderPolarFirst) return (p << azimuth_bits) | a;
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

std::uint32_t Morton2(std::uint32_t x, std::uint32_t y) {
  std::uint32_t m = 0;
  for (int b = 15; b >= 0; --b) m = (m << 2) | (((y >> b) & 1u) << 1) | ((x >> b) & 1u);
  return m;
}

// The direction / origin keys (docs/hierarchy.md, "Hash keys").
std::vector<std::uint32_t> PassHashKeys(const call::Hash& c) {
  const In<layout::Ray> rays = c.rays;
  const SceneBuffers& scene = *c.scene;
  const HashConfig& h = c.hash;
  RS_CHECK(h.light_bits + h.polar_bits + h.azimuth_bits <= layout::kHashKeyBits);
  RS_CHECK(3 * h.origin_bits + 2 * h.direction_bits <= 32);
  std::vector<std::uint32_t> keys(rays.size());
  const glm::vec3 lo = scene.lo, ext = scene.hi - scene.lo;
  ParallelFor(rays.size(), [&](std::size_t i) {
    const layout::Ray& r = rays[i];
    const glm::vec3 d = Normalize(Xyz(r.direction_tmax));
    if (r.info.z == layout::kRayShadow) {
      const std::uint32_t light = std::min(r.info.w, (1u << h.light_bits) - 1u);  // more lights share the last value
      keys[i] = (light << (h.polar_bits + h.azimuth_bits)) | DirectionKey(d, h.polar_bits, h.azimuth_bits, h.order);
    } else {
      const glm::vec3 o = Xyz(r.origin_tmin);
      const std::uint32_t cx = Cell((o.x - lo.x) / ext.x, h.origin_bits), cy = Cell((o.y - lo.y) / ext.y, h.origin_bits),
                          cz = Cell((o.z - lo.z) / ext.z, h.origin_bits);
      keys[i] = (Interleave3(cx, cy, cz, h.origin_bits) << (2 * h.direction_bits)) |
                DirectionKey(d, h.direction_bits, h.direction_bits, h.order);
    }
  });
  return keys;
}

}  // namespace

std::vector<std::uint32_t> PassHashQuadtree(In<layout::Ray> rays, std::uint32_t width, int depth) {
  std::vector<std::uint32_t> k(rays.size());
  const std::uint32_t w = std::max(width, 1u);
  ParallelFor(rays.size(), [&](std::size_t i) {
    const std::uint32_t px = rays[i].info.x % w, py = rays[i].info.x / w;
    const std::uint32_t light = rays[i].info.z == layout::kRayShadow ? rays[i].info.w : 0u;
    k[i] = (light << (2 * depth)) | Morton2(px, py);
  });
  return k;
}

std::vector<std::uint32_t> PassHash(const call::Hash& c) {
  return c.quadtree_width ? PassHashQuadtree(c.rays, c.quadtree_width, c.quadtree_depth) : PassHashKeys(c);
}

}  // namespace rayspace::emu
