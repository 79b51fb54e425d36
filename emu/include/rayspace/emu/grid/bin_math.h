// The grids' binning arithmetic (grid.count: a triangle's spans of cells per face, its (u, v)
// rectangle, a 2D grid's least distance), templated over the arithmetic like the other kernel math
// (rayspace/emu/intersect.h). `Exact` is the emulator's and gpu/shaders/grid_build.comp's: IEEE
// double, operation for operation; verify::SpecDouble asks what a device computing doubles at the
// single precision Vulkan promises may give instead (docs/numerics.md, "The relaxed device model").
// A traits type T names the double (T::D), the float (T::F) and what a cell index is (T::Index).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "rayspace/emu/grid/face_math.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/layout.h"

namespace rayspace::emu::grid::bin {

struct Exact {
  using D = double;
  using F = float;
  using Index = std::uint32_t;
};

// The double operations the templates name, for T = Exact (verify::SpecDouble brings its own). They
// hide emu's float overloads here, so no double is narrowed to float by accident.
inline double Sqrt(double x) { return std::sqrt(x); }
inline double Floor(double x) { return std::floor(x); }
inline double Lesser(double x, double b) { return b < x ? b : x; }   // std::min(x, b)
inline double Greater(double x, double b) { return x < b ? b : x; }  // std::max(x, b)
inline double ClampOf(double x, double lo, double hi) { return std::clamp(x, lo, hi); }
inline float ToFloat(double x) { return static_cast<float>(x); }
inline std::uint32_t CellIndex(double x) { return static_cast<std::uint32_t>(x); }
inline double Widen(float x) { return static_cast<double>(x); }
// The depth slice (0..D-1) of r = 1 / depth on a face whose boundaries are `b` (D + 1 of them,
// decreasing): how many inner boundaries lie at or beyond r (grid_trace.comp SliceOf).
inline std::uint32_t SliceOf(double r, const float* b, std::uint32_t depth) {
  std::uint32_t k = 0;
  for (std::uint32_t j = 1; j < depth; ++j) k += r <= static_cast<double>(b[j]) ? 1u : 0u;
  return k;
}

template <class T>
using DVec3 = glm::vec<3, typename T::D, glm::defaultp>;

template <class T>
DVec3<T> Vertex(const glm::vec4& v) {
  using D = typename T::D;
  return {D(double(v.x)), D(double(v.y)), D(double(v.z))};
}
template <class T>
typename T::D LengthOf(DVec3<T> v) {
  return Sqrt(Dot(v, v));
}

// The face's axes: the major one, and the two that become u and v.
struct FaceAxes {
  int major, a, b;
  double sign;
};
inline FaceAxes AxesOf(std::uint32_t face) {
  const int major = static_cast<int>(face / 2);
  return {major, (major + 1) % 3, (major + 2) % 3, face % 2 == 0 ? 1.0 : -1.0};
}

// A convex polygon of at most 8 vertices: a triangle clipped by at most five planes.
template <class T>
struct Poly {
  DVec3<T> p[8];
  int n = 0;
};

// Sutherland-Hodgman: the part of `in` where dot(plane, p) >= 0 (plane through the origin).
template <class T>
Poly<T> ClipHalfSpace(const Poly<T>& in, DVec3<T> plane) {
  using D = typename T::D;
  Poly<T> out;
  for (int i = 0; i < in.n; ++i) {
    const DVec3<T> p = in.p[i], q = in.p[(i + 1) % in.n];
    const D dp = Dot(plane, p), dq = Dot(plane, q);
    const bool p_in = dp >= D(0.0), q_in = dq >= D(0.0);
    if (p_in) out.p[out.n++] = p;
    if (p_in != q_in) out.p[out.n++] = p + (q - p) * (dp / (dp - dq));
  }
  return out;
}

// The cell range [c0, c1] of an extent [lo, hi] in face coordinates (-1..1) over n cells.
template <class T>
void CellRange(typename T::D lo, typename T::D hi, std::uint32_t n, double slack, typename T::Index& c0, typename T::Index& c1) {
  using D = typename T::D;
  const double half = 0.5 * n;
  const D x0 = Floor((lo + D(1.0)) * D(half) - D(slack)), x1 = Floor((hi + D(1.0)) * D(half) + D(slack));
  c0 = CellIndex(ClampOf(x0, 0.0, n - 1.0));
  c1 = CellIndex(ClampOf(x1, 0.0, n - 1.0));
}

// A triangle's references in one face of a grid: the cells [i0, i1] x [j0, j1] x [k0, k1] (columns,
// rows, depth slices; the regular grid has one "face" of x, y, z), and in a 2D grid its (u, v)
// rectangle. What grid.count writes per (triangle, face) and grid.emit expands.
template <class T>
struct SpanOf {
  using Index = typename T::Index;
  Index i0{}, i1{}, j0{}, j1{}, k0{}, k1{};
  bool valid = false;
  glm::vec<4, typename T::F, glm::defaultp> box{typename T::F(0.0f)};
  std::uint64_t Size() const { return valid ? std::uint64_t{i1 - i0 + 1} * (j1 - j0 + 1) * (k1 - k0 + 1) : 0; }
};
template <class T>
using SpansOfT = std::array<SpanOf<T>, layout::kGridFaces>;

// A span as grid.count packs it (two 16-bit bounds a word), and back.
inline SpanOf<Exact> Unpack(glm::uvec4 w) {
  SpanOf<Exact> s;
  s.i0 = w.x & 0xFFFFu, s.i1 = w.x >> 16, s.j0 = w.y & 0xFFFFu, s.j1 = w.y >> 16, s.k0 = w.z & 0xFFFFu, s.k1 = w.z >> 16;
  s.valid = w.w != 0u;
  return s;
}
inline glm::uvec4 Pack(const SpanOf<Exact>& s) {
  if (!s.valid) return glm::uvec4(0u);
  return {s.i0 | s.i1 << 16, s.j0 | s.j1 << 16, s.k0 | s.k1 << 16, 1u};
}

// The cells of face `face` that the triangle (relative to the centre) may be seen through, and its
// (u, v) rectangle; false when it is not seen through the face at all.
template <class T>
bool FaceCellRange(const DVec3<T> tri[3], std::uint32_t face, std::uint32_t n, bool margins, SpanOf<T>& s) {
  using D = typename T::D;
  using F = typename T::F;
  const FaceAxes ax = AxesOf(face);
  const double w = 1.0 + (margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0);
  Poly<T> poly;
  for (int k = 0; k < 3; ++k) poly.p[poly.n++] = tri[k];
  for (int side = 0; side < 4; ++side) {
    DVec3<T> plane(D(0.0));
    plane[ax.major] = D(ax.sign * w);
    plane[side < 2 ? ax.a : ax.b] = D(side % 2 == 0 ? -1.0 : 1.0);  // w m - a >= 0, w m + a >= 0, ...
    poly = ClipHalfSpace(poly, plane);
    if (poly.n == 0) return false;
  }
  D lo[2] = {D(INFINITY), D(INFINITY)}, hi[2] = {D(-INFINITY), D(-INFINITY)};
  for (int i = 0; i < poly.n; ++i) {
    const DVec3<T> p = poly.p[i];
    const D m = D(ax.sign) * p[ax.major];
    if (!(m > D(0.0))) {  // the triangle passes through the centre: every cell of the face
      lo[0] = lo[1] = D(-INFINITY);
      hi[0] = hi[1] = D(INFINITY);
      break;
    }
    const D uv[2] = {p[ax.a] / m, p[ax.b] / m};
    for (int k = 0; k < 2; ++k) lo[k] = Lesser(lo[k], uv[k]), hi[k] = Greater(hi[k], uv[k]);
  }
  const double slack = margins ? static_cast<double>(layout::kGridCellSlack) : 0.0;
  CellRange<T>(lo[0], hi[0], n, slack, s.i0, s.i1);  // u columns
  CellRange<T>(lo[1], hi[1], n, slack, s.j0, s.j1);  // v rows
  // The (u, v) rectangle of the projection, rounded outwards to float and widened by the face's slack
  // (a ray's rounded u, v); a triangle through the centre: the whole face.
  const double uv_slack = margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0, ulp = margins ? 1e-12 : 0.0;
  const auto down = [&](D x) { return ToFloat(Greater(D(-2.0), x - D(uv_slack)) - D(ulp)); };
  const auto up = [&](D x) { return ToFloat(Lesser(D(2.0), x + D(uv_slack)) + D(ulp)); };
  s.box = glm::vec<4, F, glm::defaultp>(down(lo[0]), down(lo[1]), up(hi[0]), up(hi[1]));
  return true;
}

// Whether every point of the box [lo, hi] lies strictly in front of the triangle's plane: the
// triangle is front-facing from every point of a light inside the box (Hunt and Mark's soft-shadow
// culling, valid for closed meshes).
template <class T>
bool FrontFromBox(const layout::Triangle& tr, DVec3<T> lo, DVec3<T> hi) {
  using D = typename T::D;
  const DVec3<T> a = Vertex<T>(tr.v0), nrm = Cross(Vertex<T>(tr.v1) - a, Vertex<T>(tr.v2) - a);
  for (int k = 0; k < 8; ++k) {
    const DVec3<T> p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    if (!(Dot(nrm, p - a) > D(0.0))) return false;
  }
  return true;
}

// A 2D grid about g.centre: per face the rectangle of cells the triangle is seen through.
template <class T>
void PerspectiveSpans(const layout::GridBuildGrid& g, const layout::Triangle& tr, SpansOfT<T>& out) {
  using F = typename T::F;
  const std::uint32_t n = g.shape.y;
  const bool margins = (g.flags.x & layout::kGridBuildMargins) != 0u;
  const auto f3 = [](const glm::vec4& v) { return Vec3<F>(F(v.x), F(v.y), F(v.z)); };
  // Front-face culling: a closed mesh's shadow is cast by the faces turned away from the light.
  if ((g.flags.x & layout::kGridBuildCull) != 0u && !FacesAwayOf(f3(tr.v0), f3(tr.v1), f3(tr.v2), f3(g.centre))) return;
  const DVec3<T> o = Vertex<T>(g.centre);
  const DVec3<T> rel[3] = {Vertex<T>(tr.v0) - o, Vertex<T>(tr.v1) - o, Vertex<T>(tr.v2) - o};
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    SpanOf<T>& s = out[f];
    s.valid = FaceCellRange<T>(rel, f, n, margins, s);
  }
}

