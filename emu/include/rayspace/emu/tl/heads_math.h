// The rounded arithmetic of the lists' windows (tl.heads' planes through a triangle, tl.cells' side
// planes of a screen cell) and their rejection tests, templated over the scalar like the walk's
// (rayspace/emu/tl/walk_math.h): float is the emulator's and the kernels' arithmetic, operation for
// operation; verify::SpecReal asks which rejections a conformant device may decide the other way.
#pragma once
#include <algorithm>
#include <cstdint>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/walk_math.h"
#include "rayspace/layout.h"

namespace rayspace::emu::tl {

// An upper bound of sqrt(2), the length of a sextant facet's normal e_a +- e_b.
inline constexpr float kSqrt2Up = 1.41421366f;

// The facet normals of list k's direction class (K = 2: 1; 6: 4, s e_a +- e_b and s e_a +- e_c;
// 8: the 3 signed axes; 1: none); returns how many.
std::uint32_t Facets(std::uint32_t count, std::uint32_t k, glm::vec3 m[4]);

// The planes of one (triangle, case, list): the triangle's plane n . (x - v0) (n = (v1 - v0) x
// (v2 - v0)), on the side behind (case & 1) or in front, and `facets` facet planes m . x against
// `bound` (starting rays: at least the triangle's least projection; ending rays, case & 2: at most
// its greatest). An element is beyond a plane when it lies farther than `margin` (scaled by |n| or
// |m|) on the far side. A sliver (|n| small against |e1| |e2|, where the normal's direction is
// uncertain) has no planes: valid = false, the whole list.
template <typename S>
struct HeadPlanesOf {
  Vec3<S> n{S(0.0f)}, v0{S(0.0f)};
  bool valid = false, behind = false, ends = false;
  S reach{0.0f}, margin{0.0f};
  std::uint32_t facets = 0;
  glm::vec3 m[4];
  S bound[4] = {S(0.0f), S(0.0f), S(0.0f), S(0.0f)}, len[4] = {S(0.0f), S(0.0f), S(0.0f), S(0.0f)};
};

template <typename S>
HeadPlanesOf<S> MakePlanesOf(Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, std::uint32_t c, std::uint32_t count, std::uint32_t k,
                             std::uint32_t mode, S margin) {
  HeadPlanesOf<S> p;
  const Vec3<S> e1 = v1 - v0, e2 = v2 - v0;
  p.n = Cross(e1, e2);
  p.valid = !SliverOf(e1, e2, p.n);
  p.v0 = v0;
  p.behind = (c & 1u) != 0;
  p.ends = (c & 2u) != 0;
  p.reach = margin * Length(p.n);
  p.margin = margin;
  p.facets = mode == layout::kTlHeadsRegular ? Facets(count, k, p.m) : 0u;
  for (std::uint32_t j = 0; j < p.facets; ++j) {
    const Vec3<S> mj(S(p.m[j].x), S(p.m[j].y), S(p.m[j].z));
    p.bound[j] = FacetBoundOf(mj, v0, v1, v2, p.ends);
    p.len[j] = S(count == 6 ? kSqrt2Up : 1.0f);
  }
  return p;
}

// Beyond the triangle's plane: the side the rays reach is h >= 0 (h the signed, scaled distance),
// up to the margin; beyond a facet: below the bound (starting rays) or above it (ending rays).
template <typename S>
bool SphereRejectedOf(const HeadPlanesOf<S>& p, Vec4<S> s) {
  const Vec3<S> c(s.x, s.y, s.z);
  const S h0 = Dot(p.n, c - p.v0), h = p.behind ? -h0 : h0;
  if (h + s.w * Length(p.n) < -p.reach) return true;
  for (std::uint32_t j = 0; j < p.facets; ++j) {
    const Vec3<S> mj(S(p.m[j].x), S(p.m[j].y), S(p.m[j].z));
    const S x = Dot(mj, c), r = s.w * p.len[j], g = p.margin * p.len[j];
    if (p.ends ? x - r > p.bound[j] + g : x + r < p.bound[j] - g) return true;
  }
  return false;
}

template <typename S>
bool TriangleRejectedOf(const HeadPlanesOf<S>& p, Vec3<S> a, Vec3<S> b, Vec3<S> d) {
  const Vec3<S> v[3] = {a, b, d};
  bool all = true;
  for (const Vec3<S>& x : v) {
    const S h0 = Dot(p.n, x - p.v0), h = p.behind ? -h0 : h0;
    all = all && h < -p.reach;
  }
  if (all) return true;
  for (std::uint32_t j = 0; j < p.facets; ++j) {
    const Vec3<S> mj(S(p.m[j].x), S(p.m[j].y), S(p.m[j].z));
    bool beyond = true;
    for (const Vec3<S>& x : v) {
      const S y = Dot(mj, x), g = p.margin * p.len[j];
      beyond = beyond && (p.ends ? y > p.bound[j] + g : y < p.bound[j] - g);
    }
    if (beyond) return true;
  }
  return false;
}

// A screen cell's four side planes through the eye (tl::MakeCellPlanes).
template <typename S>
struct CellPlanesOf {
  Vec3<S> eye{S(0.0f)};
  Vec3<S> n[4];
  S len[4] = {S(0.0f), S(0.0f), S(0.0f), S(0.0f)}, margin{0.0f};
};

// Corner pixels (x0, y0) to (x1, y1) of the cell, inclusive.
template <typename S>
CellPlanesOf<S> MakeCellPlanesOf(const layout::FrameConstants& fc, std::uint32_t x0, std::uint32_t y0, std::uint32_t x1,
                                 std::uint32_t y1, S margin) {
  const Vec3<S> c[4] = {PixelDirectionOf<S>(fc, x0, y0), PixelDirectionOf<S>(fc, x1, y0), PixelDirectionOf<S>(fc, x1, y1),
                        PixelDirectionOf<S>(fc, x0, y1)};
  const Vec3<S> mid = ((c[0] + c[1]) + c[2]) + c[3];
  CellPlanesOf<S> p;
  p.eye = Vec3<S>(S(fc.eye.x), S(fc.eye.y), S(fc.eye.z));
  p.margin = margin;
  for (std::uint32_t j = 0; j < 4; ++j) {
    Vec3<S> n = Cross(c[j], c[(j + 1) & 3u]);
    if (Dot(n, mid) < S(0.0f)) n = -n;
    p.n[j] = n;
    p.len[j] = Length(n);
  }
  return p;
}

template <typename S>
bool CellSphereRejectedOf(const CellPlanesOf<S>& p, Vec4<S> s) {
  const Vec3<S> v = Vec3<S>(s.x, s.y, s.z) - p.eye;
  for (std::uint32_t j = 0; j < 4; ++j)
    if (Dot(p.n[j], v) + s.w * p.len[j] < -(p.margin * p.len[j])) return true;
  return false;
}

template <typename S>
bool CellTriangleRejectedOf(const CellPlanesOf<S>& p, Vec3<S> a, Vec3<S> b, Vec3<S> c) {
  for (std::uint32_t j = 0; j < 4; ++j) {
    const S g = -(p.margin * p.len[j]);
    if (Dot(p.n[j], a - p.eye) < g && Dot(p.n[j], b - p.eye) < g && Dot(p.n[j], c - p.eye) < g) return true;
  }
  return false;
}

}  // namespace rayspace::emu::tl
