// All CGAL exact-kernel code lives in this one translation unit (it is slow to compile).
#include "rayspace/refs/exact.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>

#include "rayspace/emu/intersect.h"

namespace rayspace::refs {
namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = K::FT;

K::Point_3 P(const glm::vec4& v) { return {v.x, v.y, v.z}; }

// Cheap double-precision prefilter with a wide tolerance: it keeps every triangle the exact test can
// accept (errors here are ~1e-15 relative, the tolerance is 1e-6), and drops the rest of the scene.
bool MaybeHits(const layout::Ray& r, const layout::Triangle& t) {
  const glm::dvec3 o(emu::Xyz(r.origin_tmin)), d(emu::Xyz(r.direction_tmax));
  const glm::dvec3 v0(emu::Xyz(t.v0)), e1 = glm::dvec3(emu::Xyz(t.v1)) - v0, e2 = glm::dvec3(emu::Xyz(t.v2)) - v0;
  const glm::dvec3 p = glm::cross(d, e2);
  const double det = glm::dot(e1, p);
  const double scale = glm::length(e1) * glm::length(e2) * glm::length(d);
  if (std::fabs(det) <= 1e-9 * scale) return true;  // near-parallel: let the exact test decide
  const glm::dvec3 s = o - v0;
  const double u = glm::dot(s, p) / det;
  const glm::dvec3 q = glm::cross(s, e1);
  const double v = glm::dot(d, q) / det;
  const double tt = glm::dot(e2, q) / det;
  constexpr double kTol = 1e-6;
  if (u < -kTol || v < -kTol || u + v > 1 + kTol) return false;
  const double tmin = r.origin_tmin.w, tmax = r.direction_tmax.w;
  return tt > tmin - kTol * (std::fabs(tmin) + std::fabs(tt)) && tt < tmax + kTol * (std::fabs(tmax) + std::fabs(tt));
}

// Exact squared parameter t^2 of the nearest point where the ray (t >= 0) meets the triangle, if any.
bool NearestT2(const layout::Ray& r, const layout::Triangle& t, FT& t2, bool* boundary = nullptr) {
  const K::Point_3 o = P(r.origin_tmin);
  const K::Vector_3 d(r.direction_tmax.x, r.direction_tmax.y, r.direction_tmax.z);
  const K::Triangle_3 tri(P(t.v0), P(t.v1), P(t.v2));
  if (tri.is_degenerate()) return false;
  const K::Ray_3 ray(o, d);
  const auto x = CGAL::intersection(ray, tri);
  if (!x) return false;
  K::Point_3 hit;
  if (const K::Point_3* p = boost::get<K::Point_3>(&*x)) {
    hit = *p;
  } else if (const K::Segment_3* s = boost::get<K::Segment_3>(&*x)) {  // coplanar: the nearer end
    hit = CGAL::compare_distance_to_point(o, s->source(), s->target()) == CGAL::SMALLER ? s->source() : s->target();
  } else {
    return false;
  }
  t2 = CGAL::squared_distance(o, hit) / d.squared_length();
  if (boundary) {
    *boundary = false;
    for (int e = 0; e < 3; ++e)
      *boundary = *boundary || K::Segment_3(tri.vertex(e), tri.vertex(e + 1)).has_on(hit);
  }
  return true;
}

bool InRange(const layout::Ray& r, const FT& t2) {
  // t >= 0 here, so comparing squares is exact and monotone.
  const FT tmin(r.origin_tmin.w), tmax(r.direction_tmax.w);
  const bool above = r.origin_tmin.w < 0 ? true : t2 > tmin * tmin;
  const bool below = std::isinf(r.direction_tmax.w) ? true : t2 < tmax * tmax;
  return above && below;
}

// One-sided triangles: is the ray's direction against the normal (v1 - v0) x (v2 - v0), exactly?
bool Front(const layout::Ray& r, const layout::Triangle& t) {
  const K::Vector_3 d(r.direction_tmax.x, r.direction_tmax.y, r.direction_tmax.z);
  const K::Vector_3 n = CGAL::cross_product(P(t.v1) - P(t.v0), P(t.v2) - P(t.v0));
  return CGAL::is_negative(d * n);
}

}  // namespace

Contact ExactContact(const layout::Ray& ray, const layout::Triangle& tri, bool one_sided) {
  if (one_sided && !Front(ray, tri)) return Contact::kMiss;
  FT t2;
  bool boundary = false;
  if (!NearestT2(ray, tri, t2, &boundary) || !InRange(ray, t2)) return Contact::kMiss;
  return boundary ? Contact::kBoundary : Contact::kInterior;
}

Contact ExactOccluded(const layout::Ray& ray, const SceneBuffers& scene) {
  Contact best = Contact::kMiss;
  for (std::uint32_t p = 0; p < scene.triangles.size() && best != Contact::kInterior; ++p)
    if (p != ray.info.y && MaybeHits(ray, scene.triangles[p])) best = std::max(best, ExactContact(ray, scene.triangles[p], scene.one_sided));
  return best;
}

std::vector<std::uint32_t> ExactClosest(const layout::Ray& ray, const SceneBuffers& scene) {
  std::vector<std::uint32_t> best;
  FT best_t2;
  for (std::uint32_t p = 0; p < scene.triangles.size(); ++p) {
    if (p == ray.info.y || !MaybeHits(ray, scene.triangles[p])) continue;
    if (scene.one_sided && !Front(ray, scene.triangles[p])) continue;
    FT t2;
    if (!NearestT2(ray, scene.triangles[p], t2) || !InRange(ray, t2)) continue;
    if (best.empty() || t2 < best_t2) {
      best.assign(1, p);
      best_t2 = t2;
    } else if (t2 == best_t2) {
      best.push_back(p);
    }
  }
  return best;
}

}  // namespace rayspace::refs