// A 3D perspective grid about g.centre (PlanVolume in grid_build.cpp says how it is laid out).
template <class T>
void VolumeSpans(const layout::GridBuildGrid& g, const float* slices, const layout::Triangle& tr, SpansOfT<T>& out) {
  using D = typename T::D;
  const std::uint32_t n = g.shape.y, depth = g.shape.z;
  const bool margins = (g.flags.x & layout::kGridBuildMargins) != 0u;
  if ((g.flags.x & layout::kGridBuildCull) != 0u && FrontFromBox<T>(tr, Vertex<T>(g.light_lo), Vertex<T>(g.light_hi))) return;
  const DVec3<T> o = Vertex<T>(g.centre);
  const double depth_slack = margins ? 1.0 / 1024.0 : 0.0;
  using F = typename T::F;
  const D near = Widen(F(g.centre.w) * F(layout::kGridNearShrink)) * D(1.0 - depth_slack);
  const double slack = margins ? static_cast<double>(layout::kGridCellSlack) : 0.0,
               w = 1.0 + (margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0);
  const DVec3<T> rel[3] = {Vertex<T>(tr.v0) - o, Vertex<T>(tr.v1) - o, Vertex<T>(tr.v2) - o};
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    const FaceAxes ax = AxesOf(f);
    Poly<T> poly;
    for (int k = 0; k < 3; ++k) poly.p[poly.n++] = rel[k];
    DVec3<T> plane(D(0.0));
    plane[ax.major] = D(ax.sign);
    for (int side = 0; side < 5 && poly.n > 0; ++side) {
      if (side == 4) {  // beyond the near plane: sign * p[major] - near >= 0, as a plane through p - near * axis
        for (int i = 0; i < poly.n; ++i) poly.p[i] = poly.p[i] - plane * near;
        poly = ClipHalfSpace(poly, plane);
        for (int i = 0; i < poly.n; ++i) poly.p[i] = poly.p[i] + plane * near;
        continue;
      }
      DVec3<T> s(D(0.0));
      s[ax.major] = D(ax.sign * w);
      s[side < 2 ? ax.a : ax.b] = D(side % 2 == 0 ? -1.0 : 1.0);
      poly = ClipHalfSpace(poly, s);
    }
    if (poly.n == 0) continue;
    D lo[3] = {D(INFINITY), D(INFINITY), D(INFINITY)}, hi[3] = {D(-INFINITY), D(-INFINITY), D(-INFINITY)};
    for (int i = 0; i < poly.n; ++i) {
      const DVec3<T> p = poly.p[i];
      const D m = Greater(D(ax.sign) * p[ax.major], near);
      const D c3[3] = {p[ax.a] / m, p[ax.b] / m, D(1.0) / m};
      for (int k = 0; k < 3; ++k) lo[k] = Lesser(lo[k], c3[k]), hi[k] = Greater(hi[k], c3[k]);
    }
    SpanOf<T>& s = out[f];
    CellRange<T>(lo[0], hi[0], n, slack, s.i0, s.i1);
    CellRange<T>(lo[1], hi[1], n, slack, s.j0, s.j1);
    const float* b = slices + g.flags.y + std::size_t{f} * (depth + 1);
    s.k0 = SliceOf(hi[2] * D(1.0 + depth_slack), b, depth);
    s.k1 = SliceOf(lo[2] * D(1.0 - depth_slack), b, depth);
    s.valid = true;
  }
}

