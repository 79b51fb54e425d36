// The relaxed device model of grid.trace's perspective cells (docs/numerics.md, "The relaxed device
// model"): a point light's shadow ray, or an eye ray, tests the triangles of the one cell its direction
// falls in, those whose (u, v) rectangle holds its (u, v). What rounds is the direction's (u, v) (two
// quotients: which cell, which rectangles) and each triangle test. A device's answer is within the
// spec when some cell its (u, v) may fall in and some permitted tests give it; a triangle every
// device tests (its cell certain, its rectangle surely holding (u, v)) and surely hits bounds it.
// The rays that walk a grid (the regular grid, an area light's 3D grid) are judged by
// spec_grid_walk.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/grid/face_math.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/verify/call_codec.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;
using GridV3 = emu::Vec3<R>;

GridV3 GridSpec3(glm::vec4 v) { return {R(v.x), R(v.y), R(v.z)}; }

// The cells along one side that a coordinate's permitted values fall in (FaceCell: truncated,
// clamped to [0, n - 1]).
std::pair<std::uint32_t, std::uint32_t> CellSpan(R c, std::uint32_t n) {
  const R x = emu::grid::FaceCoordinateOf(c, n);
  if (x.any) return {0u, n - 1u};
  const auto cell = [n](float f) { return std::min(static_cast<std::uint32_t>(std::max(f, 0.0f)), n - 1u); };
  return {cell(x.lo), cell(x.hi)};
}

struct Bounds {
  std::vector<Candidate> candidates;
  std::uint32_t tests_lo = 0, tests_hi = 0;
};

// A perspective ray's bounds: every cell its (u, v) may fall in, every reference of it whose
// rectangle may hold (u, v).
Bounds PerspectiveBounds(const emu::call::GridTrace& c, const layout::Ray& r, std::uint32_t index, bool flush) {
  Bounds b;
  const glm::uvec4 g = c.light_grids[index];
  const emu::grid::FaceUvOf<R> uv = emu::grid::DirectionFaceOf<R>(emu::Xyz(r.direction_tmax));
  const auto [i0, i1] = CellSpan(uv.u, g.y);
  const auto [j0, j1] = CellSpan(uv.v, g.y);
  const bool one_cell = i0 == i1 && j0 == j1;
  b.tests_lo = ~0u;
  for (std::uint32_t j = j0; j <= j1; ++j)
    for (std::uint32_t i = i0; i <= i1; ++i) {
      const std::uint32_t cell = g.x + (uv.face * g.y + j) * g.y + i;
      std::uint32_t sure = 0, may = 0;
      if (r.direction_tmax.w > c.min_dist[cell])
        for (std::uint32_t k = c.first[cell]; k < c.first[cell + 1]; ++k) {
          const std::uint32_t t = c.cell_triangles[k];
          if (t == r.info.y) continue;
          const glm::vec4 box = c.boxes[k];
          ScopedSpecTrace trace(flush);
          const bool inside = uv.u >= R(box.x) && uv.v >= R(box.y) && uv.u <= R(box.z) && uv.v <= R(box.w);
          const bool flip = trace.trace().ambiguous != 0;
          if (!inside && !flip) continue;
          ++may;
          sure += inside && !flip ? 1u : 0u;
          Candidate cand = ModelCandidate(r, c.triangles[t], t, flush);
          cand.definite = cand.definite && inside && !flip && one_cell;
          b.candidates.push_back(cand);
        }
      b.tests_lo = std::min(b.tests_lo, one_cell ? sure : 0u);
      b.tests_hi = std::max(b.tests_hi, may);
    }
  return b;
}

// One differing ray of a perspective cell.
void CheckPerspectiveRay(const emu::call::GridTrace& c, std::size_t i, std::uint32_t index, const TracedRay& a, bool flush, SpecTally& t) {
  const layout::Ray& r = c.rays[i];
  const bool shadow = c.shadow != 0;
  bool may_cull = false, may_walk = true;
  const layout::Triangle* own = r.info.y < c.triangles.size() ? &c.triangles[r.info.y] : nullptr;
  if (shadow && c.closed && own) {
    ScopedSpecTrace trace(flush);
    const bool away = emu::grid::FacesAwayOf(GridSpec3(own->v0), GridSpec3(own->v1), GridSpec3(own->v2), GridSpec3(c.origins[r.info.w]));
    const bool flip = trace.trace().ambiguous != 0;
    may_cull = away || flip;
    may_walk = !away || flip;
  }
  // Culled untraced: in shadow, no step, no test.
  if (may_cull && a.result == (shadow ? 1u : 0u) && a.first == 0 && a.second == 0) {
    t.Within();
    return;
  }
  if (!may_walk) {
    t.Beyond(fmt::format("ray {}: its surface faces away from the light on every device, so it is in shadow untraced", i));
    return;
  }
  Bounds b = PerspectiveBounds(c, r, index, flush);
  if (shadow && a.result != 0) b.tests_lo = 0;  // the walk ends at any hit it may take
  if (!ResultAllowed(shadow, shadow ? 0 : emu::kMissPacked, a.result, b.candidates, r))
    t.Beyond(fmt::format("{}[{}]: {:#x} is no result of the triangles of a cell its (u, v) may fall in ({} it may test)",
                         shadow ? "occluded" : "hits", i, a.result, b.candidates.size()));
  else if (a.first != 1 || a.second < b.tests_lo || a.second > b.tests_hi)
    t.Beyond(fmt::format("ray {}: {} steps and {} tests, where a perspective cell is one step of {} to {} tests", i, a.first, a.second,
                         b.tests_lo, b.tests_hi));
  else
    t.Within();
}

}  // namespace

SpecVerdict ClassifyGridTrace(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush) {
  const DecodedCall<emu::call::GridTrace> d = DecodeCall<emu::call::GridTrace>(in);
  const emu::call::GridTrace& c = d.call;
  const bool shadow = c.shadow != 0;
  const std::vector<TracedRay> e = TracedRays(expected, shadow, "steps", "tests"), a = TracedRays(actual, shadow, "steps", "tests");
  SpecTally t;
  if (e.size() != c.rays.size() || a.size() != c.rays.size()) {
    t.Beyond("hits or occluded, steps, tests: a word per ray");
    return t.Done();
  }
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (e[i].result == a[i].result && e[i].first == a[i].first && e[i].second == a[i].second) continue;
    const layout::Ray& r = c.rays[i];
    const std::uint32_t volume = emu::grid::VolumeGridOf(r, shadow, c.light_grids, c.secondary);
    const std::uint32_t index = emu::grid::PerspectiveGridOf(r, shadow, c.light_grids, c.origins, c.eye);
    const glm::vec3 dir = emu::Xyz(r.direction_tmax);
    const bool walks = volume != layout::kGridNoLight || index == layout::kGridNoLight ||
                       !(std::max({std::fabs(dir.x), std::fabs(dir.y), std::fabs(dir.z)}) > 0.0f);
    if (walks)
      CheckWalkingRay(c, i, volume, a[i], flush, t);
    else
      CheckPerspectiveRay(c, i, index, a[i], flush, t);
  }
  return t.Done();
}

}  // namespace rayspace::verify
