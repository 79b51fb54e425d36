// The cone-sphere and ray-triangle tests on sixteen lanes: compiled with -mavx512f
// (emu/CMakeLists.txt), called only where the CPU has AVX-512F (cone_simd.cpp, intersect_simd.cpp).
#include <immintrin.h>

#include <cmath>

#include "cone_lanes.h"
#include "intersect_lanes.h"
#include "rayspace/contract.h"  // constants only: no function of it is used here

namespace rayspace::emu::cone::lanes {
namespace {

struct L {
  using V = __m512;
  using M = __mmask16;
  static constexpr int W = 16;
  static V Set(float f) { return _mm512_set1_ps(f); }
  static V Load(const float* p) { return _mm512_loadu_ps(p); }
  static V Add(V a, V b) { return _mm512_add_ps(a, b); }
  static V Sub(V a, V b) { return _mm512_sub_ps(a, b); }
  static V Mul(V a, V b) { return _mm512_mul_ps(a, b); }
  static V Sqrt(V a) { return _mm512_sqrt_ps(a); }
  static V Abs(V x) { return _mm512_castsi512_ps(_mm512_and_epi32(_mm512_castps_si512(x), _mm512_set1_epi32(0x7FFFFFFF))); }
  // emu Max: a > b ? a : b, and a when b is NaN.
  static V Max(V a, V b) {
    return _mm512_mask_blend_ps(_mm512_cmp_ps_mask(a, b, _CMP_GT_OQ) | _mm512_cmp_ps_mask(b, b, _CMP_UNORD_Q), b, a);
  }
  static V MaxOrdered(V a, V b) { return _mm512_max_ps(a, b); }
  static bool AnyNaN(V x) { return _mm512_cmp_ps_mask(x, x, _CMP_UNORD_Q) != 0; }
  // emu InversePowerOfTwo: 2^-e for the exponent of m, clamped to normal powers.
  static V InversePowerOfTwo(V m) {
    const __m512i e = _mm512_and_epi32(_mm512_srli_epi32(_mm512_castps_si512(m), 23), _mm512_set1_epi32(0xFF));
    __m512i t = _mm512_sub_epi32(_mm512_set1_epi32(254), e);
    t = _mm512_min_epi32(_mm512_max_epi32(t, _mm512_set1_epi32(1)), _mm512_set1_epi32(254));
    return _mm512_castsi512_ps(_mm512_slli_epi32(t, 23));
  }
  template <int P>
  static M Cmp(V a, V b) {
    return _mm512_cmp_ps_mask(a, b, P);
  }
  static M Or(M a, M b) { return a | b; }
  static M And(M a, M b) { return a & b; }
  static M Select(M c, M a, M b) { return (c & a) | (~c & b); }
  static V SelectV(M c, V a, V b) { return _mm512_mask_blend_ps(c, b, a); }
  static M Not(M a) { return static_cast<M>(~a); }
  static M EqInt(const std::int32_t* p, int k) { return _mm512_cmpeq_epi32_mask(_mm512_loadu_si512(p), _mm512_set1_epi32(k)); }
  static V Div(V a, V b) { return _mm512_div_ps(a, b); }
  static void Store(float* p, V v) { _mm512_storeu_ps(p, v); }
  static std::uint32_t Bits(M m) { return m; }
  // Lanes 0-7 from a, 8-15 from b.
  static V Load2(const float* a, const float* b) {
    return _mm512_castpd_ps(_mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_castps_pd(_mm256_loadu_ps(a))),
                                               _mm256_castps_pd(_mm256_loadu_ps(b)), 1));
  }
  static V Set2(float a, float b) { return _mm512_mask_blend_ps(0xFF00, _mm512_set1_ps(a), _mm512_set1_ps(b)); }
  // Lane i < 8 writes a + (i << shift), lane i >= 8 writes b + ((i - 8) << shift), set lanes in order.
  static std::size_t Emit2(std::uint32_t bits, std::uint32_t a, std::uint32_t b, int shift, std::uint32_t* out) {
    if (!bits) return 0;
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 2, 3, 4, 5, 6, 7);
    const __m512i first = _mm512_mask_blend_epi32(0xFF00, _mm512_set1_epi32(static_cast<int>(a)), _mm512_set1_epi32(static_cast<int>(b)));
    const __m512i values = _mm512_add_epi32(first, _mm512_sllv_epi32(lane, _mm512_set1_epi32(shift)));
    _mm512_storeu_si512(out, _mm512_maskz_compress_epi32(static_cast<__mmask16>(bits), values));
    return static_cast<std::size_t>(__builtin_popcount(bits));
  }
  // The set lanes' values packed in lane order by one compress and one store (out has room for 16).
  static std::size_t Emit(std::uint32_t bits, std::uint32_t first, int shift, std::uint32_t* out) {
    if (!bits) return 0;
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i values = _mm512_add_epi32(_mm512_set1_epi32(static_cast<int>(first)), _mm512_sllv_epi32(lane, _mm512_set1_epi32(shift)));
    _mm512_storeu_si512(out, _mm512_maskz_compress_epi32(static_cast<__mmask16>(bits), values));
    return static_cast<std::size_t>(__builtin_popcount(bits));
  }
};

#include "cone_lanes.inl"
#include "intersect_lanes.inl"

}  // namespace
}  // namespace rayspace::emu::cone::lanes

#define RS_ISA(name) name##Avx512
#include "lanes_entries.inl"
#undef RS_ISA
