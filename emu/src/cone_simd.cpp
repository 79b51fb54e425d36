// The cone-sphere test (cone::TestOf<float>) on eight spheres at once with AVX2: every lane performs
// the scalar test's operations in the same order (no FMA: the functions are compiled for AVX2 only,
// by target attribute, with -ffp-contract=off, and each intrinsic is one IEEE operation; sqrt is
// IEEE's), both branches are
// evaluated and selected by masks, and GLSL's max (the first operand when the second is NaN) is kept,
// so each lane gives the scalar test's answer bit for bit. tests/cone_simd_test.cpp holds it to the
// scalar test on random and special inputs.
#include "rayspace/emu/cone_simd.h"

#include <immintrin.h>

#include "rayspace/emu/cone.h"

namespace rayspace::emu::cone {
namespace {

// emu Max: a > b ? a : b, and a when b is NaN. MAXPS(a, b) is a > b ? a : b (b on NaN or equal).
__attribute__((target("avx2"))) inline __m256 Max8(__m256 a, __m256 b) {
  const __m256 b_nan = _mm256_cmp_ps(b, b, _CMP_UNORD_Q);
  return _mm256_blendv_ps(_mm256_max_ps(a, b), a, b_nan);
}

__attribute__((target("avx2"))) inline __m256 Abs8(__m256 x) {
  return _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF)));
}

// emu InversePowerOfTwo: 2^-e for the exponent of m, clamped to normal powers.
__attribute__((target("avx2"))) inline __m256 InversePowerOfTwo8(__m256 m) {
  const __m256i e = _mm256_and_si256(_mm256_srli_epi32(_mm256_castps_si256(m), 23), _mm256_set1_epi32(0xFF));
  __m256i t = _mm256_sub_epi32(_mm256_set1_epi32(254), e);
  t = _mm256_min_epi32(_mm256_max_epi32(t, _mm256_set1_epi32(1)), _mm256_set1_epi32(254));
  return _mm256_castsi256_ps(_mm256_slli_epi32(t, 23));
}

__attribute__((target("avx2"))) inline __m256 Dot8(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz) {
  return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)), _mm256_mul_ps(az, bz));
}

}  // namespace

bool HaveSimdTest() { return __builtin_cpu_supports("avx2"); }

__attribute__((target("avx2"))) std::uint32_t TestEight(const layout::ConeNode& n, const SphereLanes& s, float eps) {
  if (IsFull(n)) return 0xFFu;
  const __m256 sx = _mm256_loadu_ps(s.x), sy = _mm256_loadu_ps(s.y), sz = _mm256_loadu_ps(s.z), sr = _mm256_loadu_ps(s.r);
  // v0 = sphere - node centre; R0 = (r + r_node) * kRadiusSlack + eps.
  const __m256 v0x = _mm256_sub_ps(sx, _mm256_set1_ps(n.sphere.x)), v0y = _mm256_sub_ps(sy, _mm256_set1_ps(n.sphere.y)),
               v0z = _mm256_sub_ps(sz, _mm256_set1_ps(n.sphere.z));
  const __m256 R0 = _mm256_add_ps(_mm256_mul_ps(_mm256_add_ps(sr, _mm256_set1_ps(n.sphere.w)), _mm256_set1_ps(kRadiusSlack)),
                                  _mm256_set1_ps(eps));
  const __m256 m = Max8(Max8(Max8(Abs8(v0x), Abs8(v0y)), Abs8(v0z)), R0);
  // At the apex or out of float range: keep.
  const __m256 out_of_range = _mm256_or_ps(_mm256_cmp_ps(m, _mm256_setzero_ps(), _CMP_NGT_UQ),
                                           _mm256_cmp_ps(m, _mm256_set1_ps(INFINITY), _CMP_NLT_UQ));
  const __m256 k = InversePowerOfTwo8(m);
  const __m256 vx = _mm256_mul_ps(v0x, k), vy = _mm256_mul_ps(v0y, k), vz = _mm256_mul_ps(v0z, k);
  const __m256 xx = _mm256_set1_ps(n.cone.x), xy = _mm256_set1_ps(n.cone.y), xz = _mm256_set1_ps(n.cone.z);
  const __m256 a = Dot8(vx, vy, vz, xx, xy, xz);
  // b = |v x axis| (emu Cross, then Length).
  const __m256 cx = _mm256_sub_ps(_mm256_mul_ps(vy, xz), _mm256_mul_ps(vz, xy));
  const __m256 cy = _mm256_sub_ps(_mm256_mul_ps(vz, xx), _mm256_mul_ps(vx, xz));
  const __m256 cz = _mm256_sub_ps(_mm256_mul_ps(vx, xy), _mm256_mul_ps(vy, xx));
  const __m256 b = _mm256_sqrt_ps(Dot8(cx, cy, cz, cx, cy, cz));
  const __m256 cosa = _mm256_set1_ps(n.cone.w), sina = _mm256_set1_ps(n.extra.x);
  const __m256 sv = _mm256_sub_ps(_mm256_mul_ps(b, cosa), _mm256_mul_ps(a, sina));
  const __m256 cv = _mm256_add_ps(_mm256_mul_ps(a, cosa), _mm256_mul_ps(b, sina));
  // Inside the cone: s < 0, or s = 0 with c >= 0.
  const __m256 inside = _mm256_or_ps(_mm256_cmp_ps(sv, _mm256_setzero_ps(), _CMP_LT_OQ),
                                     _mm256_and_ps(_mm256_cmp_ps(sv, _mm256_setzero_ps(), _CMP_EQ_OQ),
                                                   _mm256_cmp_ps(cv, _mm256_setzero_ps(), _CMP_GE_OQ)));
  const __m256 R = _mm256_add_ps(_mm256_mul_ps(R0, k), _mm256_mul_ps(_mm256_add_ps(Abs8(a), b), _mm256_set1_ps(kTestSlack)));
  const __m256 surface = _mm256_cmp_ps(sv, R, _CMP_LE_OQ);                                            // c > 0
  const __m256 apex = _mm256_cmp_ps(Dot8(vx, vy, vz, vx, vy, vz), _mm256_mul_ps(R, R), _CMP_LE_OQ);  // else
  const __m256 near = _mm256_blendv_ps(apex, surface, _mm256_cmp_ps(cv, _mm256_setzero_ps(), _CMP_GT_OQ));
  const __m256 hit = _mm256_or_ps(_mm256_or_ps(out_of_range, inside), near);
  return static_cast<std::uint32_t>(_mm256_movemask_ps(hit));
}

}  // namespace rayspace::emu::cone
