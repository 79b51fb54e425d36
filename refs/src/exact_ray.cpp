#include <cmath>

#include <glm/glm.hpp>

#include "exact_filter.h"
#include "rayspace/refs/exact.h"

namespace rayspace::refs {
namespace {

using detail::Sign;

using detail::Cross;
using detail::Dot;
using detail::Sub;
using detail::V3;
template <typename NT>
V3<NT> Rel(glm::vec3 v, glm::vec3 o) { return detail::Rel<NT>(v, o); }

template <typename NT>
NT Det(const V3<NT>& a, const V3<NT>& b, const V3<NT>& c) { return Dot(a, Cross(b, c)); }

// With a, b, c the vertices relative to the origin: the line t d crosses the triangle's interior iff
// the edge volumes Va = [d, b, c], Vb = [d, c, a], Vc = [d, a, b] share a strict sign, on the side
// t > 0 iff T = [a, b, c] has that sign too. A float test sees the vertices translated and rounded,
// i.e. moved by up to delta = rel M; moving b and c by delta changes Va by at most
// |d| delta (|b| + |c| + delta) < 8 |d| delta M (|b|, |c| <= 2 sqrt(3) M), and T by less than 36 delta M^2.
// The hit is robust when every sign survives that: Va^2 > 64 delta^2 M^2 |d|^2 (and likewise), and
// T^2 > 2^11 delta^2 M^4.
template <typename NT>
bool RobustHit(glm::vec3 o, glm::vec3 dir, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, float rel, float scale) {
  const V3<NT> d{NT(dir.x), NT(dir.y), NT(dir.z)};
  const V3<NT> a = Rel<NT>(v0, o), b = Rel<NT>(v1, o), c = Rel<NT>(v2, o);
  const NT Va = Det(d, b, c), Vb = Det(d, c, a), Vc = Det(d, a, b);
  const NT S = Va + Vb + Vc;
  const int s = Sign<NT>(S);
  if (s == 0 || Sign<NT>(Va) != s || Sign<NT>(Vb) != s || Sign<NT>(Vc) != s) return false;
  const NT T = Det(a, b, c);
  if (Sign<NT>(T) != s) return false;
  const NT M(scale), delta = NT(rel) * M;
  const NT edge_bound = NT(64) * delta * delta * M * M * Dot(d, d);
  const NT side_bound = NT(2048) * delta * delta * M * M * M * M;
  return Sign<NT>(Va * Va - edge_bound) > 0 && Sign<NT>(Vb * Vb - edge_bound) > 0 && Sign<NT>(Vc * Vc - edge_bound) > 0 &&
         Sign<NT>(T * T - side_bound) > 0;
}

// The hit decision with tmin < t < tmax (as HitDecision) and whether it survives moving the vertices
// relative to the origin by up to delta = rel L per coordinate, L the largest coordinate magnitude of
// those relative vertices (the float tests round v - o and what follows at that scale). The bounds are
// RobustHit's with L for M (|b| <= sqrt(3) L); for an interval end e, e S - T moves by less than
// 36 delta L (L + |e| |d|) (S by less than 24 |d| delta L), squared as 2592 delta^2 L^2 (L^2 + e^2 |d|^2).
// A miss is robust when one reason for it is: an edge volume of the other sign beyond its bound, or
// t beyond an end by more than its bound.
// One-sided (ExactContact): S = d . ((b - a) x (c - a)) is negative from the front. Moving the vertices
// by delta moves the normal by less than 24 delta L + 12 delta^2 <= 25 delta L (|e| <= 2 sqrt(3) L),
// so the side is robust when S^2 > 625 delta^2 L^2 |d|^2; a back met robustly is a robust miss.
template <typename NT>
Judgement Judge(const layout::Ray& ray, const layout::Triangle& tri, float rel, float scale, bool one_sided) {
  const glm::vec3 o(ray.origin_tmin), dir(ray.direction_tmax);
  const V3<NT> d{NT(dir.x), NT(dir.y), NT(dir.z)};
  const V3<NT> a = Rel<NT>(glm::vec3(tri.v0), o), b = Rel<NT>(glm::vec3(tri.v1), o), c = Rel<NT>(glm::vec3(tri.v2), o);
  const NT V[3] = {Det(d, b, c), Det(d, c, a), Det(d, a, b)};
  const NT S = V[0] + V[1] + V[2], T = Det(a, b, c);
  const NT M(scale), delta = NT(rel) * M, dd = Dot(d, d);
  const NT edge_bound = NT(64) * delta * delta * M * M * dd;
  const int s = Sign<NT>(S);
  if (s == 0) return {false, false};  // in the triangle's plane, or parallel to it
  bool robust_edges = true, robust_out = false, hit = true;
  for (const NT& v : V) {
    const bool clear = Sign<NT>(v * v - edge_bound) > 0;
    if (Sign<NT>(v) == -s) {
      hit = false;
      robust_out = robust_out || clear;
    }
    robust_edges = robust_edges && clear;
  }
  // An interval end e: s (T - e S) > 0 is t > e. Its margin grows with |e| |d|.
  auto beyond = [&](float e, int want) -> std::pair<bool, bool> {
    const NT m = T - NT(e) * S;
    const NT w = NT(2592) * delta * delta * M * M * (M * M + NT(e) * NT(e) * dd);
    return {Sign<NT>(m) * s == want, Sign<NT>(m * m - w) > 0};
  };
  const auto [after_min, clear_min] = beyond(ray.origin_tmin.w, 1);
  hit = hit && after_min;
  robust_out = robust_out || (!after_min && clear_min);
  bool clear_max = true;
  if (std::isinf(ray.direction_tmax.w)) {
    hit = hit && ray.direction_tmax.w > 0;
  } else {
    const auto [before_max, c] = beyond(ray.direction_tmax.w, -1);
    hit = hit && before_max;
    robust_out = robust_out || (!before_max && c);
    clear_max = c;
  }
  const NT side_bound = NT(2048) * delta * delta * M * M * M * M;
  const Judgement two = hit ? Judgement{true, robust_edges && clear_min && clear_max && Sign<NT>(T * T - side_bound) > 0}
                            : Judgement{false, robust_out};
  if (!one_sided) return two;
  const bool front = s < 0, facing_clear = Sign<NT>(S * S - NT(625) * delta * delta * M * M * dd) > 0;
  if (!facing_clear) return {false, two.robust && !two.hit};  // the side may come out either way
  return front ? two : Judgement{false, true};
}

template <typename NT>
bool HitDecision(const layout::Ray& ray, const layout::Triangle& tri, bool one_sided) {
  const glm::vec3 o(ray.origin_tmin), dir(ray.direction_tmax);
  const V3<NT> d{NT(dir.x), NT(dir.y), NT(dir.z)};
  const V3<NT> a = Rel<NT>(glm::vec3(tri.v0), o), b = Rel<NT>(glm::vec3(tri.v1), o), c = Rel<NT>(glm::vec3(tri.v2), o);
  const NT Va = Det(d, b, c), Vb = Det(d, c, a), Vc = Det(d, a, b);
  const NT S = Va + Vb + Vc;
  const int s = Sign<NT>(S);
  if (s == 0 || (one_sided && s > 0)) return false;
  // Closed triangle: no edge volume of the opposite sign.
  if (Sign<NT>(Va) == -s || Sign<NT>(Vb) == -s || Sign<NT>(Vc) == -s) return false;
  // t = T / S; tmin < t < tmax  <=>  s (T - tmin S) > 0 and s (tmax S - T) > 0.
  const NT T = Det(a, b, c);
  if (Sign<NT>(T - NT(ray.origin_tmin.w) * S) != s) return false;
  if (std::isinf(ray.direction_tmax.w)) return ray.direction_tmax.w > 0;
  return Sign<NT>(NT(ray.direction_tmax.w) * S - T) == s;
}

// t = T / S for the ray against a triangle (vertices relative to the origin).
template <typename NT>
void TS(const layout::Ray& ray, const layout::Triangle& tri, NT& T, NT& S) {
  const glm::vec3 o(ray.origin_tmin), dir(ray.direction_tmax);
  const V3<NT> d{NT(dir.x), NT(dir.y), NT(dir.z)};
  const V3<NT> a = Rel<NT>(glm::vec3(tri.v0), o), b = Rel<NT>(glm::vec3(tri.v1), o), c = Rel<NT>(glm::vec3(tri.v2), o);
  T = Det(a, b, c);
  S = Det(d, b, c) + Det(d, c, a) + Det(d, a, b);
}

template <typename NT>
int CompareT(const layout::Ray& ray, const layout::Triangle& ta, const layout::Triangle& tb) {
  NT Ta, Sa, Tb, Sb;
  TS(ray, ta, Ta, Sa);
  TS(ray, tb, Tb, Sb);
  // Ta / Sa - Tb / Sb = (Ta Sb - Tb Sa) / (Sa Sb).
  return Sign<NT>(Ta * Sb - Tb * Sa) * Sign<NT>(Sa * Sb);
}

// |t_a - t_b| <= rel (L + max(|t_a|, |t_b|) |d|) / |d|, with t = T / S and L the relative vertices'
// largest coordinate magnitude: the order of two distances that close may come out either way in float.
template <typename NT>
bool Close(const layout::Ray& ray, const layout::Triangle& ta, const layout::Triangle& tb, float rel, float scale) {
  NT Ta, Sa, Tb, Sb;
  TS(ray, ta, Ta, Sa);
  TS(ray, tb, Tb, Sb);
  if (Sign<NT>(Sa) == 0 || Sign<NT>(Sb) == 0) return false;
  const glm::vec3 dir(ray.direction_tmax);
  const NT dd = NT(dir.x) * NT(dir.x) + NT(dir.y) * NT(dir.y) + NT(dir.z) * NT(dir.z);
  // (t_a - t_b) Sa Sb = Ta Sb - Tb Sa, and max(|t_a|, |t_b|) |Sa Sb| <= |Ta Sb| + |Tb Sa|.
  const NT diff = Ta * Sb - Tb * Sa, ss = Sa * Sb, M(scale), r(rel);
  const NT big = CGAL::abs(Ta * Sb) + CGAL::abs(Tb * Sa);
  // diff^2 dd <= r^2 (M |Sa Sb| + big sqrt(dd))^2, relaxed by (x + y)^2 <= 2 x^2 + 2 y^2.
  const NT lhs = diff * diff * dd;
  const NT rhs = NT(2) * r * r * (M * M * ss * ss + big * big * dd);
  return Sign<NT>(rhs - lhs) >= 0;
}

template <typename NT>
bool InPlane(const layout::Ray& ray, const layout::Triangle& tri) {
  const glm::vec3 o(ray.origin_tmin), dir(ray.direction_tmax);
  const V3<NT> d{NT(dir.x), NT(dir.y), NT(dir.z)};
  const V3<NT> a = Rel<NT>(glm::vec3(tri.v0), o), b = Rel<NT>(glm::vec3(tri.v1), o), c = Rel<NT>(glm::vec3(tri.v2), o);
  return Sign<NT>(Det(a, b, c)) == 0 && Sign<NT>(Det(d, b, c) + Det(d, c, a) + Det(d, a, b)) == 0;
}

float MaxAbs(glm::vec3 v) { return std::max(std::fabs(v.x), std::max(std::fabs(v.y), std::fabs(v.z))); }

// The largest coordinate magnitude of the vertices relative to the ray's origin (rounded up by a
// relative 2^-20, so that the float subtraction's rounding never shrinks the scale).
float RelativeScale(const layout::Ray& ray, const layout::Triangle& tri) {
  const glm::vec3 o(ray.origin_tmin);
  const float l = std::max(std::max(MaxAbs(glm::vec3(tri.v0) - o), MaxAbs(glm::vec3(tri.v1) - o)), MaxAbs(glm::vec3(tri.v2) - o));
  return l * (1.0f + 0x1p-20f);
}

}  // namespace

bool ExactRobustInteriorHit(glm::vec3 o, glm::vec3 d, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, float rel) {
  const float scale = std::max(std::max(MaxAbs(o), MaxAbs(v0)), std::max(MaxAbs(v1), MaxAbs(v2)));
  return detail::Filtered([&](auto nt) { return RobustHit<decltype(nt)>(o, d, v0, v1, v2, rel, scale); });
}

Judgement ExactJudge(const layout::Ray& ray, const layout::Triangle& tri, float rel, bool one_sided) {
  const float scale = RelativeScale(ray, tri);
  Judgement j;
  detail::Filtered([&](auto nt) {
    j = Judge<decltype(nt)>(ray, tri, rel, scale, one_sided);
    return true;
  });
  return j;
}

bool ExactDistancesClose(const layout::Ray& ray, const layout::Triangle& a, const layout::Triangle& b, float rel) {
  const float scale = std::max(RelativeScale(ray, a), RelativeScale(ray, b));
  return detail::Filtered([&](auto nt) { return Close<decltype(nt)>(ray, a, b, rel, scale); });
}

bool ExactHitDecision(const layout::Ray& ray, const layout::Triangle& tri, bool filtered, bool one_sided) {
  if (filtered) return detail::Filtered([&](auto nt) { return HitDecision<decltype(nt)>(ray, tri, one_sided); });
  return HitDecision<CGAL::Exact_rational>(ray, tri, one_sided);
}

int ExactCompareHitDistance(const layout::Ray& ray, const layout::Triangle& a, const layout::Triangle& b) {
  int r = 0;
  detail::Filtered([&](auto nt) {
    r = CompareT<decltype(nt)>(ray, a, b);
    return true;
  });
  return r;
}

bool ExactInPlane(const layout::Ray& ray, const layout::Triangle& tri) {
  return detail::Filtered([&](auto nt) { return InPlane<decltype(nt)>(ray, tri); });
}

namespace {

// |o + t d - c|^2 - r^2 = A t^2 + 2 B t + E, A = d.d, B = d.(o - c), E = |o - c|^2 - r^2, least on
// [t0, t1] at the vertex -B / A clamped to the ends; compared without division.
template <typename NT>
bool SegmentMeetsSphere(glm::vec3 o, glm::vec3 dir, float t0, float t1, glm::vec4 s) {
  const V3<NT> d{NT(dir.x), NT(dir.y), NT(dir.z)};
  const V3<NT> w = Rel<NT>(o, glm::vec3(s));
  const NT A = Dot(d, d), B = Dot(d, w), E = Dot(w, w) - NT(s.w) * NT(s.w);
  const NT lo(t0);
  auto f = [&](const NT& t) { return (A * t + NT(2) * B) * t + E; };
  if (Sign<NT>(-B - A * lo) < 0) return Sign<NT>(f(lo)) <= 0;
  if (std::isfinite(t1)) {
    const NT hi(t1);
    if (Sign<NT>(-B - A * hi) > 0) return Sign<NT>(f(hi)) <= 0;
  }
  return Sign<NT>(A * E - B * B) <= 0;
}

}  // namespace

bool ExactSegmentMeetsSphere(glm::vec3 o, glm::vec3 d, float t0, float t1, glm::vec4 sphere) {
  if (!(t0 <= t1)) return false;
  return detail::Filtered([&](auto nt) { return SegmentMeetsSphere<decltype(nt)>(o, d, t0, t1, sphere); });
}

}  // namespace rayspace::refs
