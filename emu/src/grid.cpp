// grid.trace, the emulated kernel (mirrors gpu/shaders/grid_trace.comp operation for operation):
// a point light's shadow ray tests the triangles of its one perspective cell, unless it ends before
// the cell's least distance; every other ray steps through the regular grid (3D DDA).
#include <algorithm>
#include <limits>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/grid/walk_math.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/intersect_simd.h"
#include "rayspace/parallel.h"
#include "rayspace/error.h"
#include "grid_bin.h"
#include "grid_eye_tiles.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/workgroup_ops.h"
#include "simd/intersect_lanes.h"
#include "rayspace/settings.h"

namespace rayspace::emu {
namespace {

constexpr std::uint32_t kMissWord = 0xFFFFFFFFu;


// The ray and its best answer so far; Test() runs the watertight test on one triangle.
struct Walk {
  const call::GridTrace& c;
  const layout::Ray& r;
  WatertightRay w;
  float tmin, tmax;
  const GridLanes* lanes = nullptr;  // PassGridTraceLanes: each cell's triangles W at a time
  std::uint64_t best = kMissPacked;
  std::uint32_t tests = 0, steps = 0;
  std::uint32_t core_steps = 0;  // of `steps`, those in an area light's core cube (statistics only)
  bool Done() const { return c.shadow != 0u && best != kMissPacked; }
  // Whether the ray tests reference i of the cell list (own surface, and in a perspective cell, the
  // reference's (u, v) rectangle).
  bool Tests(std::uint32_t i, std::uint32_t t, const grid::FaceUv* uv) const {
    if (t == r.info.y) return false;
    if (!uv) return true;
    const glm::vec4 box = c.boxes[i];
    return uv->u >= box.x && uv->v >= box.y && uv->u <= box.z && uv->v <= box.w;
  }
  // Tests the triangles of cell `cell` (ascending ids); in a perspective cell (`uv` given) only those
  // whose projection's rectangle holds the ray's (u, v), as a z-buffer tests the pixels of a
  // triangle's box.
  void Cell(std::uint32_t cell, const grid::FaceUv* uv = nullptr) {
    if (lanes && lanes->isa != cone::Isa::kScalar) return CellLanes(cell, uv);
    const std::uint32_t b = c.first[cell], e = c.first[cell + 1];
    for (std::uint32_t i = b; i < e && !Done(); ++i) {
      const std::uint32_t t = c.cell_triangles[i];
      if (!Tests(i, t, uv)) continue;
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

  // Cell() W triangles at a time: the tested references gathered in list order into the lanes; the
  // hits recorded as the scalar scan records them (a shadow ray stops at its first).
  void CellLanes(std::uint32_t cell, const grid::FaceUv* uv) {
    const bool wide = lanes->isa == cone::Isa::kAvx512;
    const std::uint32_t W = wide ? 16u : 8u;
    const intersect_lanes::OneRay one{{w.org.x, w.org.y, w.org.z}, {w.dir.x, w.dir.y, w.dir.z}, w.sx, w.sy, tmin, tmax, w.kx, w.ky, w.kz};
    intersect_lanes::TriangleLanes group{};
    std::uint32_t ids[16];
    float t[16];
    const std::uint32_t e = c.first[cell + 1];
    for (std::uint32_t i = c.first[cell]; i < e && !Done();) {
      std::uint32_t m = 0;
      for (; i < e && m < W; ++i) {
        const std::uint32_t tri = c.cell_triangles[i];
        if (!Tests(i, tri, uv)) continue;
        const float* src = &lanes->triangles[std::size_t{tri} * 12];
        for (int f = 0; f < 12; ++f) group.v[f][m] = src[f];
        ids[m++] = tri;
      }
      if (CurrentSettings().grid_lanes_fault && m == W) --m;
      std::uint32_t bits = (wide ? intersect_lanes::TrianglesAvx512(one, group, t) : intersect_lanes::TrianglesAvx2(one, group, t)) &
                           ((1u << m) - 1u);
      if (c.shadow != 0u && bits) {
        const std::uint32_t k = static_cast<std::uint32_t>(__builtin_ctz(bits));
        tests += k + 1;
        best = PackHit(t[k], ids[k]);
        return;
      }
      tests += m;
      for (; bits; bits &= bits - 1) {
        const std::uint32_t k = static_cast<std::uint32_t>(__builtin_ctz(bits));
        best = std::min(best, PackHit(t[k], ids[k]));
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

// 3D DDA through the regular grid over (tmin, tmax) clipped to its box (the arithmetic is
// grid/walk_math.h's).
void StepRegular(Walk& k, float tmin, float tmax) {
  const call::GridTrace& c = k.c;
  const glm::vec3 lo = Xyz(c.volume[0]), cell = Xyz(c.volume[1]), inv_cell = Xyz(c.volume[2]), hi = Xyz(c.volume[3]);
  const glm::uvec4 dims = c.volume_dims[0];
  const glm::vec3 org = Xyz(k.r.origin_tmin), dir = Xyz(k.r.direction_tmax);
  const grid::BoxClipOf<float> clip = grid::BoxClip(lo, hi, org, dir, tmin, tmax);
  const glm::vec3 inv = clip.inv;
  const float t0 = clip.t0, t1 = clip.t1;
  if (clip.outside || !(t0 <= t1)) return;
  glm::ivec3 at, step;
  glm::vec3 next;
  for (int a = 0; a < 3; ++a) {
    const float x = grid::EntryCoordinateOf(org[a], dir[a], t0, lo[a], inv_cell[a]);
    at[a] = static_cast<int>(static_cast<std::uint32_t>(Min(Max(x, 0.0f), static_cast<float>(dims[a] - 1u))));
    step[a] = dir[a] > 0.0f ? 1 : (dir[a] < 0.0f ? -1 : 0);
    // The t where the ray leaves this cell along axis a (infinite when it does not move along a).
    next[a] = step[a] == 0 ? INFINITY : grid::CrossingOf(lo[a], cell[a], at[a] + (step[a] > 0 ? 1 : 0), org[a], inv[a]);
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
    next[a] = grid::CrossingOf(lo[a], cell[a], at[a] + (step[a] > 0 ? 1 : 0), org[a], inv[a]);
  }
}

// The core cube's part of an area light's shadow ray: the regular grid's cells, counted apart too.
void StepCore(Walk& k, float t0, float t1) {
  const std::uint32_t before = k.steps;
  StepRegular(k, t0, t1);
  k.core_steps += k.steps - before;
}

// An area light's shadow ray through its 3D perspective grid: the part in the core through the
// regular grid, the part in each face's frustum through the face's cells, in order of entry, each each a 3D DDA along the straight line the ray is in perspective
// space (Hunt and Mark 5.3). Returns early on a hit (shadow) or once the best hit lies before where
// the walk is (closest).
void StepVolume(Walk& k, std::uint32_t index) {
  const call::GridTrace& c = k.c;
  const glm::uvec4 g = c.light_grids[index];
  const glm::vec4 o = c.origins[index];
  const std::uint32_t n = g.y, depth = g.z;
  const float zn = o.w, near = zn * layout::kGridNearShrink, half_n = static_cast<float>(n) * 0.5f;
  const glm::vec3 org = Xyz(k.r.origin_tmin), dir = Xyz(k.r.direction_tmax);
  const glm::vec3 oq = org - Xyz(o);
  // The ray within the regular grid's box (every triangle lies inside it).
  float T0 = k.tmin, T1 = k.tmax;
  for (int a = 0; a < 3; ++a) {
    grid::ClipLinearOf(org[a] - c.volume[0][a], dir[a], T0, T1);
    grid::ClipLinearOf(c.volume[3][a] - org[a], -dir[a], T0, T1);
  }
  if (!(T0 <= T1)) return;
  constexpr std::uint32_t kRegions = layout::kGridFaces + 1u;
  float r0[kRegions], r1[kRegions];
  for (std::uint32_t s = 0; s < kRegions; ++s) {
    r0[s] = T0;
    r1[s] = T1;
    grid::RegionRangeOf(oq, dir, zn, s, r0[s], r1[s]);
  }
  std::uint32_t done = 0u;  // regions walked, one bit each
  const std::uint32_t cells_per_face = n * n * depth;
  for (std::uint32_t round = 0; round < kRegions; ++round) {
    // The next region in order of entry (ties: the lower region), skipping empty ones.
    std::uint32_t s = kRegions;
    for (std::uint32_t x = 0; x < kRegions; ++x)
      if (!(done & (1u << x)) && r0[x] <= r1[x] && (s == kRegions || r0[x] < r0[s])) s = x;
    if (s == kRegions) return;
    done |= 1u << s;
    const float t0 = r0[s], t1 = r1[s];
    if (k.best != kMissPacked && HitT(k.best) < t0) return;
    if (s == layout::kGridFaces) {  // the core: the regular grid's cells
      StepCore(k, t0, t1);
      if (k.Done()) return;
      continue;
    }
    const float* bounds = &c.slices[g.w + s * (depth + 1u)];
    glm::vec3 p0, p1;
    const float ma = grid::PerspectiveOf(oq + dir * t0, s, half_n, near, p0);
    const float mb = grid::PerspectiveOf(oq + dir * t1, s, half_n, near, p1);
    const glm::vec3 delta = p1 - p0;
    glm::ivec3 at;
    glm::ivec3 step;
    glm::vec3 next;
    for (int a = 0; a < 2; ++a) {
      at[a] = static_cast<int>(Min(static_cast<std::uint32_t>(Max(p0[a], 0.0f)), n - 1u));
      step[a] = delta[a] > 0.0f ? 1 : (delta[a] < 0.0f ? -1 : 0);
      next[a] = step[a] == 0 ? INFINITY : grid::ColumnCrossingOf(at[a], step[a], p0[a], delta[a]);
    }
    std::uint32_t slice = 0;
    for (std::uint32_t j = 1; j < depth; ++j) slice += p0.z <= bounds[j] ? 1u : 0u;
    at.z = static_cast<int>(slice);
    // Away from the light, r falls: the far boundary is slice + 1's.
    step.z = delta.z < 0.0f ? 1 : (delta.z > 0.0f ? -1 : 0);
    next.z = step.z == 0 ? INFINITY : grid::SliceCrossingOf(bounds[at.z + (step.z > 0 ? 1 : 0)], p0.z, delta.z);
    for (std::uint32_t guard = 0; guard < 2u * n + depth; ++guard) {
      ++k.steps;
      k.Cell(g.x + s * cells_per_face + (static_cast<std::uint32_t>(at.z) * n + static_cast<std::uint32_t>(at.y)) * n +
             static_cast<std::uint32_t>(at.x));
      if (k.Done()) return;
      int a = 0;
      if (next.y < next[a]) a = 1;
      if (next.z < next[a]) a = 2;
      const float exit = next[a];
      if (!(exit <= 1.0f)) break;
      // The exit's t (perspective-correct: the fraction of the way in perspective space is not t's).
      if (k.best != kMissPacked) {
        const float te = t0 + (t1 - t0) * ((exit * ma) / ((1.0f - exit) * mb + exit * ma));
        if (HitT(k.best) < te) return;
      }
      at[a] += step[a];
      if (at[a] < 0 || at[a] >= static_cast<int>(a == 2 ? depth : n)) break;
      next[a] = a == 2 ? grid::SliceCrossingOf(bounds[at.z + (step.z > 0 ? 1 : 0)], p0.z, delta.z)
                       : grid::ColumnCrossingOf(at[a], step[a], p0[a], delta[a]);
    }
  }
}

}  // namespace

namespace {

GridWalks Trace(const call::GridTrace& c, const GridLanes* lanes) {
  const std::size_t n = c.rays.size();
  GridWalks out;
  if (c.shadow) out.occluded.assign(n, 0u);
  else out.hits.assign(n, kMissPacked);
  out.steps.assign(n, 0u);
  out.tests.assign(n, 0u);
  out.core_steps.assign(n, 0u);
  // The render path takes eye rays per cell and triangle (Hunt and Mark's tiled order).
  const std::vector<std::uint8_t> tiled = lanes ? TraceEyeTiles(c, *lanes, out) : std::vector<std::uint8_t>(n, 0);
  ParallelFor(n, [&](std::size_t i) {
    if (tiled[i]) return;
    const layout::Ray& r = c.rays[i];
    Walk k{c, r, SetupWatertight(Xyz(r.origin_tmin), Xyz(r.direction_tmax)), r.origin_tmin.w, r.direction_tmax.w, lanes};
    grid::FaceUv uv;
    const std::uint32_t cell = PerspectiveCell(c, r, uv);
    const std::uint32_t volume = grid::VolumeGridOf(r, c.shadow != 0u, c.light_grids, c.secondary);
    const layout::Triangle* own = r.info.y < c.triangles.size() ? &c.triangles[r.info.y] : nullptr;
    // --closed-models: a surface facing away from the light (an area light's sample: the ray's
    // origin) is in shadow untraced.
    const bool culled = (cell != kMissWord || volume != layout::kGridNoLight) && c.shadow != 0u && c.closed && own;
    if (culled && grid::FacesAway(Xyz(own->v0), Xyz(own->v1), Xyz(own->v2), Xyz(volume != layout::kGridNoLight ? r.origin_tmin : c.origins[r.info.w]))) {
      k.best = 0;
    } else if (volume != layout::kGridNoLight) {
      StepVolume(k, volume);
    } else if (cell != kMissWord) {
      k.steps = 1;
      // The ray ends before the cell's nearest triangle: nothing to test.
      if (k.tmax > c.min_dist[cell]) k.Cell(cell, &uv);
    } else {
      StepRegular(k, k.tmin, k.tmax);
    }
    if (c.shadow) out.occluded[i] = k.best != kMissPacked ? 1u : 0u;
    else out.hits[i] = k.best;
    out.steps[i] = k.steps;
    out.tests[i] = k.tests;
    out.core_steps[i] = k.core_steps;
  });
  return out;
}

}  // namespace

GridWalks PassGridTrace(const call::GridTrace& c) { return Trace(c, nullptr); }

GridLanes PrepareGridLanes(std::span<const layout::Triangle> triangles, cone::Isa isa) {
  GridLanes l;
  l.isa = cone::Runs(isa) ? isa : cone::BestIsa();
  if (l.isa == cone::Isa::kScalar) return l;
  l.triangles.resize(triangles.size() * 12);
  // The final tests' own set-up (vertices, then PlaneNormalOf), 12 floats a triangle.
  static_assert(sizeof(LanesTriangle) == 12 * sizeof(float));
  ParallelFor(triangles.size(), [&](std::size_t i) {
    const LanesTriangle t = PrepareLanesTriangle(triangles[i]);
    std::copy(t.v, t.v + 12, l.triangles.begin() + static_cast<std::ptrdiff_t>(i * 12));
  });
  return l;
}

GridWalks PassGridTraceLanes(const call::GridTrace& c, const GridLanes& lanes) {
  RS_CHECK_MSG(lanes.isa == cone::Isa::kScalar || lanes.triangles.size() == c.triangles.size() * 12,
               "grid.trace lanes set up for {} triangles, called with {}", lanes.triangles.size() / 12, c.triangles.size());
  return Trace(c, &lanes);
}


// ---- the grids' build as passes (gpu/shaders/grid_build.comp): grid.count, grid.emit and grid.cells
// around the sort pass, one grid a call; the host build (grid_build.cpp) bins with the same
// functions (grid_bin.h), so both give the same lists (tests/grid_build_test.cpp).

namespace grid {
GridDescriptor Describe(const layout::GridBuildGrid& g) { return {{g.centre, g.cell, g.light_lo, g.light_hi}, {g.shape, g.flags}}; }

layout::GridBuildGrid FromDescriptor(std::span<const glm::vec4> params, std::span<const glm::uvec4> shape) {
  RS_CHECK(params.size() == 4 && shape.size() == 2);
  layout::GridBuildGrid g{};
  g.centre = params[0], g.cell = params[1], g.light_lo = params[2], g.light_hi = params[3];
  g.shape = shape[0], g.flags = shape[1];
  return g;
}
}  // namespace grid

namespace {

// The first sorted reference whose cell is not below `cell` (grid_build.comp LowerBound).
std::uint32_t LowerBound(const std::vector<std::uint32_t>& sorted, std::uint32_t cell) {
  return static_cast<std::uint32_t>(std::lower_bound(sorted.begin(), sorted.end(), cell) - sorted.begin());
}

}  // namespace

GridCounts PassGridCount(const call::GridCount& c) {
  const layout::GridBuildGrid g = grid::FromDescriptor(c.grid, c.shape);
  const std::size_t n = c.triangles.size();
  const bool perspective = g.shape.x == layout::kGridKindPerspective;
  GridCounts out;
  out.counts.assign(n, 0);
  out.spans.assign(n * layout::kGridFaces, glm::uvec4(0u));
  if (perspective) out.dist.assign(n, 0.0f), out.span_boxes.assign(n * layout::kGridFaces, glm::vec4(0.0f));
  // One invocation per triangle.
  ParallelFor(n, [&](std::size_t t) {
    const grid::bin::Spans spans = grid::bin::SpansOf(g, c.slices, c.triangles[t]);
    std::uint64_t count = 0;
    for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
      out.spans[t * layout::kGridFaces + f] = grid::bin::Pack(spans[f]);
      if (perspective) out.span_boxes[t * layout::kGridFaces + f] = spans[f].valid ? spans[f].box : glm::vec4(0.0f);
      count += spans[f].Size();
    }
    out.counts[t] = static_cast<std::uint32_t>(count);
    if (perspective) out.dist[t] = grid::bin::LeastDistance(g, c.triangles[t]);
  });
  return out;
}

GridRefs PassGridEmit(const call::GridEmit& c) {
  const layout::GridBuildGrid g = grid::FromDescriptor(c.grid, c.shape);
  GridRefs out;
  std::uint32_t total = 0;
  // The kernel's reduce-then-scan over blocks of triangles, then one invocation per reference.
  out.offsets = ExclusiveScan(c.counts, &total, KernelSite::Of(call::GridEmit::kName));
  const bool boxes = g.shape.x == layout::kGridKindPerspective;
  out.cells.assign(total, 0);
  out.triangles.assign(total, 0);
  if (boxes) out.boxes.assign(total, glm::vec4(0.0f));
  ParallelFor(total, [&](std::size_t r) {
    // Its triangle: the last whose offset is not past r (a load-balancing search, grid_build.comp).
    const std::size_t t = static_cast<std::size_t>(std::upper_bound(out.offsets.begin(), out.offsets.end(), r) - out.offsets.begin()) - 1;
    std::uint64_t q = r - out.offsets[t];
    for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
      const grid::bin::Span s = grid::bin::Unpack(c.spans[t * layout::kGridFaces + f]);
      if (q >= s.Size()) {
        q -= s.Size();
        continue;
      }
      const std::uint64_t w = s.i1 - s.i0 + 1, h = s.j1 - s.j0 + 1;
      const auto i = static_cast<std::uint32_t>(s.i0 + q % w), j = static_cast<std::uint32_t>(s.j0 + q / w % h),
                 k = static_cast<std::uint32_t>(s.k0 + q / (w * h));
      out.cells[r] = grid::bin::CellOf(g, f, i, j, k);
      out.triangles[r] = static_cast<std::uint32_t>(t);
      if (boxes) out.boxes[r] = c.span_boxes[t * layout::kGridFaces + f];
      return;
    }
  });
  return out;
}

GridLists PassGridCells(const call::GridCells& c) {
  const std::size_t refs = c.cells.size();
  GridLists out;
  // Gather: one invocation per sorted reference.
  std::vector<std::uint32_t> sorted(refs);
  out.triangles.resize(refs);
  if (!c.boxes.empty()) out.boxes.resize(refs);
  ParallelFor(refs, [&](std::size_t i) {
    const std::uint32_t r = c.order[i];
    sorted[i] = c.cells[r];
    out.triangles[i] = c.triangles[r];
    if (!c.boxes.empty()) out.boxes[i] = c.boxes[r];
  });
  // Cells: one invocation per cell, its offset a lower bound in the sorted cells; the last one the total.
  out.first.resize(std::size_t{c.cell_count} + 1);
  ParallelFor(std::size_t{c.cell_count} + 1, [&](std::size_t cell) { out.first[cell] = LowerBound(sorted, static_cast<std::uint32_t>(cell)); });
  if (c.dist.empty()) return out;
  // Min: per cell the least distance of its references (the kernel's atomicMin on the bits of
  // non-negative floats, which order as the floats do; the minimum does not depend on the order).
  out.min_dist.assign(c.cell_count, INFINITY);
  for (std::size_t i = 0; i < refs; ++i) {
    float& m = out.min_dist[sorted[i]];
    const float d = c.dist[out.triangles[i]];
    m = d < m ? d : m;
  }
  return out;
}

}  // namespace rayspace::emu
