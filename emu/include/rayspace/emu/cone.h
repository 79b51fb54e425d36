// Cone-sphere node arithmetic (thesis eqs. 3.8-3.16, Roger et al. eq. 1) without trigonometry: a
// cone's half-angle alpha is carried as (cos alpha, sin alpha), so every operation is one a GPU
// computes exactly. The papers' special cases are handled (docs/hierarchy.md):
// - a ray inside the cone leaves it unchanged (eqs. 3.8-3.11 would shrink it);
// - a ray along or against the axis (eq. 3.8 divides by zero): unchanged, or the full sphere;
// - antiparallel axes in a union (eq. 3.12 divides by zero): the full sphere;
// - half-angles >= pi/2 and spheres behind the apex in the test (eq. 3.16 assumes alpha < pi/2).
// Each finished node is checked against its rays or children in float (Enclose*) and then widened by
// small margins (Finish) that cover the rounding of those checks; the test adds a margin for its own
// rounding. Lengths of coordinate differences are computed scaled (ScaledLength) so tiny and huge
// coordinates neither underflow nor overflow. The bounds and their proofs: docs/numerics.md.
#pragma once
#include <bit>
#include <type_traits>
#include <utility>

#include "rayspace/contract.h"
#include "rayspace/emu/intersect.h"

