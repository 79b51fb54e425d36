// grid.trace, the emulated kernel (mirrors gpu/shaders/grid_trace.comp operation for operation):
// a point light's shadow ray tests the triangles of its one perspective cell, unless it ends before
// the cell's least distance; every other ray steps through the regular grid (3D DDA).
#include <algorithm>
#include <limits>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

constexpr std::uint32_t kMissWord = 0xFFFFFFFFu;

// The ray and its best answer so far; Test() runs the watertight test on one triangle.
struct Walk {
  const call::GridTrace& c;
  const layout::Ray& r;
  WatertightRay w;
  float tmin, tmax;
  std::uint64_t best = kMissPacked;
  std::uint32_t tests = 0, steps = 0;
  bool Done() const { return c.shadow != 0u && best != kMissPacked; }
  // Tests the triangles of cell `cell` (ascending ids); in a perspective cell (`uv` given) only those
  // whose projection's rectangle holds the ray's (u, v), as a z-buffer tests the pixels of a
  // triangle's box.
  void Cell(std::uint32_t cell, const grid::FaceUv* uv = nullptr) {
    const std::uint32_t b = c.first[cell], e = c.first[cell + 1];
    for (std::uint32_t i = b; i < e && !Done(); ++i) {
      const std::uint32_t t = c.cell_triangles[i];
      if (t == r.info.y) continue;
      if (uv) {
        const glm::vec4 box = c.boxes[i];
        if (!(uv->u >= box.x && uv->v >= box.y && uv->u <= box.z && uv->v <= box.w)) continue;
      }
      ++tests;
      const layout::Triangle& tr = c.triangles[t];
      // The whole range, not the best hit's t: a hit at the same t with a lower id must still win.
      float th;
      if (IntersectWatertight(w, Xyz(tr.v0), Xyz(tr.v1), Xyz(tr.v2), tmin, tmax, th)) {
        const std::uint64_t packed = PackHit(th, t);
        if (packed < best) best = packed;
      }
    }
  }
};

// A point light's shadow ray: its light's grid; an eye ray: the eye's (--primary grid); kMissWord
// when there is none or the ray does not start at the grid's origin. `uv`: the ray's face and (u, v).
std::uint32_t PerspectiveCell(const call::GridTrace& c, const layout::Ray& r, grid::FaceUv& uv) {
  const std::uint32_t index = grid::PerspectiveGridOf(r, c.shadow != 0u, c.light_grids, c.origins, c.eye);
  if (index == layout::kGridNoLight) return kMissWord;
  const glm::uvec4 g = c.light_grids[index];
  const glm::vec3 d = Xyz(r.direction_tmax);
  if (!(Max(Max(Abs(d.x), Abs(d.y)), Abs(d.z)) > 0.0f)) return kMissWord;
  uv = grid::DirectionFace(d);
  return g.x + grid::FaceCell(uv, g.y);
}

// 3D DDA through the regular grid over (tmin, tmax) clipped to its box.
void StepRegular(Walk& k) {
  const call::GridTrace& c = k.c;
  const glm::vec3 lo = Xyz(c.volume[0]), cell = Xyz(c.volume[1]), inv_cell = Xyz(c.volume[2]), hi = Xyz(c.volume[3]);
  const glm::uvec4 dims = c.volume_dims[0];
  const glm::vec3 org = Xyz(k.r.origin_tmin), dir = Xyz(k.r.direction_tmax);
  glm::vec3 inv;
  float t0 = k.tmin, t1 = k.tmax;
  for (int a = 0; a < 3; ++a) {
    inv[a] = 1.0f / dir[a];
    float ta = (lo[a] - org[a]) * inv[a], tb = (hi[a] - org[a]) * inv[a];
    if (inv[a] < 0.0f) std::swap(ta, tb);
    t0 = Max(t0, ta);
    t1 = Min(t1, tb);
  }
  if (!(t0 <= t1)) return;
  glm::ivec3 at, step;
  glm::vec3 next;
  for (int a = 0; a < 3; ++a) {
    const float p = org[a] + dir[a] * t0;
    const float x = (p - lo[a]) * inv_cell[a];
    at[a] = static_cast<int>(static_cast<std::uint32_t>(Min(Max(x, 0.0f), static_cast<float>(dims[a] - 1u))));
    step[a] = dir[a] > 0.0f ? 1 : (dir[a] < 0.0f ? -1 : 0);
    // The t where the ray leaves this cell along axis a (infinite when it does not move along a).
    const float boundary = lo[a] + static_cast<float>(at[a] + (step[a] > 0 ? 1 : 0)) * cell[a];
    next[a] = step[a] == 0 ? INFINITY : (boundary - org[a]) * inv[a];
  }
  for (std::uint32_t guard = 0; guard < dims.x + dims.y + dims.z; ++guard) {
    ++k.steps;
    k.Cell(dims.w + (static_cast<std::uint32_t>(at.z) * dims.y + static_cast<std::uint32_t>(at.y)) * dims.x + static_cast<std::uint32_t>(at.x));
    if (k.Done()) return;
    int a = 0;
    if (next.y < next[a]) a = 1;
    if (next.z < next[a]) a = 2;
    const float exit = next[a];
    // A hit before this cell's exit: no triangle further on is closer (each is binned in every cell
    // its box meets, widened by kGridCellSlack).
    if (k.best != kMissPacked && HitT(k.best) < exit) return;
    // Past the ray's end (or its box's exit): done.
    if (!(exit <= t1)) return;
    at[a] += step[a];
    if (at[a] < 0 || at[a] >= static_cast<int>(dims[a])) return;
    const float boundary = lo[a] + static_cast<float>(at[a] + (step[a] > 0 ? 1 : 0)) * cell[a];
    next[a] = (boundary - org[a]) * inv[a];
  }
}

}  // namespace

GridWalks PassGridTrace(const call::GridTrace& c) {
  const std::size_t n = c.rays.size();
  GridWalks out;
  if (c.shadow) out.occluded.assign(n, 0u);
  else out.hits.assign(n, kMissPacked);
  out.steps.assign(n, 0u);
  out.tests.assign(n, 0u);
  ParallelFor(n, [&](std::size_t i) {
    const layout::Ray& r = c.rays[i];
    Walk k{c, r, SetupWatertight(Xyz(r.origin_tmin), Xyz(r.direction_tmax)), r.origin_tmin.w, r.direction_tmax.w};
    grid::FaceUv uv;
    const std::uint32_t cell = PerspectiveCell(c, r, uv);
    const layout::Triangle* own = r.info.y < c.triangles.size() ? &c.triangles[r.info.y] : nullptr;
    if (cell != kMissWord && c.shadow != 0u && c.closed && own &&
        grid::FacesAway(Xyz(own->v0), Xyz(own->v1), Xyz(own->v2), Xyz(c.origins[r.info.w]))) {
      k.best = 0;  // --closed-models: the surface faces away from its light, in shadow untraced
    } else if (cell != kMissWord) {
      k.steps = 1;
      // The ray ends before the cell's nearest triangle: nothing to test.
      if (k.tmax > c.min_dist[cell]) k.Cell(cell, &uv);
    } else {
      StepRegular(k);
    }
    if (c.shadow) out.occluded[i] = k.best != kMissPacked ? 1u : 0u;
    else out.hits[i] = k.best;
    out.steps[i] = k.steps;
    out.tests[i] = k.tests;
  });
  return out;
}

}  // namespace rayspace::emu
