// Certified-interval first, exact rationals when the interval cannot decide: a predicate written once
// as a template over the number type runs with CGAL's interval arithmetic (rounding toward +inf, so
// every interval encloses the exact value) and falls back to exact rationals only when a sign is
// uncertain (Uncertain_conversion_exception). The answer is always the exact one.
#pragma once
#include <type_traits>

#include <CGAL/Exact_rational.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Uncertain.h>

namespace rayspace::refs::detail {

template <typename F>
bool Filtered(F&& predicate) {
  {
    CGAL::Protect_FPU_rounding<true> protect;
    try {
      return predicate(CGAL::Interval_nt_advanced());
    } catch (const CGAL::Uncertain_conversion_exception&) {
    }
  }
  return predicate(CGAL::Exact_rational());
}

// Sign of a number as an int (throws Uncertain_conversion_exception for an undecided interval).
template <typename NT>
int Sign(const std::type_identity_t<NT>& x) {
  return static_cast<int>(static_cast<CGAL::Sign>(CGAL::sign(x)));
}

// Sign of A + B sqrt(S) for S >= 0.
template <typename NT>
int SignSqrt(const std::type_identity_t<NT>& A, const std::type_identity_t<NT>& B, const std::type_identity_t<NT>& S) {
  const int sa = Sign<NT>(A), sb = Sign<NT>(S) == 0 ? 0 : Sign<NT>(B);
  if (sb == 0) return sa;
  if (sa == 0) return sb;
  if (sa == sb) return sa;
  const int c = Sign<NT>(A * A - B * B * S);
  return c > 0 ? sa : c < 0 ? sb : 0;
}

// 3-vectors of an exact or interval number type, and the operations the predicates need.
template <typename NT>
struct V3 {
  NT x, y, z;
};
template <typename NT>
V3<NT> Sub(const V3<NT>& a, const V3<NT>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <typename NT>
NT Dot(const V3<NT>& a, const V3<NT>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <typename NT>
V3<NT> Cross(const V3<NT>& a, const V3<NT>& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
// v - o, each float taken exactly.
template <typename NT, typename Vec>
V3<NT> Rel(const Vec& v, const Vec& o) { return {NT(v.x) - NT(o.x), NT(v.y) - NT(o.y), NT(v.z) - NT(o.z)}; }
template <typename NT, typename Vec>
V3<NT> Exact(const Vec& v) { return {NT(v.x), NT(v.y), NT(v.z)}; }

}  // namespace rayspace::refs::detail
