// One triangle's references in one grid, as the host build (grid_build.cpp) and the emulated
// grid.count and grid.emit (grid_build_passes.cpp) bin it, and as gpu/shaders/grid_build.comp mirrors
// it: in double, the cells in the order face, slice, row, column. Private to emu/src.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "rayspace/contract.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/intersect.h"

namespace rayspace::emu::grid::bin {

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
struct Poly {
  glm::dvec3 p[8];
  int n = 0;
};

// Sutherland-Hodgman: the part of `in` where dot(plane, p) >= 0 (plane through the origin).
inline Poly ClipHalfSpace(const Poly& in, glm::dvec3 plane) {
  Poly out;
  for (int i = 0; i < in.n; ++i) {
    const glm::dvec3 p = in.p[i], q = in.p[(i + 1) % in.n];
    const double dp = glm::dot(plane, p), dq = glm::dot(plane, q);
    if (dp >= 0) out.p[out.n++] = p;
    if ((dp >= 0) != (dq >= 0)) out.p[out.n++] = p + (q - p) * (dp / (dp - dq));
  }
  return out;
}

inline glm::dvec3 Vertex(const glm::vec4& v) { return {v.x, v.y, v.z}; }

// The cell range [lo, hi] of an extent [a, b] in face coordinates (-1..1) over n cells.
inline void CellRange(double lo, double hi, std::uint32_t n, double slack, std::uint32_t& c0, std::uint32_t& c1) {
  const double half = 0.5 * n;
  const double x0 = std::floor((lo + 1.0) * half - slack), x1 = std::floor((hi + 1.0) * half + slack);
  c0 = static_cast<std::uint32_t>(std::clamp(x0, 0.0, n - 1.0));
  c1 = static_cast<std::uint32_t>(std::clamp(x1, 0.0, n - 1.0));
}

// The cells [i0, i1] x [j0, j1] of face `face` that the triangle (relative to the centre) may be seen
// through, and its (u, v) rectangle; false when it is not seen through the face at all.
inline bool FaceCellRange(const glm::dvec3 tri[3], std::uint32_t face, std::uint32_t n, bool margins, glm::uvec4& range, glm::vec4& box) {
  const FaceAxes ax = AxesOf(face);
  const double w = 1.0 + (margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0);
  Poly poly;
  for (int k = 0; k < 3; ++k) poly.p[poly.n++] = tri[k];
  for (int side = 0; side < 4; ++side) {
    glm::dvec3 plane(0.0);
    plane[ax.major] = ax.sign * w;
    plane[side < 2 ? ax.a : ax.b] = side % 2 == 0 ? -1.0 : 1.0;  // w m - a >= 0, w m + a >= 0, ...
    poly = ClipHalfSpace(poly, plane);
    if (poly.n == 0) return false;
  }
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int i = 0; i < poly.n; ++i) {
    const glm::dvec3 p = poly.p[i];
    const double m = ax.sign * p[ax.major];
    if (!(m > 0.0)) {  // the triangle passes through the centre: every cell of the face
      lo[0] = lo[1] = -INFINITY;
      hi[0] = hi[1] = INFINITY;
      break;
    }
    const double uv[2] = {p[ax.a] / m, p[ax.b] / m};
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], uv[k]), hi[k] = std::max(hi[k], uv[k]);
  }
  const double slack = margins ? static_cast<double>(layout::kGridCellSlack) : 0.0;
  CellRange(lo[0], hi[0], n, slack, range.x, range.y);  // u columns
  CellRange(lo[1], hi[1], n, slack, range.z, range.w);  // v rows
  // The (u, v) rectangle of the projection, rounded outwards to float and widened by the face's slack
  // (a ray's rounded u, v); a triangle through the centre: the whole face.
  const double uv_slack = margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0, ulp = margins ? 1e-12 : 0.0;
  const auto down = [&](double x) { return static_cast<float>(std::max(-2.0, x - uv_slack) - ulp); };
  const auto up = [&](double x) { return static_cast<float>(std::min(2.0, x + uv_slack) + ulp); };
  box = glm::vec4(down(lo[0]), down(lo[1]), up(hi[0]), up(hi[1]));
  return true;
}

// Whether every point of the box [lo, hi] lies strictly in front of the triangle's plane: the
// triangle is front-facing from every point of a light inside the box (Hunt and Mark's soft-shadow
// culling, valid for closed meshes).
inline bool FrontFromBox(const layout::Triangle& tr, glm::dvec3 lo, glm::dvec3 hi) {
  const glm::dvec3 a = Vertex(tr.v0), nrm = glm::cross(Vertex(tr.v1) - a, Vertex(tr.v2) - a);
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    if (!(glm::dot(nrm, p - a) > 0.0)) return false;
  }
  return true;
}

