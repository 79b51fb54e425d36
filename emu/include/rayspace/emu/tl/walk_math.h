// The rounded arithmetic of the traversal lists (tl.lists' culling, a tl.trace walk), templated over
// the scalar like the other kernel math (rayspace/emu/intersect.h): float is the emulator's and the
// kernels' arithmetic, operation for operation; verify::SpecReal asks which decisions a conformant
// device may take the other way (docs/numerics.md, "The relaxed device model"). The integer
// decisions (the list of a direction, escapes, windows) stay in tl.cpp.
#pragma once
#include <bit>
#include <cmath>
#include <cstdint>

#include "rayspace/emu/intersect.h"
#include "rayspace/contract.h"
#include "rayspace/layout.h"

namespace rayspace::emu::tl {

// May list k of `count` drop the triangle (tl::Culled): every direction of its class sees its back,
// by a margin that covers the normal's rounding.
template <typename S>
bool CulledOf(Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, std::uint32_t count, std::uint32_t k) {
  if (count != 6 && count != 8) return false;
  const Vec3<S> e1 = v1 - v0, e2 = v2 - v0;
  const Vec3<S> n = Cross(e1, e2);
  const S m = S(layout::kTlCullMargin) * (MaxAbs(e1, e1) * MaxAbs(e2, e2));
  // Tiny or huge edges (a margin below the normal range, an overflow, a NaN) are never dropped.
  if (!(m >= S(0x1p-100f) && m <= S(0x1p100f))) return false;
  if (count == 8) {
    const S sx = (k & 1u) ? -n.x : n.x, sy = (k & 2u) ? -n.y : n.y, sz = (k & 4u) ? -n.z : n.z;
    return sx > m && sy > m && sz > m;
  }
  const std::uint32_t a = k / 2u, b = a == 2u ? 0u : a + 1u, c = b == 2u ? 0u : b + 1u;
  const S na = (k & 1u) ? -n[a] : n[a];
  return na - (Abs(n[b]) + Abs(n[c])) > S(3.0f) * m;
}

// Along the unit direction u, the centre lies at a and at distance b from the line. The ray's part
// [t0, t1] (in length) meets the sphere only if b <= r and [a - r, a + r] meets [t0, t1]; both are
// checked with the sphere grown by the cone test's slacks (contract.h), which cover the rounding of
// v, u, a, b and the t scaling (a few ulps of |a| + b, of t), so the test only ever accepts more.
// A result out of float range keeps the sphere (|x| < inf is false for inf and NaN).
template <typename S>
bool SphereMayHitOf(Vec3<S> org, Vec3<S> dir, S tmin, S tlimit, Vec4<S> sphere) {
  const S len = Length(dir);
  const Vec3<S> v = Xyz(sphere) - org;
  const Vec3<S> u(dir.x / len, dir.y / len, dir.z / len);
  const S a = Dot(v, u), b = Length(Cross(v, u));
  if (!(Abs(a) < S(INFINITY)) || !(Abs(b) < S(INFINITY))) return true;
  const S r = (sphere.w * S(layout::kRadiusSlack) + (Abs(a) + b) * S(layout::kTestSlack)) +
              S(std::bit_cast<float>(layout::kRadiusFloorBits));
  if (b > r) return false;
  const S t0 = tmin * len, t1 = tlimit * len;
  if (a + r < t0 - Abs(t0) * S(layout::kTestSlack)) return false;
  return !(a - r > t1 + Abs(t1) * S(layout::kTestSlack));
}

// Is |n| too small against |e1| |e2| (max norms, |n| < |e1| |e2| / 32) for the float normal's
// direction to be trusted?
template <typename S>
bool SliverOf(Vec3<S> e1, Vec3<S> e2, Vec3<S> n) {
  return !(MaxAbs(n, n) * S(32.0f) >= MaxAbs(e1, e1) * MaxAbs(e2, e2));
}

// The least (starting rays) or greatest (ending rays) projection of the triangle on m, by comparisons
// in vertex order.
template <typename S>
S FacetBoundOf(Vec3<S> m, Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, bool ends) {
  const S a = Dot(m, v0), b = Dot(m, v1), d = Dot(m, v2);
  return ends ? Greater(Greater(a, b), d) : Lesser(Lesser(a, b), d);
}

// What tl::RayCase decides from the ray and its triangle's vertices: 2 * ends + behind, or
// `no_case`. `facets` holds list k's facet normals (tl::Facets; none unless the heads are regular).
template <typename S>
std::uint32_t RayCaseOf(Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, Vec3<S> org, Vec3<S> d, S tmax, bool ends, const glm::vec3* m,
                        std::uint32_t facets, std::uint32_t no_case) {
  const Vec3<S> e1 = v1 - v0, e2 = v2 - v0, n = Cross(e1, e2);
  if (SliverOf(e1, e2, n)) return no_case;
  const S dn = Dot(d, n), lim = S(layout::kTlSideRatio) * (Length(d) * Length(n));
  if (!(Abs(dn) > lim)) return no_case;  // along the plane, or NaN
  // A starting ray reaches the side d points to; an ending one comes from the other.
  const bool behind = ends ? dn > S(0.0f) : dn < S(0.0f);
  const Vec3<S> p = ends ? org + d * tmax : org;
  for (std::uint32_t j = 0; j < facets; ++j) {
    const Vec3<S> mj(S(m[j].x), S(m[j].y), S(m[j].z));
    const S bound = FacetBoundOf(mj, v0, v1, v2, ends), x = Dot(mj, p);
    if (ends ? !(x <= bound) : !(x >= bound)) return no_case;
  }
  return (ends ? 2u : 0u) + (behind ? 1u : 0u);
}

}  // namespace rayspace::emu::tl