// The regular grid: the cells of the triangle's bounding box, as face 0.
template <class T>
void RegularSpans(const layout::GridBuildGrid& g, const layout::Triangle& tr, SpansOfT<T>& out) {
  using D = typename T::D;
  const glm::uvec3 dims(g.shape.y, g.shape.z, g.shape.w);
  const double slack = (g.flags.x & layout::kGridBuildMargins) != 0u ? static_cast<double>(layout::kGridCellSlack) : 0.0;
  const DVec3<T> a = Vertex<T>(tr.v0), b = Vertex<T>(tr.v1), c = Vertex<T>(tr.v2);
  SpanOf<T>& s = out[0];
  typename T::Index* const c0[3] = {&s.i0, &s.j0, &s.k0};
  typename T::Index* const c1[3] = {&s.i1, &s.j1, &s.k1};
  for (int k = 0; k < 3; ++k) {
    const D tlo = Lesser(a[k], Lesser(b[k], c[k])), thi = Greater(a[k], Greater(b[k], c[k]));
    const D lo = D(double(g.centre[k])), cell = D(double(g.cell[k]));
    const D x0 = Floor((tlo - lo) / cell - D(slack)), x1 = Floor((thi - lo) / cell + D(slack));
    *c0[k] = CellIndex(ClampOf(x0, 0.0, dims[k] - 1.0));
    *c1[k] = CellIndex(ClampOf(x1, 0.0, dims[k] - 1.0));
  }
  s.valid = true;
}

