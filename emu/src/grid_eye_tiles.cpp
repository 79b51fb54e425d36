// Eye rays through the eye's perspective grid in Hunt and Mark's tiled z-buffer order (their 5.1):
// per cell, per triangle of its list (ascending), the cell's rays whose (u, v) the triangle's
// rectangle holds, tested many rays at a time. To find those rays without scanning the whole cell,
// a cell's rays are sorted into kSub x kSub bins of its (u, v) square; a rectangle visits the bins
// its corners fall in. Each bin index is one monotone float function of u (or v), applied to a
// ray's coordinate and to a rectangle's edges alike, so a rectangle that holds a ray's (u, v) visits
// its bin; the exact rectangle test then decides, as the ray-by-ray scan does. The same tests, counts
// and closest hits as grid.trace's pass (grid_lanes_test.cpp).
#include "grid_eye_tiles.h"

#include <algorithm>
#include <cstring>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/intersect_simd.h"
#include "rayspace/parallel.h"
#include "simd/intersect_lanes.h"
#include "rayspace/settings.h"

namespace rayspace::emu {
namespace {

constexpr std::uint32_t kSub = 16;  // bins per cell side
constexpr std::uint32_t kNone = 0xFFFFFFFFu;

// The bin column (or row) of cell coordinate x (u mapped as FaceCell maps it) in cell `at`.
std::uint32_t BinOf(float x, std::uint32_t at) {
  const float f = (x - static_cast<float>(at)) * static_cast<float>(kSub);
  return !(f > 0.0f) ? 0u : std::min(static_cast<std::uint32_t>(f), kSub - 1u);
}

struct Tiles {
  std::vector<std::uint32_t> order;       // the eye rays, by cell, then bin, then index
  std::vector<std::uint32_t> cell_start;  // per non-empty cell: its first position in order; then the total
  std::vector<std::uint32_t> cells;       // the non-empty cells, ascending
  std::vector<std::uint32_t> bin_start;   // per non-empty cell, per bin, then its end: positions in order
  std::vector<float> u, v;                // per position: the ray's face coordinates
};

// The eye rays with a cell and a hit possible before their end, sorted into cells and bins.
Tiles SortTiles(const call::GridTrace& c, std::uint32_t n, std::uint32_t grid_first, std::vector<std::uint8_t>& tiled) {
  const std::size_t count = c.rays.size();
  std::vector<std::uint32_t> cell_of(count, kNone), bin_of(count, 0);
  std::vector<grid::FaceUv> uv(count);
  const float half = static_cast<float>(n) * 0.5f;
  ParallelFor(count, [&](std::size_t i) {
    const layout::Ray& r = c.rays[i];
    if (grid::PerspectiveGridOf(r, false, c.light_grids, c.origins, c.eye) != c.eye) return;
    const glm::vec3 d = Xyz(r.direction_tmax);
    if (!(Max(Max(Abs(d.x), Abs(d.y)), Abs(d.z)) > 0.0f)) return;
    uv[i] = grid::DirectionFace(d);
    const std::uint32_t local = grid::FaceCell(uv[i], n), cell = grid_first + local;
    tiled[i] = 1;
    if (!(r.direction_tmax.w > c.min_dist[cell])) return;  // ends before the cell's nearest triangle
    cell_of[i] = local;
    const std::uint32_t ci = local % n, cj = (local / n) % n;
    bin_of[i] = BinOf((uv[i].v + 1.0f) * half, cj) * kSub + BinOf((uv[i].u + 1.0f) * half, ci);
  });
  // Counting sort by cell, then by bin within each cell (both stable: ray index order within a bin).
  std::vector<std::uint32_t> per_cell(std::size_t{6} * n * n + 1, 0);
  for (std::size_t i = 0; i < count; ++i)
    if (cell_of[i] != kNone) ++per_cell[cell_of[i]];
  Tiles t;
  std::uint32_t at = 0;
  for (std::size_t k = 0; k + 1 < per_cell.size(); ++k) {
    if (per_cell[k]) t.cells.push_back(static_cast<std::uint32_t>(k)), t.cell_start.push_back(at);
    at += std::exchange(per_cell[k], at);
  }
  t.cell_start.push_back(at);
  std::vector<std::uint32_t> by_cell(at);
  for (std::size_t i = 0; i < count; ++i)
    if (cell_of[i] != kNone) by_cell[per_cell[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  t.order.resize(at);
  t.bin_start.resize(t.cells.size() * (kSub * kSub + 1));
  t.u.resize(at);
  t.v.resize(at);
  ParallelFor(t.cells.size(), [&](std::size_t k) {
    std::uint32_t* start = &t.bin_start[k * (kSub * kSub + 1)];
    std::fill(start, start + kSub * kSub + 1, 0u);
    const std::uint32_t b = t.cell_start[k], e = t.cell_start[k + 1];
    for (std::uint32_t j = b; j < e; ++j) ++start[bin_of[by_cell[j]]];
    std::uint32_t pos = b;
    for (std::uint32_t s = 0; s <= kSub * kSub; ++s) pos += std::exchange(start[s], pos);
    std::vector<std::uint32_t> cursor(start, start + kSub * kSub);
    for (std::uint32_t j = b; j < e; ++j) {
      const std::uint32_t ray = by_cell[j], p = cursor[bin_of[ray]]++;
      t.order[p] = ray;
      t.u[p] = uv[ray].u;
      t.v[p] = uv[ray].v;
    }
  });
  return t;
}

template <int W>
std::uint32_t RaysOf(const intersect_lanes::RayArrays& r, const intersect_lanes::Triangle& tri, std::uint32_t j, float* t) {
  return W == 16 ? intersect_lanes::RaysAvx512(r, tri, j, t) : intersect_lanes::RaysAvx2(r, tri, j, t);
}

// Cell k's triangles against its rays, per triangle the bins its rectangle covers; per position of
// the order, the best hit and the tests.
template <int W>
void TestCell(const call::GridTrace& c, const GridLanes& lanes, const Tiles& t, const intersect_lanes::RayArrays& arrays, std::size_t k,
              std::uint32_t n, std::uint32_t grid_first, std::vector<std::uint64_t>& best, std::vector<std::uint32_t>& tests) {
  const std::uint32_t local = t.cells[k], cell = grid_first + local, ci = local % n, cj = (local / n) % n;
  const std::uint32_t* start = &t.bin_start[k * (kSub * kSub + 1)];
  const float half = static_cast<float>(n) * 0.5f;
  float th[16];
  for (std::uint32_t i = c.first[cell]; i < c.first[cell + 1]; ++i) {
    const std::uint32_t tri = c.cell_triangles[i];
    const glm::vec4 box = c.boxes[i];
    intersect_lanes::Triangle lt;
    std::memcpy(&lt, &lanes.triangles[std::size_t{tri} * 12], sizeof lt);
    const std::uint32_t x0 = BinOf((box.x + 1.0f) * half, ci), x1 = BinOf((box.z + 1.0f) * half, ci);
    const std::uint32_t y0 = BinOf((box.y + 1.0f) * half, cj), y1 = BinOf((box.w + 1.0f) * half, cj);
    for (std::uint32_t by = y0; by <= y1; ++by) {
      const std::uint32_t b = start[by * kSub + x0], e = start[by * kSub + x1 + 1];
      for (std::uint32_t j = b; j < e; j += W) {
        std::uint32_t in = 0;
        for (std::uint32_t l = 0; l < W && j + l < e; ++l) {
          const std::uint32_t p = j + l;
          const bool holds = t.u[p] >= box.x && t.v[p] >= box.y && t.u[p] <= box.z && t.v[p] <= box.w;
          in |= (holds && tri != c.rays[t.order[p]].info.y ? 1u : 0u) << l;
        }
        if (CurrentSettings().grid_lanes_fault && in >> (W - 1)) in &= ~(1u << (W - 1));
        if (!in) continue;
        std::uint32_t hit = RaysOf<W>(arrays, lt, j, th) & in;
        for (std::uint32_t m = in; m; m &= m - 1) ++tests[j + static_cast<std::uint32_t>(__builtin_ctz(m))];
        for (; hit; hit &= hit - 1) {
          const std::uint32_t l = static_cast<std::uint32_t>(__builtin_ctz(hit));
          best[j + l] = std::min(best[j + l], PackHit(th[l], tri));
        }
      }
    }
  }
}

}  // namespace

std::vector<std::uint8_t> TraceEyeTiles(const call::GridTrace& c, const GridLanes& lanes, GridWalks& out) {
  std::vector<std::uint8_t> tiled(c.rays.size(), 0);
  if (c.shadow != 0u || c.eye >= c.light_grids.size() || lanes.isa == cone::Isa::kScalar) return tiled;
  const glm::uvec4 g = c.light_grids[c.eye];
  if (g.x == layout::kGridNoLight || g.z != 0u) return tiled;
  const Tiles t = SortTiles(c, g.y, g.x, tiled);
  const WatertightArrays w = ToWatertightArrays(c.rays, t.order);
  const intersect_lanes::RayArrays arrays{w.ox.data(), w.oy.data(), w.oz.data(), w.dx.data(),   w.dy.data(),   w.dz.data(),   w.sx.data(),
                                          w.sy.data(), w.tmin.data(), w.tmax.data(), w.kx.data(), w.ky.data(), w.kz.data()};
  std::vector<std::uint64_t> best(t.order.size(), kMissPacked);
  std::vector<std::uint32_t> tests(t.order.size(), 0);
  ParallelForDynamic(t.cells.size(), 1, [&](std::size_t k) {
    if (lanes.isa == cone::Isa::kAvx512) TestCell<16>(c, lanes, t, arrays, k, g.y, g.x, best, tests);
    else TestCell<8>(c, lanes, t, arrays, k, g.y, g.x, best, tests);
  });
  // Every tiled ray visits its one cell; those past the sort (ending before the cell's least
  // distance) test nothing.
  for (std::size_t i = 0; i < c.rays.size(); ++i)
    if (tiled[i]) out.steps[i] = 1, out.hits[i] = kMissPacked, out.tests[i] = 0;
  for (std::size_t p = 0; p < t.order.size(); ++p) {
    out.hits[t.order[p]] = best[p];
    out.tests[t.order[p]] = tests[p];
  }
  return tiled;
}

}  // namespace rayspace::emu