namespace rayspace::emu::cone {

// Margins applied once per finished node (radii: relative 2^-18, half-angles: 2^-18 rad) and the
// test's own rounding slack are part of the kernel contract (rayspace/contract.h).
using layout::kAngleSlack;
using layout::kRadiusSlack;
using layout::kTestSlack;
// Absolute radius margin (2^-122): covers the absolute rounding of tiny radii, including a device's
// flushing of denormal results to zero (so it is itself normal); absorbed by rounding for radii above
// about 2^-97, so it changes nothing at ordinary scales.
inline constexpr float kRadiusFloor = std::bit_cast<float>(layout::kRadiusFloorBits);
static_assert(kRadiusFloor == 0x1p-122f);

// The node arithmetic is templated over the node type: layout::ConeNode (floats) in the emulated
// passes, NodeOf<verify::SpecReal> when the diff bounds what a device may compute (intersect.h).
template <typename S>
struct NodeOf {
  Vec4<S> sphere, cone, extra;
};
template <typename S>
struct NodeType {
  using type = NodeOf<S>;
};
template <>
struct NodeType<float> {
  using type = layout::ConeNode;
};
template <typename S>
using Node = typename NodeType<S>::type;
template <typename N>
using Scalar = std::decay_t<decltype(std::declval<N>().cone.w)>;

template <typename N>
N FullSphereCone(N n) {
  using S = Scalar<N>;
  n.cone = Vec4<S>(S(1.0f), S(0.0f), S(0.0f), S(-1.0f));
  n.extra.x = S(0.0f);
  return n;
}

template <typename N>
bool IsFull(const N& n) { return n.cone.w <= Scalar<N>(-1.0f); }

// Widens the half-angle by about kAngleSlack: (cos, sin) move as by a rotation of delta, rounded
// outward. In the test, s = b cos - a sin then drops by delta * (a cos + b sin) > 0 on the branch
// that uses it, so the test only accepts more. Sin carries small angles that cos cannot resolve.
template <typename N>
void Loosen(N& n) {
  using S = Scalar<N>;
  if (IsFull(n)) return;
  const S c = n.cone.w, s = n.extra.x;
  const S c2 = NextAfter(c - S(kAngleSlack) * s, -2.0f);
  const S s2 = NextAfter(s + S(kAngleSlack) * c, 2.0f);
  if (c2 <= S(-1.0f) || s2 < S(0.0f)) {
    n = FullSphereCone(n);
    return;
  }
  n.cone.w = c2;
  n.extra.x = Min(S(1.0f), s2);
}

// Makes sure the cone holds a direction (unit r) in float evaluation: if angle(axis, r) exceeds the
// half-angle, the half-angle becomes that angle. theta <= alpha iff sin(alpha - theta) >= 0.
template <typename N>
void EncloseDirection(N& n, Vec3<Scalar<N>> r) {
  using S = Scalar<N>;
  if (IsFull(n)) return;
  const Vec3<S> x = Xyz(n.cone);
  const S c = Dot(x, r), sr = Length(Cross(x, r));
  if (n.extra.x * c - n.cone.w * sr >= S(0.0f)) return;
  n.cone.w = Clamp(c, S(-1.0f), S(1.0f));
  n.extra.x = Min(S(1.0f), sr);
  if (n.cone.w <= S(-1.0f)) n = FullSphereCone(n);
}

// Makes sure the cone holds a child cone: angle(axis, child axis) + child half-angle <= half-angle.
template <typename N>
void EncloseCone(N& n, const N& child) {
  using S = Scalar<N>;
  if (IsFull(n)) return;
  if (IsFull(child)) {
    n = FullSphereCone(n);
    return;
  }
  const Vec3<S> x = Xyz(n.cone), xc = Xyz(child.cone);
  const S c = Dot(x, xc), sr = Length(Cross(x, xc));
  const S cs = c * child.cone.w - sr * child.extra.x;  // cos(theta + alpha_child)
  const S ss = sr * child.cone.w + c * child.extra.x;  // sin(theta + alpha_child)
  if (ss < S(0.0f) || cs <= S(-1.0f)) {                // past pi
    n = FullSphereCone(n);
    return;
  }
  if (n.extra.x * cs - n.cone.w * ss >= S(0.0f)) return;
  n.cone.w = Clamp(cs, S(-1.0f), S(1.0f));
  n.extra.x = Min(S(1.0f), ss);
}

// Makes sure the sphere holds a point or a child sphere (radius r at c).
template <typename N>
void EncloseSphere(N& n, Vec3<Scalar<N>> c, Scalar<N> r) {
  const Scalar<N> need = ScaledLength(c - Xyz(n.sphere)) + r;
  if (need > n.sphere.w) n.sphere.w = need;
}

template <typename N>
void Finish(N& n) {
  using S = Scalar<N>;
  n.sphere.w = NextAfter(n.sphere.w * S(kRadiusSlack) + S(kRadiusFloor), INFINITY);
  Loosen(n);
}

// A leaf: one ray (origin, unit direction), radius 0, half-angle 0.
template <typename S>
Node<S> FromRayOf(Vec3<S> origin, Vec3<S> unit_dir) {
  Node<S> n;
  n.sphere = Vec4<S>(origin, S(0.0f));
  n.cone = Vec4<S>(unit_dir, S(1.0f));
  n.extra = Vec4<S>(S(0.0f), S(1.0f), S(0.0f), S(0.0f));
  return n;
}
inline layout::ConeNode FromRay(glm::vec3 origin, glm::vec3 unit_dir) { return FromRayOf<float>(origin, unit_dir); }

// Sphere union, eqs. 3.14-3.15: centre at the midpoint, radius half the distance plus the larger
// radius (conservative, not minimal).
template <typename S>
Vec4<S> SphereUnion(Vec4<S> a, Vec4<S> b) {
  const Vec3<S> ca = Xyz(a), cb = Xyz(b);
  const Vec3<S> c = (ca + cb) * S(0.5f);
  const S r = ScaledLength(cb - ca) * S(0.5f) + Max(a.w, b.w);
  return Vec4<S>(c, r);
}

// Grows a node's cone by one unit ray direction r, eqs. 3.8-3.11.
template <typename N>
void GrowCone(N& n, Vec3<Scalar<N>> r) {
  using S = Scalar<N>;
  if (IsFull(n)) return;
  const Vec3<S> x = Xyz(n.cone);
  const S cosphi = n.cone.w, sinphi = n.extra.x;
  const S c = Dot(x, r);
  if (c >= cosphi) return;  // already inside
  const Vec3<S> qv = x * c - r;  // eq. 3.8 numerator
  const S ql = Length(qv);
  if (!(ql > S(0.0f))) {  // r against the axis (along it returned above)
    n = FullSphereCone(n);
    return;
  }
  const Vec3<S> q = qv / ql;
  const Vec3<S> e = x * cosphi + q * sinphi;  // eq. 3.9: the cone's far edge
  const Vec3<S> s = e + r;
  const S sl = Length(s);
  if (!(sl > S(0.0f))) {  // e = -r: the new cone is the whole sphere
    n = FullSphereCone(n);
    return;
  }
  const Vec3<S> xn = s / sl;                           // eq. 3.10
  n.cone = Vec4<S>(xn, Min(S(1.0f), Dot(xn, r)));      // eq. 3.11
  n.extra.x = Min(S(1.0f), Length(Cross(xn, r)));
}

// Cone union, eqs. 3.12-3.13 (intent: alpha = angle(x1, x2) / 2 + max(alpha1, alpha2) around
// normalize(x1 + x2)), with cos/sin of the half angle from the half-angle identities.
template <typename N>
Vec4<Scalar<N>> ConeUnion(const N& a, const N& b, Scalar<N>& sin_out) {
  using S = Scalar<N>;
  const Vec4<S> full(S(1.0f), S(0.0f), S(0.0f), S(-1.0f));
  if (IsFull(a) || IsFull(b)) {
    sin_out = S(0.0f);
    return full;
  }
  const Vec3<S> x1 = Xyz(a.cone), x2 = Xyz(b.cone);
  const Vec3<S> s = x1 + x2;
  const S sl = Length(s);
  if (!(sl > S(0.0f))) {
    sin_out = S(0.0f);
    return full;
  }
  const S c = Clamp(Dot(x1, x2), S(-1.0f), S(1.0f));
  const S ch = Sqrt((S(1.0f) + c) * S(0.5f)), sh = Sqrt((S(1.0f) - c) * S(0.5f));  // half of angle(x1, x2)
  const bool a_wider = a.cone.w <= b.cone.w;
  const S cm = a_wider ? a.cone.w : b.cone.w, sm = a_wider ? a.extra.x : b.extra.x;
  const S cn = ch * cm - sh * sm;  // cos(theta/2 + alpha_max)
  const S sn = sh * cm + ch * sm;  // sin(theta/2 + alpha_max)
  if (sn < S(0.0f)) {              // past pi: every direction
    sin_out = S(0.0f);
    return full;
  }
  sin_out = sn;
  return Vec4<S>(s / sl, cn);
}

template <typename N>
N Union(const N& a, const N& b) {
  using S = Scalar<N>;
  N n;
  n.sphere = SphereUnion(a.sphere, b.sphere);
  S sn;
  n.cone = ConeUnion(a, b, sn);
  n.extra = Vec4<S>(sn, a.extra.y + b.extra.y, S(0.0f), S(0.0f));
  if (n.cone.w <= S(-1.0f)) n = FullSphereCone(n);
  return n;
}

// Does the node's ray bundle possibly meet the sphere (p, radius)? Roger et al.'s eq. 1 generalised:
// the distance from p to the cone of apex C is at most d + r. With a = (p - C).axis, b = |(p - C) x
// axis|: inside the cone when b cos(alpha) - a sin(alpha) <= 0; otherwise the nearest cone point is
// on the surface (distance b cos - a sin) while a cos + b sin > 0, else the apex (distance |p - C|).
// Conservative in float (docs/numerics.md): v and R are scaled by a power of two so nothing over- or
// underflows, and the reach grows by kTestSlack (|a| + |b|) for the rounding of a, b and s.
// Templated over the scalar like intersect.h (verify::SpecReal bounds what a device may decide).
// Always inlined: it runs once per (node, triangle) slot, and as a template GCC no longer inlined it
// into the traversal loops by itself (8 % of the traversal's time, measured).
template <typename S>
[[gnu::always_inline]] inline bool TestOf(const layout::ConeNode& n, glm::vec4 sphere, float eps) {
  if (IsFull(n)) return true;
  using V = Vec3<S>;
  const V v0 = V(Xyz(sphere)) - V(Xyz(n.sphere));
  const S R0 = (S(sphere.w) + S(n.sphere.w)) * S(kRadiusSlack) + S(eps);
  const S m = Max(Max(Max(Abs(v0.x), Abs(v0.y)), Abs(v0.z)), R0);
  if (!(m > S(0.0f)) || !(m < S(INFINITY))) return true;  // at the apex, or out of float range: keep
  const S k = InversePowerOfTwo(m);
  const V v(v0.x * k, v0.y * k, v0.z * k);
  const V x = V(Xyz(n.cone));
  const S a = Dot(v, x);
  const S b = Length(Cross(v, x));
  const S cosa(n.cone.w), sina(n.extra.x);
  const S s = b * cosa - a * sina;  // |v| sin(gamma - alpha), gamma = angle(v, axis)
  const S c = a * cosa + b * sina;  // |v| cos(gamma - alpha)
  // Inside when gamma - alpha lies in [-pi, 0]: s <= 0, except s = 0 at gamma - alpha = pi (behind).
  if (s < S(0.0f) || (s == S(0.0f) && c >= S(0.0f))) return true;
  const S R = R0 * k + (Abs(a) + b) * S(kTestSlack);
  if (c > S(0.0f)) return s <= R;  // nearest point on the cone's surface
  return SelfDot(v) <= Square(R);  // nearest point is the apex
}

inline bool Test(const layout::ConeNode& n, glm::vec4 sphere, float eps) { return TestOf<float>(n, sphere, eps); }

// --leaf-test ray-sphere (kLeafTestRaySphere): may the ray meet the sphere? The ray as the leaf build
// makes a one-ray node (normalised direction, Finish), under the traversal's Test: a node holding the
// ray passes wherever the ray meets the sphere, so this one does too (the test is conservative).
inline bool RayMayMeetSphere(const layout::Ray& r, glm::vec4 sphere, float eps) {
  layout::ConeNode n = FromRay(Xyz(r.origin_tmin), Normalize(Xyz(r.direction_tmax)));
  Finish(n);
  return Test(n, sphere, eps);
}

// Thesis eq. 3.16 as printed (after Roger et al. eq. 1): |C - H| tan(alpha) + (d + r) / cos(alpha) >=
// |P - H|, H the projection of the sphere's centre P on the axis; in float, with no margins and none
// of Test's other special cases, so it is not conservative (docs/accuracy.md measures how often it
// errs). The equation assumes alpha < pi/2: a cone at or past a half-space (cos alpha <= 0, the full
// sphere among them) is kept, as Test keeps full cones, instead of dividing by a cos that flips or
// zeroes the left side. One function, so that accuracy and the traversal (--cone-test printed)
// evaluate the printed test the same way (cone.glsl PrintedConeTest: the same operations in order).
// The traversal's absolute margin eps widens the sphere. Templated over the scalar like TestOf
// (verify::SpecReal bounds what a device may decide).
// `signed_axis` (--cone-test printed-signed): the distance along the axis without its absolute value,
// one cone opening forward, where |C - H| makes two apex to apex.
template <typename S, bool signed_axis = false>
[[gnu::always_inline]] inline bool PrintedTestOf(const layout::ConeNode& n, glm::vec4 sphere, float eps) {
  using V = Vec3<S>;
  const S c(n.cone.w), s(n.extra.x);
  if (!(c > S(0.0f))) return true;
  const S r = S(sphere.w) + S(eps);
  const V v = V(Xyz(sphere)) - V(Xyz(n.sphere)), x = V(Xyz(n.cone));
  const S a = Dot(v, x);
  const V off = v - x * a;
  if constexpr (signed_axis) return a * (s / c) + (S(n.sphere.w) + r) / c >= Length(off);
  return Abs(a) * (s / c) + (S(n.sphere.w) + r) / c >= Length(off);
}
inline bool PrintedTest(const layout::ConeNode& n, glm::vec4 sphere, float eps) { return PrintedTestOf<float>(n, sphere, eps); }
inline bool PrintedSignedTest(const layout::ConeNode& n, glm::vec4 sphere, float eps) {
  return PrintedTestOf<float, true>(n, sphere, eps);
}
// The geometric question alone (accuracy's per-query table): no margin, sphere.w + 0 = sphere.w.
inline bool PrintedTest(const layout::ConeNode& n, glm::vec4 sphere) { return PrintedTest(n, sphere, 0.0f); }

// The two tests as lambdas, not function pointers, so a traversal loop templated on its test inlines it.
inline constexpr auto kTestFn = [](const layout::ConeNode& n, glm::vec4 sphere, float eps) { return Test(n, sphere, eps); };
inline constexpr auto kPrintedTestFn = [](const layout::ConeNode& n, glm::vec4 sphere, float eps) {
  return PrintedTest(n, sphere, eps);
};
inline constexpr auto kPrintedSignedTestFn = [](const layout::ConeNode& n, glm::vec4 sphere, float eps) {
  return PrintedSignedTest(n, sphere, eps);
};

// The test a traversal's cone_test (layout::kConeTest*) names.
[[gnu::always_inline]] inline bool TestBy(std::uint32_t cone_test, const layout::ConeNode& n, glm::vec4 sphere, float eps) {
  return cone_test == layout::kConeTestPrinted         ? PrintedTest(n, sphere, eps)
         : cone_test == layout::kConeTestPrintedSigned ? PrintedSignedTest(n, sphere, eps)
                                                       : Test(n, sphere, eps);
}

// One step of a leaf build: the node grown by one ray (origin o, unit direction r) with eqs. 3.8-3.11
// and 3.14-3.15, checked in float against the old node and the ray, then finished with the margins.
// It contains both exactly (docs/numerics.md; fuzz/cone_grow), so a leaf folded from these steps
// contains all its rays.
template <typename N>
N GrowNode(const N& old, Vec3<Scalar<N>> o, Vec3<Scalar<N>> r) {
  using S = Scalar<N>;
  N n = old;
  n.sphere = SphereUnion(n.sphere, Vec4<S>(o, S(0.0f)));
  GrowCone(n, r);
  EncloseSphere(n, Xyz(old.sphere), old.sphere.w);
  EncloseSphere(n, o, S(0.0f));
  EncloseCone(n, old);
  EncloseDirection(n, r);
  Finish(n);
  n.extra.y = old.extra.y + S(1.0f);
  return n;
}

// A level-1 node over rays (given by index through `order`): a finished one-ray node grown ray by ray.
template <typename S, typename RayAt>
Node<S> LeafNodeOf(std::uint32_t count, RayAt&& ray_at) {
  const layout::Ray& r0 = ray_at(0);
  Node<S> n = FromRayOf<S>(Vec3<S>(Xyz(r0.origin_tmin)), Normalize(Vec3<S>(Xyz(r0.direction_tmax))));
  Finish(n);
  for (std::uint32_t j = 1; j < count; ++j) {
    const layout::Ray& r = ray_at(j);
    n = GrowNode(n, Vec3<S>(Xyz(r.origin_tmin)), Normalize(Vec3<S>(Xyz(r.direction_tmax))));
  }
  return n;
}
template <typename RayAt>
layout::ConeNode LeafNode(std::uint32_t count, RayAt&& ray_at) {
  return LeafNodeOf<float>(count, ray_at);
}

// --child-merge pairwise: the children united as a balanced binary tree in child order. A binary
// counter over a stack: each child is pushed, and while the two newest partial unions hold equally
// many children they merge (older one first); the partial unions left are then folded newest first
// into the older ones. 8 points evenly spaced on a line: radius 3.5 spacings where the sequential fold
// gives 6 (a union's radius is half the distance plus the larger radius, so it grows per fold step).
template <typename N>
N PairwiseUnion(const N* children, std::uint32_t count) {
  N stack[33];
  std::uint32_t held[33];
  int top = -1;
  for (std::uint32_t j = 0; j < count; ++j) {
    stack[++top] = children[j];
    held[top] = 1;
    while (top >= 1 && held[top] == held[top - 1]) {
      stack[top - 1] = Union(stack[top - 1], stack[top]);
      held[top - 1] *= 2;
      --top;
    }
  }
  N n = stack[top];
  for (int i = top - 1; i >= 0; --i) n = Union(stack[i], n);
  return n;
}

// An upper-level node: unions of the children (eqs. 3.12-3.15), one after another or pairwise
// (layout::kChildMergePairwise), checked against each child, finished.
template <typename N>
N ParentNode(const N* children, std::uint32_t count, std::uint32_t merge = layout::kChildMergeSequential) {
  N n = children[0];
  if (merge == layout::kChildMergePairwise && count > 1)
    n = PairwiseUnion(children, count);
  else
    for (std::uint32_t j = 1; j < count; ++j) n = Union(n, children[j]);
  for (std::uint32_t j = 0; j < count; ++j) {
    EncloseSphere(n, Xyz(children[j].sphere), children[j].sphere.w);
    EncloseCone(n, children[j]);
  }
  Finish(n);
  return n;
}

}  // namespace rayspace::emu::cone
