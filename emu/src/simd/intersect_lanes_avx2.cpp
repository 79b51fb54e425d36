// emu::IntersectWatertight on eight rays against one triangle: every lane performs the scalar
// test's operations in its order (each intrinsic one IEEE operation, no FMA) with the per-ray axis
// permutation done by selects, so each lane answers as the scalar test does, bit for bit
// (tests/intersect_simd_test.cpp). Compiled with -mavx2; called only where the CPU has AVX2.
#include <immintrin.h>

#include <cmath>

#include "intersect_lanes.h"

namespace rayspace::emu::intersect_lanes {
namespace {

using V = __m256;

V Set(float f) { return _mm256_set1_ps(f); }
V Abs(V x) { return _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF))); }
// emu InversePowerOfTwo.
V InversePowerOfTwo(V m) {
  const __m256i e = _mm256_and_si256(_mm256_srli_epi32(_mm256_castps_si256(m), 23), _mm256_set1_epi32(0xFF));
  __m256i t = _mm256_sub_epi32(_mm256_set1_epi32(254), e);
  t = _mm256_min_epi32(_mm256_max_epi32(t, _mm256_set1_epi32(1)), _mm256_set1_epi32(254));
  return _mm256_castsi256_ps(_mm256_slli_epi32(t, 23));
}
V Add(V a, V b) { return _mm256_add_ps(a, b); }
V Sub(V a, V b) { return _mm256_sub_ps(a, b); }
V Mul(V a, V b) { return _mm256_mul_ps(a, b); }

struct V3 {
  V x, y, z;
};
V MaxAbs1(const V3& a) { return _mm256_max_ps(_mm256_max_ps(Abs(a.x), Abs(a.y)), Abs(a.z)); }

// emu: Max(MaxAbs(A0, B0), MaxAbs(C0, C0)). The instruction's max, not GLSL's: they differ only
// when an operand is NaN, and a lane with a NaN coordinate of the vertices or the origin misses
// whatever its scale: t = A0.n / d.n is NaN (n is NaN when a vertex is).
V Largest(const V3& A0, const V3& B0, const V3& C0) {
  const V mc = MaxAbs1(C0);
  return _mm256_max_ps(_mm256_max_ps(MaxAbs1(A0), MaxAbs1(B0)), _mm256_max_ps(mc, mc));
}

// Component k of a for each lane (k = 0, 1, 2 per lane).
struct Pick {
  V is0, is1;
  explicit Pick(const std::int32_t* k) {
    const __m256i kk = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(k));
    is0 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kk, _mm256_setzero_si256()));
    is1 = _mm256_castsi256_ps(_mm256_cmpeq_epi32(kk, _mm256_set1_epi32(1)));
  }
  V operator()(const V3& a) const { return _mm256_blendv_ps(_mm256_blendv_ps(a.z, a.y, is1), a.x, is0); }
};

// The sheared 2D vertex: (P[kx] - sx P[kz], P[ky] - sy P[kz]).
void Shear(const V3& P, const Pick& kx, const Pick& ky, const Pick& kz, V sx, V sy, V& px, V& py) {
  const V pz = kz(P);
  px = Sub(kx(P), Mul(sx, pz));
  py = Sub(ky(P), Mul(sy, pz));
}

}  // namespace

std::uint32_t EightAvx2(const RayArrays& r, const Triangle& tri, std::uint32_t j, float t_out[8]) {
  const V3 org{_mm256_loadu_ps(r.ox + j), _mm256_loadu_ps(r.oy + j), _mm256_loadu_ps(r.oz + j)};
  const V3 A0{Sub(Set(tri.v0[0]), org.x), Sub(Set(tri.v0[1]), org.y), Sub(Set(tri.v0[2]), org.z)};
  const V3 B0{Sub(Set(tri.v1[0]), org.x), Sub(Set(tri.v1[1]), org.y), Sub(Set(tri.v1[2]), org.z)};
  const V3 C0{Sub(Set(tri.v2[0]), org.x), Sub(Set(tri.v2[1]), org.y), Sub(Set(tri.v2[2]), org.z)};
  const V ka = InversePowerOfTwo(Largest(A0, B0, C0));
  const V3 A{Mul(A0.x, ka), Mul(A0.y, ka), Mul(A0.z, ka)}, B{Mul(B0.x, ka), Mul(B0.y, ka), Mul(B0.z, ka)},
      C{Mul(C0.x, ka), Mul(C0.y, ka), Mul(C0.z, ka)};
  const Pick kx(r.kx + j), ky(r.ky + j), kz(r.kz + j);
  const V sx = _mm256_loadu_ps(r.sx + j), sy = _mm256_loadu_ps(r.sy + j);
  V ax, ay, bx, by, cx, cy;
  Shear(A, kx, ky, kz, sx, sy, ax, ay);
  Shear(B, kx, ky, kz, sx, sy, bx, by);
  Shear(C, kx, ky, kz, sx, sy, cx, cy);
  const V u = Sub(Mul(cx, by), Mul(cy, bx)), v = Sub(Mul(ax, cy), Mul(ay, cx)), w = Sub(Mul(bx, ay), Mul(by, ax));
  const V zero = _mm256_setzero_ps();
  const V some_neg = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_LT_OQ), _mm256_cmp_ps(v, zero, _CMP_LT_OQ)),
                                  _mm256_cmp_ps(w, zero, _CMP_LT_OQ));
  const V some_pos = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(u, zero, _CMP_GT_OQ), _mm256_cmp_ps(v, zero, _CMP_GT_OQ)),
                                  _mm256_cmp_ps(w, zero, _CMP_GT_OQ));
  const V det = Add(Add(u, v), w);
  const V inside = _mm256_andnot_ps(_mm256_or_ps(_mm256_and_ps(some_neg, some_pos), _mm256_cmp_ps(det, zero, _CMP_EQ_OQ)),
                                    _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
  // t = A0.n / d.n (emu Dot order).
  const V nx = Set(tri.n[0]), ny = Set(tri.n[1]), nz = Set(tri.n[2]);
  const V num = Add(Add(Mul(A0.x, nx), Mul(A0.y, ny)), Mul(A0.z, nz));
  const V den = Add(Add(Mul(_mm256_loadu_ps(r.dx + j), nx), Mul(_mm256_loadu_ps(r.dy + j), ny)), Mul(_mm256_loadu_ps(r.dz + j), nz));
  const V t = _mm256_div_ps(num, den);
  const V in_range = _mm256_and_ps(_mm256_cmp_ps(t, _mm256_loadu_ps(r.tmin + j), _CMP_GT_OQ),
                                   _mm256_cmp_ps(t, _mm256_loadu_ps(r.tmax + j), _CMP_LT_OQ));
  _mm256_storeu_ps(t_out, t);
  return static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_and_ps(inside, in_range)));
}

}  // namespace rayspace::emu::intersect_lanes
