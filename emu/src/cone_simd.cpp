// Chooses the instruction set of the multi-lane cone-sphere test and lays out its arrays; the lanes
// themselves are emu/src/simd/cone_lanes.inl, compiled once per instruction set.
#include "rayspace/emu/cone_simd.h"

#include "rayspace/error.h"
#include "rayspace/emu/cone.h"
#include "simd/cone_lanes.h"

namespace rayspace::emu::cone {
namespace {

std::vector<float> Padded(std::size_t n) { return std::vector<float>(n + kLanePad, 0.0f); }

lanes::NodeArrays View(const NodeArrays& n) {
  return {n.x.data(), n.y.data(), n.z.data(), n.r.data(), n.ax.data(), n.ay.data(), n.az.data(), n.cosa.data(), n.sina.data()};
}

lanes::Output OutputOf(std::uint32_t first, int shift, std::uint32_t* out) { return {first, shift, out}; }

}  // namespace

bool Runs(Isa isa) {
  __builtin_cpu_init();  // may run from a static initializer, before libgcc's own
  switch (isa) {
    case Isa::kScalar: return true;
    case Isa::kAvx2: return __builtin_cpu_supports("avx2");
    case Isa::kAvx512: return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("popcnt");
  }
  return false;
}

Isa BestIsa() {
  static const Isa best = Runs(Isa::kAvx512) ? Isa::kAvx512 : Runs(Isa::kAvx2) ? Isa::kAvx2 : Isa::kScalar;
  return best;
}

const char* IsaName(Isa isa) {
  switch (isa) {
    case Isa::kScalar: return "scalar";
    case Isa::kAvx2: return "avx2";
    case Isa::kAvx512: return "avx512";
  }
  return "?";
}

SphereArrays ToArrays(std::span<const glm::vec4> spheres) {
  SphereArrays a{Padded(spheres.size()), Padded(spheres.size()), Padded(spheres.size()), Padded(spheres.size()),
                 spheres};
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    a.x[i] = spheres[i].x;
    a.y[i] = spheres[i].y;
    a.z[i] = spheres[i].z;
    a.r[i] = spheres[i].w;
  }
  return a;
}

NodeArrays ToArrays(std::span<const layout::ConeNode> nodes) {
  const std::size_t n = nodes.size();
  NodeArrays a{Padded(n), Padded(n), Padded(n), Padded(n), Padded(n), Padded(n), Padded(n), Padded(n), Padded(n),
               nodes};
  for (std::size_t i = 0; i < n; ++i) {
    const layout::ConeNode& c = nodes[i];
    a.x[i] = c.sphere.x, a.y[i] = c.sphere.y, a.z[i] = c.sphere.z, a.r[i] = c.sphere.w;
    a.ax[i] = c.cone.x, a.ay[i] = c.cone.y, a.az[i] = c.cone.z, a.cosa[i] = c.cone.w, a.sina[i] = c.extra.x;
  }
  return a;
}

std::size_t TestSpheres(Isa isa, const layout::ConeNode& n, const SphereArrays& s, std::uint32_t i0, std::uint32_t i1, float eps,
                        std::uint32_t first, int shift, std::uint32_t* out) {
  RS_DCHECK(i1 <= s.spheres.size() && Runs(isa));
  const lanes::Node node{n.sphere.x, n.sphere.y, n.sphere.z, n.sphere.w, n.cone.x, n.cone.y, n.cone.z, n.cone.w, n.extra.x};
  const lanes::SphereArrays arrays{s.x.data(), s.y.data(), s.z.data(), s.r.data()};
  if (isa == Isa::kAvx512) return lanes::SpheresAvx512(node, arrays, i0, i1, eps, OutputOf(first, shift, out));
  if (isa == Isa::kAvx2) return lanes::SpheresAvx2(node, arrays, i0, i1, eps, OutputOf(first, shift, out));
  std::size_t count = 0;
  for (std::uint32_t i = i0; i < i1; ++i)
    if (Test(n, s.spheres[i], eps)) out[count++] = first + (i << shift);
  return count;
}

std::size_t TestNodes(Isa isa, const NodeArrays& nodes, glm::vec4 sphere, std::uint32_t k0, std::uint32_t k1, float eps,
                      std::uint32_t first, int shift, std::uint32_t* out) {
  RS_DCHECK(k1 <= nodes.nodes.size() && Runs(isa));
  const lanes::NodeArrays arrays = View(nodes);
  const float s[4] = {sphere.x, sphere.y, sphere.z, sphere.w};
  if (isa == Isa::kAvx512) return lanes::NodesAvx512(arrays, s, k0, k1, eps, OutputOf(first, shift, out));
  if (isa == Isa::kAvx2) return lanes::NodesAvx2(arrays, s, k0, k1, eps, OutputOf(first, shift, out));
  std::size_t count = 0;
  for (std::uint32_t k = k0; k < k1; ++k)
    if (Test(nodes.nodes[k], sphere, eps)) out[count++] = first + (k << shift);
  return count;
}

std::size_t TestPairs(Isa isa, const NodeArrays& nodes, const PairLevel& lv, std::size_t p0, std::size_t p1, float eps,
                      std::uint32_t* out, std::uint64_t& tested) {
  RS_DCHECK(p1 <= lv.pairs.size() && Runs(isa));
  const lanes::PairLevel l{lv.pairs.data(), lv.first.data(), lv.base_up, lv.base, &lv.spheres->x, static_cast<int>(layout::kPairTriangleBits)};
  if (isa == Isa::kAvx512) return lanes::PairsAvx512(View(nodes), l, p0, p1, eps, out, &tested);
  if (isa == Isa::kAvx2) return lanes::PairsAvx2(View(nodes), l, p0, p1, eps, out, &tested);
  std::size_t count = 0;
  for (std::size_t p = p0; p < p1; ++p) {
    const std::uint32_t parent = lv.base_up + (lv.pairs[p] >> layout::kPairTriangleBits), tri = lv.pairs[p] & layout::kPairTriangleMask;
    const std::uint32_t k0 = lv.first[parent], k1 = lv.first[parent + 1];
    tested += k1 - k0;
    count += TestNodes(isa, nodes, lv.spheres[tri], k0, k1, eps, tri - (lv.base << layout::kPairTriangleBits), layout::kPairTriangleBits, out + count);
  }
  return count;
}

}  // namespace rayspace::emu::cone
