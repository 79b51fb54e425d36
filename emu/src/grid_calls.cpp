// The contract of the grids' build calls' inputs (emu/calls.h, `--algo grid`), checked before a saved
// or hand-made call runs: a call that passes runs on every backend without reading or writing out of
// bounds, and every loop of its kernel stays within lavapipe's budget.
#include <algorithm>
#include <cmath>

#include "grid_bin.h"
#include "rayspace/emu/calls.h"
#include "rayspace/error.h"

namespace rayspace::emu {


namespace {



// Columns, rows and slices of one face (the regular grid's one "face": x, y, z).
std::uint32_t FaceColumns(const layout::GridBuildGrid& g) { return g.shape.y; }
std::uint32_t FaceRows(const layout::GridBuildGrid& g) { return g.shape.x == layout::kGridKindRegular ? g.shape.z : g.shape.y; }
std::uint32_t FaceSlices(const layout::GridBuildGrid& g) {
  return g.shape.x == layout::kGridKindRegular ? g.shape.w : g.shape.x == layout::kGridKindVolume ? g.shape.z : 1u;
}

void CheckGrid(std::string_view call, In<layout::Triangle> triangles, In<glm::vec4> params, In<glm::uvec4> shape, In<float> slices,
               bool binning = true) {
  if (params.size() != 4 || shape.size() != 2) ThrowInput("{}: inputs 'grid'/'shape' hold {} and {} entries, not 4 and 2", call, params.size(), shape.size());
  const layout::GridBuildGrid g = grid::FromDescriptor(params, shape);
  if (g.shape.x > layout::kGridKindVolume) ThrowInput("{}: input 'shape': grid kind {} is none of 0, 1, 2", call, g.shape.x);
  if (g.flags.x > (layout::kGridBuildCull | layout::kGridBuildMargins)) ThrowInput("{}: input 'shape': flags {} unknown", call, g.flags.x);
  if (triangles.size() >= (std::size_t{1} << 31)) ThrowInput("{}: {} triangles", call, triangles.size());
  const bool regular = g.shape.x == layout::kGridKindRegular, volume = g.shape.x == layout::kGridKindVolume;
  // Every loop of the kernel within lavapipe's bounds: a row or column of cells at most 4096 long.
  if (g.shape.y == 0 || g.shape.y > 4096u || (regular && (g.shape.z == 0 || g.shape.z > 4096u || g.shape.w == 0 || g.shape.w > 4096u)))
    ThrowInput("{}: input 'shape': {} x {} x {} cells, not 1 to 4096 a side", call, g.shape.y, g.shape.z, g.shape.w);
  if (volume && (g.shape.z == 0 || g.shape.z > layout::kGridMaxSlices))
    ThrowInput("{}: input 'shape': {} depth slices, not 1 to {}", call, g.shape.z, layout::kGridMaxSlices);
  if (binning && volume && std::uint64_t{g.flags.y} + std::uint64_t{layout::kGridFaces} * (g.shape.z + 1) > slices.size())
    ThrowInput("{}: input 'shape' reads slices past the {} in 'slices'", call, slices.size());
  if (grid::bin::CellCount(g) >= (std::uint64_t{1} << 32)) ThrowInput("{}: input 'shape': {} cells", call, grid::bin::CellCount(g));
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(params[0][k]) || !std::isfinite(params[1][k]) || !std::isfinite(params[2][k]) || !std::isfinite(params[3][k]))
      ThrowInput("{}: input 'grid' holds a value that is not finite", call);
  if (regular && !(g.cell.x > 0.0f && g.cell.y > 0.0f && g.cell.z > 0.0f)) ThrowInput("{}: input 'grid': the regular grid's cells are not > 0", call);
}

}  // namespace

void CheckInputs(const call::GridCount& c) { CheckGrid(c.kName, c.triangles, c.grid, c.shape, c.slices); }

void CheckInputs(const call::GridEmit& c) {
  CheckGrid(c.kName, {}, c.grid, c.shape, {}, false);
  const std::size_t n = c.counts.size();
  const layout::GridBuildGrid g = grid::FromDescriptor(c.grid, c.shape);
  const bool boxes = g.shape.x == layout::kGridKindPerspective;
  if (c.spans.size() != n * layout::kGridFaces || c.span_boxes.size() != (boxes ? n * layout::kGridFaces : 0))
    ThrowInput("{}: inputs 'spans' and 'span_boxes' hold {} and {}, not {} per triangle (boxes in a 2D grid only)", c.kName, c.spans.size(),
               c.span_boxes.size(), layout::kGridFaces);
  std::uint64_t total = 0;
  for (std::size_t t = 0; t < n; ++t) {
    std::uint64_t size = 0;
    for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
      const grid::bin::Span s = grid::bin::Unpack(c.spans[t * layout::kGridFaces + f]);
      if (!s.valid) continue;
      if (s.i0 > s.i1 || s.j0 > s.j1 || s.k0 > s.k1 || std::uint64_t{grid::bin::CellOf(g, f, s.i1, s.j1, s.k1)} >= grid::bin::CellCount(g) ||
          (g.shape.x == layout::kGridKindRegular && f > 0) || s.i1 >= FaceColumns(g) || s.j1 >= FaceRows(g) || s.k1 >= FaceSlices(g))
        ThrowInput("{}: input 'spans' element {} is no range of cells of face {}", c.kName, t * layout::kGridFaces + f, f);
      size += s.Size();
    }
    if (size != c.counts[t]) ThrowInput("{}: input 'counts' element {} is {}, its spans hold {}", c.kName, t, c.counts[t], size);
    total += size;
  }
  if (total >= (std::uint64_t{1} << 31)) ThrowInput("{}: input 'counts' sums to {} references", c.kName, total);
}

void CheckInputs(const call::GridCells& c) {
  const std::size_t refs = c.cells.size();
  // Least distances are minimised as the bits of non-negative floats (atomicMin in the kernel).
  for (std::size_t t = 0; t < c.dist.size(); ++t)
    if (std::isnan(c.dist[t]) || std::signbit(c.dist[t])) ThrowInput("{}: input 'dist' element {} is {}, not a float >= +0", c.kName, t, c.dist[t]);
  if (c.triangles.size() != refs || c.order.size() != refs || (!c.boxes.empty() && c.boxes.size() != refs))
    ThrowInput("{}: inputs 'cells', 'triangles', 'order' and 'boxes' (or none) differ in length", c.kName);
  if (refs >= (std::size_t{1} << 31) || c.cell_count >= (1u << 31)) ThrowInput("{}: {} references in {} cells", c.kName, refs, c.cell_count);
  for (std::size_t i = 0; i < refs; ++i) {
    if (c.order[i] >= refs) ThrowInput("{}: input 'order' element {} is {}, out of range [0, {})", c.kName, i, c.order[i], refs);
    if (c.cells[i] >= c.cell_count) ThrowInput("{}: input 'cells' element {} is {}, out of range [0, {})", c.kName, i, c.cells[i], c.cell_count);
    if (!c.dist.empty() && c.triangles[i] >= c.dist.size())
      ThrowInput("{}: input 'triangles' element {} is {}, with no entry in the {} of 'dist'", c.kName, i, c.triangles[i], c.dist.size());
  }
}

}  // namespace rayspace::emu
