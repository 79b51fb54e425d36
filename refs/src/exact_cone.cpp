#include "rayspace/refs/exact_cone.h"

#include <cmath>

#include <glm/glm.hpp>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include "exact_filter.h"

namespace rayspace::refs {
namespace {

using detail::Filtered;
using detail::Sign;
using detail::SignSqrt;

using detail::Cross;
using detail::Dot;
using detail::Sub;
using detail::V3;
template <typename NT>
V3<NT> Vec(glm::vec3 v) { return detail::Exact<NT>(v); }

bool Full(const layout::ConeNode& n) {
  return n.cone.w <= -1.0f || (n.cone.w == 0.0f && n.extra.x == 0.0f) ||
         (n.cone.x == 0.0f && n.cone.y == 0.0f && n.cone.z == 0.0f) || (n.extra.x <= 0.0f && n.cone.w < 0.0f);
}

// angle of u = (p, sqrt(S)) <= angle of w = (c, s), both nonzero in the closed upper half-plane:
// cross(u, w) = p s - q c > 0 means u comes first; when they are collinear the angles are equal if
// they point the same way (u.w > 0), else the one along +x (angle 0) comes first.
template <typename NT>
bool AngleLeq(const NT& p, const NT& S, const NT& c, const NT& s) {
  const int cross = SignSqrt<NT>(p * s, -c, S);
  if (cross != 0) return cross > 0;
  if (SignSqrt<NT>(p * c, s, S) > 0) return true;
  return Sign<NT>(p) > 0;
}

template <typename NT>
bool ContainsDirection(const layout::ConeNode& n, glm::vec3 d) {
  const V3<NT> x = Vec<NT>(glm::vec3(n.cone)), r = Vec<NT>(d);
  const V3<NT> xr = Cross(x, r);
  return AngleLeq(Dot(x, r), Dot(xr, xr), NT(n.cone.w), NT(n.extra.x));
}

template <typename NT>
bool ContainsCone(const layout::ConeNode& n, const layout::ConeNode& child) {
  const NT c(n.cone.w), s(n.extra.x), cc(child.cone.w), sc(child.extra.x);
  // alpha_child <= alpha: cross((cc, sc), (c, s)) >= 0.
  if (Sign<NT>(cc * s - sc * c) < 0) return false;
  // beta = alpha - alpha_child as the vector (c, s) * conj(cc, sc), in [0, pi].
  const NT bx = c * cc + s * sc, by = s * cc - c * sc;
  const V3<NT> x = Vec<NT>(glm::vec3(n.cone)), xc = Vec<NT>(glm::vec3(child.cone));
  const V3<NT> k = Cross(x, xc);
  return AngleLeq(Dot(x, xc), Dot(k, k), bx, by);
}

template <typename NT>
bool BallContainsBall(glm::vec4 outer, glm::vec4 inner) {
  const NT slack = NT(outer.w) - NT(inner.w);
  if (Sign<NT>(slack) < 0) return false;
  const V3<NT> d = Sub(Vec<NT>(glm::vec3(inner)), Vec<NT>(glm::vec3(outer)));
  return Sign<NT>(slack * slack - Dot(d, d)) >= 0;
}

template <typename NT>
bool MeetsSphere(const layout::ConeNode& n, glm::vec4 sphere) {
  const NT D = NT(n.sphere.w) + NT(sphere.w);
  if (Sign<NT>(D) < 0) return false;
  const V3<NT> v = Sub(Vec<NT>(glm::vec3(sphere)), Vec<NT>(glm::vec3(n.sphere)));
  const NT vv = Dot(v, v);
  if (Sign<NT>(D * D - vv) >= 0) return true;  // within reach of the apex: distance to the cone <= |v|
  if (Full(n)) return true;
  const V3<NT> x = Vec<NT>(glm::vec3(n.cone));
  const NT c(n.cone.w), s(n.extra.x);
  const NT p = Dot(v, x);
  const V3<NT> k = Cross(v, x);
  const NT S = Dot(k, k);  // (|v||x| sin gamma)^2
  if (AngleLeq(p, S, c, s)) return true;  // gamma <= alpha: the centre is inside the cone
  // gamma - alpha < pi/2: the nearest cone point lies on the surface; |v| sin(gamma - alpha) =
  // (q c - p s) / (|x| sqrt(c^2 + s^2)) with q = sqrt(S). Else the apex is nearest (handled above).
  if (SignSqrt<NT>(p * c, s, S) <= 0) return false;
  // (q c - p s) > 0 here; compare its square with D^2 |x|^2 (c^2 + s^2).
  const NT X = Dot(x, x), N = c * c + s * s;
  return SignSqrt<NT>(D * D * X * N - S * c * c - p * p * s * s, NT(2) * p * s * c, S) >= 0;
}

}  // namespace

bool ExactConeContainsDirection(const layout::ConeNode& n, glm::vec3 d) {
  if (Full(n) || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f)) return true;
  return Filtered([&](auto nt) { return ContainsDirection<decltype(nt)>(n, d); });
}