// Every face's span of triangle `tr` in grid g.
template <class T>
SpansOfT<T> SpansOfTriangle(const layout::GridBuildGrid& g, const float* slices, const layout::Triangle& tr) {
  SpansOfT<T> s{};
  if (g.shape.x == layout::kGridKindPerspective)
    PerspectiveSpans<T>(g, tr, s);
  else if (g.shape.x == layout::kGridKindVolume)
    VolumeSpans<T>(g, slices, tr, s);
  else
    RegularSpans<T>(g, tr, s);
  return s;
}

// The least distance from p to the triangle (a, b, c) (Ericson's closest point, its regions in
// turn), in double.
template <class T>
typename T::D PointTriangleDistanceOf(DVec3<T> p, DVec3<T> a, DVec3<T> b, DVec3<T> c) {
  using D = typename T::D;
  const D zero(0.0);
  const DVec3<T> ab = b - a, ac = c - a, ap = p - a;
  const D d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= zero && d2 <= zero) return LengthOf<T>(p - a);
  const DVec3<T> bp = p - b;
  const D d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= zero && d4 <= d3) return LengthOf<T>(p - b);
  const D vc = d1 * d4 - d3 * d2;
  // An edge region is taken only where its edge has a length: a triangle with two equal vertices
  // (0 / 0 there) is a segment, whose closest point a later region finds.
  if (vc <= zero && d1 >= zero && d3 <= zero && d1 - d3 > zero) return LengthOf<T>(p - (a + ab * (d1 / (d1 - d3))));
  const DVec3<T> cp = p - c;
  const D d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= zero && d5 <= d6) return LengthOf<T>(p - c);
  const D vb = d5 * d2 - d1 * d6;
  if (vb <= zero && d2 >= zero && d6 <= zero && d2 - d6 > zero) return LengthOf<T>(p - (a + ac * (d2 / (d2 - d6))));
  const D va = d3 * d6 - d5 * d4;
  if (va <= zero && (d4 - d3) >= zero && (d5 - d6) >= zero && (d4 - d3) + (d5 - d6) > zero)
    return LengthOf<T>(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const D denom = va + vb + vc;
  if (!(denom != zero)) return Lesser(Lesser(LengthOf<T>(p - a), LengthOf<T>(p - b)), LengthOf<T>(p - c));  // degenerate
  const D v = vb / denom, w = vc / denom;
  return LengthOf<T>(p - (a + ab * v + ac * w));
}

}  // namespace rayspace::emu::grid::bin