// The depth slice (0..D-1) of r = 1 / depth on a face whose boundaries are `b` (D + 1 of them,
// decreasing): how many inner boundaries lie at or beyond r (grid_trace.comp SliceOf).
inline std::uint32_t SliceOf(double r, const float* b, std::uint32_t depth) {
  std::uint32_t k = 0;
  for (std::uint32_t j = 1; j < depth; ++j) k += r <= static_cast<double>(b[j]) ? 1u : 0u;
  return k;
}

// A triangle's references in one face of a grid: the cells [i0, i1] x [j0, j1] x [k0, k1] (columns,
// rows, depth slices; the regular grid has one "face" of x, y, z), and in a 2D grid its (u, v)
// rectangle. What grid.count writes per (triangle, face) and grid.emit expands.
struct Span {
  std::uint32_t i0 = 0, i1 = 0, j0 = 0, j1 = 0, k0 = 0, k1 = 0;
  bool valid = false;
  glm::vec4 box{0.0f};
  std::uint64_t Size() const { return valid ? std::uint64_t{i1 - i0 + 1} * (j1 - j0 + 1) * (k1 - k0 + 1) : 0; }
};
using Spans = std::array<Span, layout::kGridFaces>;

inline Span Unpack(glm::uvec4 w) {
  Span s;
  s.i0 = w.x & 0xFFFFu, s.i1 = w.x >> 16, s.j0 = w.y & 0xFFFFu, s.j1 = w.y >> 16, s.k0 = w.z & 0xFFFFu, s.k1 = w.z >> 16;
  s.valid = w.w != 0u;
  return s;
}

// A span as grid.count packs it (two 16-bit bounds a word).
inline glm::uvec4 Pack(const Span& s) {
  if (!s.valid) return glm::uvec4(0u);
  return {s.i0 | s.i1 << 16, s.j0 | s.j1 << 16, s.k0 | s.k1 << 16, 1u};
}

// A 2D grid about g.centre: per face the rectangle of cells the triangle is seen through.
inline void PerspectiveSpans(const layout::GridBuildGrid& g, const layout::Triangle& tr, Spans& out) {
  const std::uint32_t n = g.shape.y;
  const bool margins = (g.flags.x & layout::kGridBuildMargins) != 0u;
  // Front-face culling: a closed mesh's shadow is cast by the faces turned away from the light.
  if ((g.flags.x & layout::kGridBuildCull) != 0u && !FacesAway(Xyz(tr.v0), Xyz(tr.v1), Xyz(tr.v2), Xyz(g.centre))) return;
  const glm::dvec3 o = Vertex(g.centre);
  const glm::dvec3 rel[3] = {Vertex(tr.v0) - o, Vertex(tr.v1) - o, Vertex(tr.v2) - o};
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    glm::uvec4 r;
    Span& s = out[f];
    if (!FaceCellRange(rel, f, n, margins, r, s.box)) continue;
    s.i0 = r.x, s.i1 = r.y, s.j0 = r.z, s.j1 = r.w, s.valid = true;
  }
}

// A 3D perspective grid about g.centre (PlanVolume in grid_build.cpp says how it is laid out).
inline void VolumeSpans(const layout::GridBuildGrid& g, std::span<const float> slices, const layout::Triangle& tr, Spans& out) {
  const std::uint32_t n = g.shape.y, depth = g.shape.z;
  const bool margins = (g.flags.x & layout::kGridBuildMargins) != 0u;
  if ((g.flags.x & layout::kGridBuildCull) != 0u && FrontFromBox(tr, Vertex(g.light_lo), Vertex(g.light_hi))) return;
  const glm::dvec3 o = Vertex(g.centre);
  const double depth_slack = margins ? 1.0 / 1024.0 : 0.0;
  const double near = static_cast<double>(g.centre.w * layout::kGridNearShrink) * (1.0 - depth_slack);
  const double slack = margins ? static_cast<double>(layout::kGridCellSlack) : 0.0,
               w = 1.0 + (margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0);
  const glm::dvec3 rel[3] = {Vertex(tr.v0) - o, Vertex(tr.v1) - o, Vertex(tr.v2) - o};
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    const FaceAxes ax = AxesOf(f);
    Poly poly;
    for (int k = 0; k < 3; ++k) poly.p[poly.n++] = rel[k];
    glm::dvec3 plane(0.0);
    plane[ax.major] = ax.sign;
    for (int side = 0; side < 5 && poly.n > 0; ++side) {
      if (side == 4) {  // beyond the near plane: sign * p[major] - near >= 0, as a plane through p - near * axis
        for (int i = 0; i < poly.n; ++i) poly.p[i] -= plane * near;
        poly = ClipHalfSpace(poly, plane);
        for (int i = 0; i < poly.n; ++i) poly.p[i] += plane * near;
        continue;
      }
      glm::dvec3 s(0.0);
      s[ax.major] = ax.sign * w;
      s[side < 2 ? ax.a : ax.b] = side % 2 == 0 ? -1.0 : 1.0;
      poly = ClipHalfSpace(poly, s);
    }
    if (poly.n == 0) continue;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < poly.n; ++i) {
      const glm::dvec3 p = poly.p[i];
      const double m = std::max(ax.sign * p[ax.major], near);
      const double c3[3] = {p[ax.a] / m, p[ax.b] / m, 1.0 / m};
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c3[k]), hi[k] = std::max(hi[k], c3[k]);
    }
    Span& s = out[f];
    CellRange(lo[0], hi[0], n, slack, s.i0, s.i1);
    CellRange(lo[1], hi[1], n, slack, s.j0, s.j1);
    const float* b = slices.data() + g.flags.y + std::size_t{f} * (depth + 1);
    s.k0 = SliceOf(hi[2] * (1.0 + depth_slack), b, depth);
    s.k1 = SliceOf(lo[2] * (1.0 - depth_slack), b, depth);
    s.valid = true;
  }
}