bool ExactConeContainsCone(const layout::ConeNode& n, const layout::ConeNode& child) {
  if (Full(n)) return true;
  if (Full(child)) return false;
  return Filtered([&](auto nt) { return ContainsCone<decltype(nt)>(n, child); });
}

bool ExactBallContainsBall(glm::vec4 outer, glm::vec4 inner) {
  if (outer.w == INFINITY) return true;  // an overflowed radius bounds everything
  return Filtered([&](auto nt) { return BallContainsBall<decltype(nt)>(outer, inner); });
}

bool ExactNodeContains(const layout::ConeNode& n, const layout::ConeNode& child, std::string* why) {
  if (!ExactBallContainsBall(n.sphere, child.sphere)) {
    if (why) *why = "sphere";
    return false;
  }
  if (!ExactConeContainsCone(n, child)) {
    if (why) *why = "cone";
    return false;
  }
  return true;
}

bool ExactNodeContainsRay(const layout::ConeNode& n, glm::vec3 origin, glm::vec3 direction, std::string* why) {
  if (!ExactBallContainsBall(n.sphere, glm::vec4(origin, 0.0f))) {
    if (why) *why = "sphere";
    return false;
  }
  if (!ExactConeContainsDirection(n, direction)) {
    if (why) *why = "cone";
    return false;
  }
  return true;
}

bool ExactNodeMeetsSphere(const layout::ConeNode& n, glm::vec4 sphere) {
  if (n.sphere.w == INFINITY || sphere.w == INFINITY) return true;
  return Filtered([&](auto nt) { return MeetsSphere<decltype(nt)>(n, sphere); });
}

bool ExactNodeMeetsSphere(const layout::ConeNode& n, glm::vec4 sphere, ExactArithmetic arithmetic) {
  if (n.sphere.w == INFINITY || sphere.w == INFINITY) return true;
  switch (arithmetic) {
    case ExactArithmetic::kFiltered: return ExactNodeMeetsSphere(n, sphere);
    case ExactArithmetic::kRational: return MeetsSphere<CGAL::Exact_rational>(n, sphere);
    case ExactArithmetic::kLazy: return MeetsSphere<CGAL::Epeck::FT>(n, sphere);
  }
  return true;
}

bool DoubleNodeMeetsSphere(const layout::ConeNode& n, glm::vec4 sphere) {
  if (Full(n)) return true;
  const glm::dvec3 v = glm::dvec3(glm::vec3(sphere)) - glm::dvec3(glm::vec3(n.sphere));
  const double R = double(sphere.w) + double(n.sphere.w);
  const glm::dvec3 x(glm::vec3(n.cone));
  const double a = glm::dot(v, x), b = glm::length(glm::cross(v, x));
  const double c = n.cone.w, s = n.extra.x;
  const double sn = b * c - a * s, cs = a * c + b * s;
  if (sn < 0.0 || (sn == 0.0 && cs >= 0.0)) return true;
  if (cs > 0.0) return sn <= R;
  return glm::dot(v, v) <= R * R;
}

}  // namespace rayspace::refs
