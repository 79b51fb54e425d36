// The cone-sphere and ray-triangle tests on eight lanes: compiled with -mavx2 (emu/CMakeLists.txt),
// called only where the CPU has AVX2 (cone_simd.cpp, intersect_simd.cpp).
#include <immintrin.h>

#include <cmath>

#include "cone_lanes.h"
#include "intersect_lanes.h"
#include "rayspace/contract.h"  // constants only: no function of it is used here

namespace rayspace::emu::cone::lanes {
namespace {

struct L {
  using V = __m256;
  using M = __m256;  // all-ones lanes
  static constexpr int W = 8;
  static V Set(float f) { return _mm256_set1_ps(f); }
  static V Load(const float* p) { return _mm256_loadu_ps(p); }
  static V Add(V a, V b) { return _mm256_add_ps(a, b); }
  static V Sub(V a, V b) { return _mm256_sub_ps(a, b); }
  static V Mul(V a, V b) { return _mm256_mul_ps(a, b); }
  static V Sqrt(V a) { return _mm256_sqrt_ps(a); }
  static V Abs(V x) { return _mm256_and_ps(x, _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF))); }
  // emu Max: a > b ? a : b, and a when b is NaN. MAXPS(a, b) is a > b ? a : b (b on NaN or equal).
  static V Max(V a, V b) { return _mm256_blendv_ps(_mm256_max_ps(a, b), a, _mm256_cmp_ps(b, b, _CMP_UNORD_Q)); }
  static V MaxOrdered(V a, V b) { return _mm256_max_ps(a, b); }
  static bool AnyNaN(V x) { return _mm256_movemask_ps(_mm256_cmp_ps(x, x, _CMP_UNORD_Q)) != 0; }
  // emu InversePowerOfTwo: 2^-e for the exponent of m, clamped to normal powers.
  static V InversePowerOfTwo(V m) {
    const __m256i e = _mm256_and_si256(_mm256_srli_epi32(_mm256_castps_si256(m), 23), _mm256_set1_epi32(0xFF));
    __m256i t = _mm256_sub_epi32(_mm256_set1_epi32(254), e);
    t = _mm256_min_epi32(_mm256_max_epi32(t, _mm256_set1_epi32(1)), _mm256_set1_epi32(254));
    return _mm256_castsi256_ps(_mm256_slli_epi32(t, 23));
  }
  template <int P>
  static M Cmp(V a, V b) {
    return _mm256_cmp_ps(a, b, P);
  }
  static M Or(M a, M b) { return _mm256_or_ps(a, b); }
  static M And(M a, M b) { return _mm256_and_ps(a, b); }
  static M Select(M c, M a, M b) { return _mm256_blendv_ps(b, a, c); }
  static V SelectV(M c, V a, V b) { return _mm256_blendv_ps(b, a, c); }
  static M Not(M a) { return _mm256_xor_ps(a, _mm256_castsi256_ps(_mm256_set1_epi32(-1))); }
  static M EqInt(const std::int32_t* p, int k) {
    return _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)), _mm256_set1_epi32(k)));
  }
  static V Div(V a, V b) { return _mm256_div_ps(a, b); }
  static void Store(float* p, V v) { _mm256_storeu_ps(p, v); }
  static std::uint32_t Bits(M m) { return static_cast<std::uint32_t>(_mm256_movemask_ps(m)); }
  static std::size_t Emit(std::uint32_t bits, std::uint32_t first, int shift, std::uint32_t* out) {
    std::size_t n = 0;
    for (; bits; bits &= bits - 1) out[n++] = first + (static_cast<std::uint32_t>(__builtin_ctz(bits)) << shift);
    return n;
  }
};

#include "cone_lanes.inl"
#include "intersect_lanes.inl"

}  // namespace
}  // namespace rayspace::emu::cone::lanes

#define RS_ISA(name) name##Avx2
#include "lanes_entries.inl"
#undef RS_ISA