// The regular grid: the cells of the triangle's bounding box, as face 0.
inline void RegularSpans(const layout::GridBuildGrid& g, const layout::Triangle& tr, Spans& out) {
  const glm::uvec3 dims(g.shape.y, g.shape.z, g.shape.w);
  const double slack = (g.flags.x & layout::kGridBuildMargins) != 0u ? static_cast<double>(layout::kGridCellSlack) : 0.0;
  const glm::dvec3 a = Vertex(tr.v0), b = Vertex(tr.v1), c = Vertex(tr.v2);
  const glm::dvec3 tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
  std::uint32_t c0[3], c1[3];
  for (int k = 0; k < 3; ++k) {
    const double x0 = std::floor((tlo[k] - double(g.centre[k])) / double(g.cell[k]) - slack);
    const double x1 = std::floor((thi[k] - double(g.centre[k])) / double(g.cell[k]) + slack);
    c0[k] = static_cast<std::uint32_t>(std::clamp(x0, 0.0, dims[k] - 1.0));
    c1[k] = static_cast<std::uint32_t>(std::clamp(x1, 0.0, dims[k] - 1.0));
  }
  Span& s = out[0];
  s.i0 = c0[0], s.i1 = c1[0], s.j0 = c0[1], s.j1 = c1[1], s.k0 = c0[2], s.k1 = c1[2], s.valid = true;
}

// Every face's span of triangle `tr` in grid g.
inline Spans SpansOf(const layout::GridBuildGrid& g, std::span<const float> slices, const layout::Triangle& tr) {
  Spans s{};
  if (g.shape.x == layout::kGridKindPerspective)
    PerspectiveSpans(g, tr, s);
  else if (g.shape.x == layout::kGridKindVolume)
    VolumeSpans(g, slices, tr, s);
  else
    RegularSpans(g, tr, s);
  return s;
}

// The cells a grid has.
inline std::uint64_t CellCount(const layout::GridBuildGrid& g) {
  const std::uint64_t n = g.shape.y;
  if (g.shape.x == layout::kGridKindPerspective) return layout::kGridFaces * n * n;
  if (g.shape.x == layout::kGridKindVolume) return layout::kGridFaces * n * n * g.shape.z;
  return n * g.shape.z * g.shape.w;
}

// The cell (within the grid) of column i, row j, slice k of face f.
inline std::uint32_t CellOf(const layout::GridBuildGrid& g, std::uint32_t f, std::uint32_t i, std::uint32_t j, std::uint32_t k) {
  const std::uint32_t n = g.shape.y;
  if (g.shape.x == layout::kGridKindRegular) return (k * g.shape.z + j) * n + i;
  return ((f * (g.shape.x == layout::kGridKindVolume ? g.shape.z : 1u) + k) * n + j) * n + i;
}

// Every reference of triangle `tr` in grid g, faces, slices, rows, columns in order: sink(cell within
// the grid, (u, v) rectangle).
template <typename Sink>
void BinTriangle(const layout::GridBuildGrid& g, std::span<const float> slices, const layout::Triangle& tr, Sink&& sink) {
  const Spans spans = SpansOf(g, slices, tr);
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    const Span& s = spans[f];
    if (!s.valid) continue;
    for (std::uint32_t k = s.k0; k <= s.k1; ++k)
      for (std::uint32_t j = s.j0; j <= s.j1; ++j)
        for (std::uint32_t i = s.i0; i <= s.i1; ++i) sink(CellOf(g, f, i, j, k), s.box);
  }
}

// A 2D grid's least distance from its centre to the triangle: rounded down to float, then by the
// slack, so that no hit of a ray of a cell listing the triangle is closer (docs/grids.md).
inline float LeastDistance(const layout::GridBuildGrid& g, const layout::Triangle& tr) {
  const bool margins = (g.flags.x & layout::kGridBuildMargins) != 0u;
  const double d = PointTriangleDistance(Vertex(g.centre), Vertex(tr.v0), Vertex(tr.v1), Vertex(tr.v2));
  float df = static_cast<float>(d);
  if (margins && static_cast<double>(df) > d) df = std::nextafter(df, 0.0f);
  return margins ? df * layout::kGridDistanceSlack : df;
}

}  // namespace rayspace::emu::grid::bin
