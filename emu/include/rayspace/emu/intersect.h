// Per-element kernel math shared by the emulated passes. Every operation is one IEEE float
// operation in a fixed order (the build uses -ffp-contract=off), so a GLSL kernel that performs the
// same operations in the same order on lavapipe produces the same bits.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "rayspace/layout.h"

namespace rayspace::emu {

// The vector math below is templated over the scalar: float here, and verify::SpecReal when the
// diff asks which values a device with relaxed division and square root may produce
// (verify/include/rayspace/verify/spec_real.h). The float instantiation is the kernels' arithmetic.
template <typename S>
using Vec3 = glm::vec<3, S, glm::defaultp>;
template <typename S>
using Vec4 = glm::vec<4, S, glm::defaultp>;

inline float Abs(float x) { return std::fabs(x); }
inline float Sqrt(float x) { return std::sqrt(x); }
inline float Square(float x) { return x * x; }
inline float NextAfter(float x, float toward) { return std::nextafter(x, toward); }
// The value lavapipe computes (verify::SpecReal's own for its type): for decisions on input words,
// which every device reads alike.
inline float Nominal(float x) { return x; }
template <typename S>
Vec3<S> Xyz(const Vec4<S>& v) { return {v.x, v.y, v.z}; }

template <typename S>
S Dot(Vec3<S> a, Vec3<S> b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
// Dot(v, v), written with Square so that a relaxed evaluation knows each term is not negative.
template <typename S>
S SelfDot(Vec3<S> v) { return (Square(v.x) + Square(v.y)) + Square(v.z); }
template <typename S>
Vec3<S> Cross(Vec3<S> a, Vec3<S> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// GLSL normalize on lavapipe: v / sqrt(dot(v, v)).
template <typename S>
Vec3<S> Normalize(Vec3<S> v) {
  const S l = Sqrt(SelfDot(v));
  return {v.x / l, v.y / l, v.z / l};
}
template <typename S>
S Length(Vec3<S> v) { return Sqrt(SelfDot(v)); }
// GLSL min/max on lavapipe return the first operand when the second is NaN.
inline float Min(float a, float b) { return b != b ? a : (a < b ? a : b); }
inline float Max(float a, float b) { return b != b ? a : (a > b ? a : b); }
inline float Clamp(float x, float lo, float hi) { return Min(Max(x, lo), hi); }
// The lesser (greater) of x and b by one comparison, x kept on a tie: a kernel's `if (b < x) x = b;`.
// In verify::SpecReal the interval of the value the device's own comparison picks.
inline float Lesser(float x, float b) { return b < x ? b : x; }
inline float Greater(float x, float b) { return b > x ? b : x; }

inline std::uint32_t FloatBits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
inline float BitsFloat(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// x^n for an integer n >= 0 by repeated squaring, lowest bit first (no pow(): lavapipe's pow is not
// correctly rounded). x^0 = 1.
template <typename S>
S IntPowOf(S x, std::uint32_t n) {
  S result(1.0f), base = x;
  bool first = true;
  while (n != 0) {
    if (n & 1u) {
      result = first ? base : result * base;  // avoid 1*base: lavapipe folds x*1.0 anyway
      first = false;
    }
    n >>= 1;
    if (n != 0) base = base * base;
  }
  return result;
}
inline float IntPow(float x, std::uint32_t n) { return IntPowOf(x, n); }

// A closest hit packed so that the numerically smallest value is the nearest hit, ties broken by the
// lower primitive id: (float bits of t) << 32 | primitive. t > 0, so its bits order like its value.
inline constexpr std::uint64_t kMissPacked = ~std::uint64_t{0};
inline std::uint64_t PackHit(float t, std::uint32_t prim) {
  return (static_cast<std::uint64_t>(FloatBits(t)) << 32) | prim;
}
inline std::uint32_t HitPrim(std::uint64_t h) { return static_cast<std::uint32_t>(h); }
inline float HitT(std::uint64_t h) { return BitsFloat(static_cast<std::uint32_t>(h >> 32)); }

// 2^-e for the exponent e of |m| (m > 0), clamped to normal powers: multiplying by it is exact and
// brings m into [1, 2). Used to keep products of tiny or huge coordinates in range.
inline float InversePowerOfTwo(float m) {
  const std::int32_t e = static_cast<std::int32_t>((FloatBits(m) >> 23) & 0xFFu);
  return BitsFloat(static_cast<std::uint32_t>(std::clamp(254 - e, 1, 254)) << 23);
}

// |v| without overflow or underflow of the squares: v is scaled by a power of two first (exact), so
// for vectors whose squares stay in range the result is Length(v) bit for bit.
template <typename S>
S ScaledLength(Vec3<S> v) {
  const S m = Max(Max(Abs(v.x), Abs(v.y)), Abs(v.z));
  if (!(m > S(0.0f)) || !(m < S(INFINITY))) return m;
  const S k = InversePowerOfTwo(m);
  const Vec3<S> s(v.x * k, v.y * k, v.z * k);
  return Sqrt(SelfDot(s)) / k;
}

// The largest magnitude among the components of a and b (NaN-free inputs).
template <typename S>
S MaxAbs(Vec3<S> a, Vec3<S> b) {
  const S x = Max(Max(Abs(a.x), Abs(a.y)), Abs(a.z));
  const S y = Max(Max(Abs(b.x), Abs(b.y)), Abs(b.z));
  return Max(x, y);
}

// layout::PixelDirection (rayspace/kernel_functions.h, which the kernels include) in S: (pixel_origin
// + px * pixel_dx) + py * pixel_dy, each operation rounded.
template <typename S>
Vec3<S> PixelDirectionOf(const layout::FrameConstants& f, std::uint32_t px, std::uint32_t py) {
  const S fx(static_cast<float>(px)), fy(static_cast<float>(py));
  Vec3<S> d;
  for (int k = 0; k < 3; ++k) {
    const S a = fx * S(f.pixel_dx[k]);
    const S b = S(f.pixel_origin[k]) + a;
    const S c = fy * S(f.pixel_dy[k]);
    d[k] = b + c;
  }
  return d;
}

// Per-ray setup of the watertight ray-triangle test (Woop, Benthin, Wald 2013): the axis where the
// direction is largest becomes z, and the ray is sheared onto +z.
template <typename S>
struct WatertightRayOf {
  Vec3<S> org, dir;
  int kx, ky, kz;
  S sx, sy;
};
using WatertightRay = WatertightRayOf<float>;

template <typename S>
WatertightRayOf<S> SetupWatertight(Vec3<S> org, Vec3<S> dir) {
  WatertightRayOf<S> r;
  r.org = org;
  r.dir = dir;
  const Vec3<S> a(Abs(dir.x), Abs(dir.y), Abs(dir.z));
  int kz = 0;
  if (a.y > a[kz]) kz = 1;
  if (a.z > a[kz]) kz = 2;
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the sheared triangle
  r.kx = kx;
  r.ky = ky;
  r.kz = kz;
  r.sx = dir[kx] / dir[kz];
  r.sy = dir[ky] / dir[kz];
  return r;
}

// The triangle's normal for the distance, from edges and normal scaled by powers of two (t is
// unchanged): n.A and n.d stay in range for coordinates from 2^-60 to 2^60.
template <typename S>
Vec3<S> PlaneNormalOf(Vec3<S> v0, Vec3<S> v1, Vec3<S> v2) {
  const Vec3<S> e1 = v1 - v0, e2 = v2 - v0;
  const S ke = InversePowerOfTwo(MaxAbs(e1, e2));
  const Vec3<S> n0 = Cross(e1 * ke, e2 * ke);
  const S kn = InversePowerOfTwo(MaxAbs(n0, n0));
  return n0 * kn;
}

// Two-sided, edges inclusive. Returns true and t when the ray meets the triangle with
// tmin < t < tmax. The inside decision is Woop's (sheared edge functions); t = (v0 - o).n / d.n. Watertight: a ray through a shared edge hits at least one of its triangles.
// det_out (if given) receives the sheared triangle's signed area: positive when the ray meets the
// front, the side (v1 - v0) x (v2 - v0) points to (a one-sided test keeps det > 0 only).
template <typename S>
bool IntersectWatertight(const WatertightRayOf<S>& r, Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, S tmin, S tmax, S& t_out,
                         S* det_out = nullptr) {
  // Vertices relative to the origin, scaled by a power of two (exact; the signs of the edge functions
  // and their ratios are unchanged) so the products below neither overflow nor underflow.
  const Vec3<S> A0 = v0 - r.org, B0 = v1 - r.org, C0 = v2 - r.org;
  const S ka = InversePowerOfTwo(Max(MaxAbs(A0, B0), MaxAbs(C0, C0)));
  const Vec3<S> A = A0 * ka, B = B0 * ka, C = C0 * ka;
  const S ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
  const S bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
  const S cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
  const S u = cx * by - cy * bx;
  const S v = ax * cy - ay * cx;
  const S w = bx * ay - by * ax;
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  const S det = (u + v) + w;
  if (det == 0.0f) return false;
  // The distance comes from the plane, not from Woop's barycentric sum: on long thin triangles that
  // sum loses about log2(length / width) bits, the plane equation does not (PlaneNormalOf).
  const Vec3<S> n = PlaneNormalOf(v0, v1, v2);
  const S t = Dot(A0, n) / Dot(r.dir, n);
  if (!(t > tmin && t < tmax)) return false;  // also rejects NaN
  t_out = t;
  if (det_out) *det_out = det;
  return true;
}

inline glm::vec3 Xyz(const glm::vec4& v) { return {v.x, v.y, v.z}; }

}  // namespace rayspace::emu
