// Correctly rounded division and square root from integer arithmetic alone, written once for GLSL
// (the kernels under `--strict-math`) and C++ (tests/strict_math_test.cpp holds it to IEEE). Vulkan
// lets a device divide within 2.5 ULP and take sqrt as 1 / inversesqrt; integer operations, shifts
// and 64-bit integer division are exact everywhere, so these give IEEE's round-to-nearest-even bits on
// any conformant device, denormal operands and results included (the bits are read and built as
// integers, so no float control can flush them). docs/numerics.md, "Strict math", says why.
#ifndef RAYSPACE_STRICT_MATH_H
#define RAYSPACE_STRICT_MATH_H

#ifdef __cplusplus
#include <bit>
#include <cstdint>

#include "rayspace/layout.h"

namespace rayspace::layout {
inline uint floatBitsToUint(float f) { return std::bit_cast<uint>(f); }
inline float uintBitsToFloat(uint u) { return std::bit_cast<float>(u); }
inline int findMSB(uint x) { return x == 0u ? -1 : 31 - std::countl_zero(x); }
#define RS_INLINE inline
#define RS_OUT(T) T&
#else
#define RS_INLINE
#define RS_OUT(T) out T
#endif

// The index of the highest set bit of q > 0.
RS_INLINE int StrictMsb64(uint64_t q) {
  const uint hi = uint(q >> 32);
  return hi != 0u ? 32 + findMSB(hi) : findMSB(uint(q));
}

// The float nearest to q * 2^e (q > 0; `sticky`: the exact value is a little above q * 2^e), ties to
// even, with IEEE's gradual underflow and overflow to infinity; `sign` is 0 or 0x80000000.
RS_INLINE float StrictRound(uint sign, uint64_t q, int e, bool sticky) {
  const int msb = StrictMsb64(q);
  const int exponent = msb + e;  // of the leading bit
  if (exponent > 127) return uintBitsToFloat(sign | 0x7F800000u);
  // Bits dropped below the float's last place: 24 significant bits when normal, the 2^-149 quantum
  // when not.
  const int drop = exponent >= -126 ? msb - 23 : -149 - e;
  uint64_t kept = drop >= 64 ? uint64_t(0) : q >> uint(drop);
  bool round_bit = false;
  bool rest = sticky;
  if (drop >= 1 && drop <= 64) {
    round_bit = ((q >> uint(drop - 1)) & uint64_t(1)) != uint64_t(0);
    if (drop >= 2) rest = rest || (q & ((uint64_t(1) << uint(drop - 1)) - uint64_t(1))) != uint64_t(0);
  } else if (drop > 64) {
    rest = true;
  }
  if (round_bit && (rest || (kept & uint64_t(1)) != uint64_t(0))) kept += uint64_t(1);
  // A normal: biased exponent above the hidden bit (kept includes it, so a carry out of the
  // significand moves the exponent, up to infinity). A denormal: kept is the bit pattern itself, and
  // a carry into bit 23 makes the smallest normal.
  const uint bits = exponent >= -126 ? (uint(exponent + 126) << 23) + uint(kept) : uint(kept);
  return uintBitsToFloat(sign | bits);
}

// |x|'s significand with its hidden bit (normalised so bit 23 is set, denormals included) and the
// exponent of its bit 0: |x| = m * 2^e. x finite and non-zero.
RS_INLINE uint StrictSplit(uint bits, RS_OUT(int) e) {
  const uint biased = (bits >> 23) & 0xFFu;
  uint m = bits & 0x7FFFFFu;
  if (biased != 0u) {
    e = int(biased) - 150;
    return m | 0x800000u;
  }
  const int shift = 23 - findMSB(m);
  e = -149 - shift;
  return m << uint(shift);
}

// a / b rounded to nearest even. The quotient of the significands, with 40 bits more below the
// dividend, has 40 or 41 bits; its remainder decides the sticky bit.
RS_INLINE float DivRN(float a, float b) {
  const uint ua = floatBitsToUint(a), ub = floatBitsToUint(b);
  const uint sign = (ua ^ ub) & 0x80000000u;
  const uint aa = ua & 0x7FFFFFFFu, ab = ub & 0x7FFFFFFFu;
  if (aa > 0x7F800000u || ab > 0x7F800000u) return uintBitsToFloat(0x7FC00000u);  // NaN operand
  if (aa == 0x7F800000u) return uintBitsToFloat(ab == 0x7F800000u ? 0x7FC00000u : (sign | 0x7F800000u));
  if (ab == 0x7F800000u) return uintBitsToFloat(sign);  // finite / inf = 0
  if (ab == 0u) return uintBitsToFloat(aa == 0u ? 0x7FC00000u : (sign | 0x7F800000u));
  if (aa == 0u) return uintBitsToFloat(sign);
  int ea, eb;
  const uint ma = StrictSplit(aa, ea), mb = StrictSplit(ab, eb);
  const uint64_t n = uint64_t(ma) << 40u;
  const uint64_t q = n / uint64_t(mb);
  return StrictRound(sign, q, ea - eb - 40, q * uint64_t(mb) != n);
}

// sqrt(x) rounded to nearest even. The significand, shifted by an even count so the exponent stays
// even, has an integer square root of 25 or 26 bits: integer Newton steps from a power of two above
// it (at most twice the root; six steps leave it within one), then exact integer squares. No float
// operation is used, so a device's loose sqrt cannot enter. (No square root of a float lies halfway
// between two floats, so the round bit alone decides, but the sticky bit is passed anyway.)
RS_INLINE float SqrtRN(float x) {
  const uint ux = floatBitsToUint(x);
  if ((ux & 0x7FFFFFFFu) == 0u) return x;  // +-0
  if (ux > 0x7F800000u) return uintBitsToFloat(0x7FC00000u);  // NaN or negative
  if (ux == 0x7F800000u) return x;
  int e;
  uint64_t m = uint64_t(StrictSplit(ux, e));
  if ((e & 1) != 0) {
    m = m << 1u;
    e = e - 1;
  }
  const uint64_t big = m << 26u;  // < 2^51
  uint64_t r = uint64_t(1) << uint((StrictMsb64(big) + 2) / 2);
  for (int i = 0; i < 6; ++i) r = (r + big / r) >> 1u;
  for (int i = 0; i < 4; ++i)
    if (r * r > big) r = r - uint64_t(1);
  for (int i = 0; i < 4; ++i)
    if ((r + uint64_t(1)) * (r + uint64_t(1)) <= big) r = r + uint64_t(1);
  return StrictRound(0u, r, (e - 26) / 2, r * r != big);
}

#undef RS_INLINE
#undef RS_OUT
#ifdef __cplusplus
}  // namespace rayspace::layout
#endif

#endif  // RAYSPACE_STRICT_MATH_H
