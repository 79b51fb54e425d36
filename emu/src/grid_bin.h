// One triangle's references in one grid, as the host build (grid_build.cpp) and the emulated
// grid.count and grid.emit (grid.cpp) bin it, and as gpu/shaders/grid_build.comp mirrors it: in
// double (the arithmetic is rayspace/emu/grid/bin_math.h's), the cells in the order face, slice, row,
// column. Private to emu/src.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "rayspace/contract.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/grid/bin_math.h"
#include "rayspace/emu/intersect.h"

namespace rayspace::emu::grid::bin {

using Span = SpanOf<Exact>;
using Spans = SpansOfT<Exact>;

// Every face's span of triangle `tr` in grid g.
inline Spans SpansOf(const layout::GridBuildGrid& g, std::span<const float> slices, const layout::Triangle& tr) {
  return SpansOfTriangle<Exact>(g, slices.data(), tr);
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
  const double d = PointTriangleDistanceOf<Exact>(Vertex<Exact>(g.centre), Vertex<Exact>(tr.v0), Vertex<Exact>(tr.v1), Vertex<Exact>(tr.v2));
  float df = static_cast<float>(d);
  if (margins && static_cast<double>(df) > d) df = std::nextafter(df, 0.0f);
  return margins ? df * layout::kGridDistanceSlack : df;
}

}  // namespace rayspace::emu::grid::bin
