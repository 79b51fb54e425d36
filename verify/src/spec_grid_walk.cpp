// The relaxed device model of a ray's walk through a grid in grid.trace: the regular grid
// (StepRegular) and an area light's 3D perspective grid (StepVolume); the arithmetic is
// rayspace/emu/grid/walk_math.h. A device's rounding moves the clips, the entry cell and each
// crossing by a few ULP (each crossing is computed from its boundary, never accumulated), so it may
// step along another axis where two crossings nearly tie, start one cell over where the ray enters
// near a boundary, or stop one crossing earlier or later near the end. The model follows every
// such choice at once: a graph of the cells some device's walk (without hits) reaches, in which a
// cell on every path from an entry to an end is surely visited.
//
// A device that reports no hit walked to the end, so it tested every triangle of every surely
// visited cell: one that surely hits is a contradiction. A device that reports a hit may have
// stopped early; in the regular grid it stops only at a hit nearer than the crossing it stands at,
// so a triangle surely hit inside a surely visited cell that lists it bounds the answer as the
// final tests' rule does (spec_tally.h, ResultAllowed). A 3D grid's walk is only bounded that way
// when it reports no hit (its regions overlap in t, so an earlier region's stop says nothing about
// a later one's triangle).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/grid/walk_math.h"
#include "rayspace/emu/intersect.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;
using WalkV3 = emu::Vec3<R>;

WalkV3 WalkSpec3(glm::vec4 v) { return {R(v.x), R(v.y), R(v.z)}; }

// What every device's hit-free walk of one ray may and must do.
struct WalkBounds {
  bool unbounded = false;
  std::vector<std::uint32_t> may_cells;
  struct Sure {
    std::uint32_t cell;
    float enter_hi = INFINITY, leave_lo = -INFINITY;  // regular grid: the ray surely lies in the cell strictly between
  };
  std::vector<Sure> sure;
  std::uint32_t min_steps = 0, max_steps = 0;
  void Add(const WalkBounds& region, bool surely) {
    unbounded = unbounded || region.unbounded;
    may_cells.insert(may_cells.end(), region.may_cells.begin(), region.may_cells.end());
    max_steps += region.max_steps;
    if (!surely) return;
    sure.insert(sure.end(), region.sure.begin(), region.sure.end());
    min_steps += region.min_steps;
  }
};

// One DDA's cells as a graph: a node per cell some walk reaches, an edge per step some device may
// take, an end where some device may stop. The geometry (a cell's crossings, its index, where the
// walk ends) comes from the caller.
class WalkGraph {
 public:
  struct Node {
    glm::ivec3 at;
    R next[3];
    std::vector<std::size_t> succ;
    bool ends = false;
  };
  using NextFn = std::function<R(glm::ivec3, int)>;
  using CellFn = std::function<std::uint32_t(glm::ivec3)>;
  WalkGraph(NextFn next, CellFn cell, glm::ivec3 size, glm::ivec3 step, R limit)
      : next_(std::move(next)), cell_(std::move(cell)), size_(size), step_(step), limit_(limit) {}

  // Walks from every cell of [first, last] (per axis) to every end; false when the graph is
  // unbounded (a crossing without bound, too many cells).
  bool Run(glm::uvec3 first, glm::uvec3 last) {
    for (std::uint32_t z = first.z; z <= last.z; ++z)
      for (std::uint32_t y = first.y; y <= last.y; ++y)
        for (std::uint32_t x = first.x; x <= last.x; ++x) starts_.push_back(NodeOf(glm::ivec3(x, y, z)));
    for (std::size_t k = 0; k < nodes_.size() && !unbounded_; ++k) Expand(k);
    return !unbounded_;
  }
  const std::vector<Node>& nodes() const { return nodes_; }
  // The reachable cells, those on every path from a start to an end (dominators of the end, in the
  // order of the steps), the shortest and longest walks in cells.
  WalkBounds Summarise(bool must_start, std::vector<std::size_t>* sure_nodes) const {
    WalkBounds w;
    const std::size_t n = nodes_.size();
    std::vector<std::size_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = k;
    const auto key = [&](std::size_t k) { return step_.x * nodes_[k].at.x + step_.y * nodes_[k].at.y + step_.z * nodes_[k].at.z; };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return key(x) < key(y); });
    std::vector<std::vector<bool>> dom(n);
    std::vector<bool> reached(n, false);
    std::vector<std::uint32_t> shortest(n, ~0u), longest(n, 0);
    for (std::size_t s : starts_) {
      reached[s] = true;
      dom[s] = std::vector<bool>(n, false);
      dom[s][s] = true;
      shortest[s] = longest[s] = 1;
    }
    std::vector<bool> end_dom;
    bool any_end = false;
    std::uint32_t min_steps = must_start ? ~0u : 0u, max_steps = 0;
    for (std::size_t k : order) {
      if (!reached[k]) continue;
      if (nodes_[k].ends) {
        end_dom = any_end ? Meet(end_dom, dom[k]) : dom[k];
        any_end = true;
        min_steps = std::min(min_steps, shortest[k]);
        max_steps = std::max(max_steps, longest[k]);
      }
      for (std::size_t s : nodes_[k].succ) {
        std::vector<bool> d = dom[k];
        d[s] = true;
        dom[s] = reached[s] ? Meet(dom[s], d) : d;
        dom[s][s] = true;
        reached[s] = true;
        shortest[s] = std::min(shortest[s], shortest[k] + 1);
        longest[s] = std::max(longest[s], longest[k] + 1);
      }
    }
    w.min_steps = min_steps == ~0u ? 0u : min_steps;
    w.max_steps = max_steps;
    for (std::size_t k = 0; k < n; ++k)
      if (reached[k]) w.may_cells.push_back(cell_(nodes_[k].at));
    if (!must_start || !any_end) return w;  // a walk of no cell is one of the paths
    for (std::size_t k = 0; k < n; ++k)
      if (end_dom[k]) {
        w.sure.push_back({cell_(nodes_[k].at)});
        if (sure_nodes) sure_nodes->push_back(k);
      }
    return w;
  }

 private:
  std::size_t NodeOf(glm::ivec3 at) {
    const auto [it, added] = index_.emplace(cell_(at), nodes_.size());
    if (!added) return it->second;
    Node n;
    n.at = at;
    for (int a = 0; a < 3; ++a) n.next[a] = step_[a] == 0 ? R(INFINITY) : next_(at, a);
    nodes_.push_back(n);
    if (nodes_.size() > 4096) unbounded_ = true;
    return nodes_.size() - 1;
  }
  // Every axis a device's argmin may pick, every end it may take.
  void Expand(std::size_t k) {
    const Node n = nodes_[k];
    float least_hi = INFINITY;
    for (const R& x : n.next) {
      if (x.any) {
        unbounded_ = true;
        return;
      }
      least_hi = std::min(least_hi, x.hi);
    }
    for (int a = 0; a < 3; ++a) {
      const R exit = n.next[a];
      if (!(exit.lo <= least_hi)) continue;
      if (exit.hi > limit_.lo) nodes_[k].ends = true;  // past the walk's end on some device
      if (!(exit.lo <= limit_.hi)) continue;
      glm::ivec3 to = n.at;
      to[a] += step_[a];
      // An axis the ray does not move along (its crossing infinite, an unbounded end) stays in the
      // cell until the walk's guard: taken as an end.
      if (step_[a] == 0 || to[a] < 0 || to[a] >= size_[a]) {
        nodes_[k].ends = true;
        continue;
      }
      const std::size_t next = NodeOf(to);  // before indexing nodes_: it may grow
      nodes_[k].succ.push_back(next);
    }
  }
  static std::vector<bool> Meet(const std::vector<bool>& x, const std::vector<bool>& y) {
    std::vector<bool> m(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) m[k] = x[k] && y[k];
    return m;
  }

  NextFn next_;
  CellFn cell_;
  glm::ivec3 size_, step_;
  R limit_;
  std::vector<Node> nodes_;
  std::map<std::uint32_t, std::size_t> index_;
  std::vector<std::size_t> starts_;
  bool unbounded_ = false;
};

WalkBounds Unbounded() {
  WalkBounds w;
  w.unbounded = true;
  return w;
}

// The truncated, clamped cell of a coordinate's permitted values along an axis of `size` cells.
std::pair<std::uint32_t, std::uint32_t> CellsOf(R x, std::uint32_t size) {
  if (x.any) return {0u, size - 1u};
  const float top = static_cast<float>(size - 1u);
  const auto cell = [top](float v) { return static_cast<std::uint32_t>(std::min(std::max(v, 0.0f), top)); };
  return {cell(x.lo), cell(x.hi)};
}

// The regular grid between tmin and tmax (StepRegular).
WalkBounds RegularBounds(const emu::call::GridTrace& c, const layout::Ray& r, R tmin, R tmax) {
  const WalkV3 lo = WalkSpec3(c.volume[0]), cell = WalkSpec3(c.volume[1]), inv_cell = WalkSpec3(c.volume[2]), hi = WalkSpec3(c.volume[3]);
  const glm::uvec4 dims = c.volume_dims[0];
  const WalkV3 org = WalkSpec3(r.origin_tmin), dir = WalkSpec3(r.direction_tmax);
  const emu::grid::BoxClipOf<R> clip = emu::grid::BoxClip<R>(lo, hi, org, dir, tmin, tmax);
  if (clip.t0.any || clip.t1.any) return Unbounded();
  if (clip.outside || !(clip.t0.lo <= clip.t1.hi)) return {};  // no device's walk starts
  glm::ivec3 step;
  glm::uvec3 first, last;
  for (int a = 0; a < 3; ++a) {
    step[a] = r.direction_tmax[a] > 0.0f ? 1 : (r.direction_tmax[a] < 0.0f ? -1 : 0);
    std::tie(first[a], last[a]) = CellsOf(emu::grid::EntryCoordinateOf<R>(org[a], dir[a], clip.t0, lo[a], inv_cell[a]), dims[a]);
  }
  const auto crossing = [&](int a, int k) { return emu::grid::CrossingOf<R>(lo[a], cell[a], k, org[a], clip.inv[a]); };
  WalkGraph g([&](glm::ivec3 at, int a) { return crossing(a, at[a] + (step[a] > 0 ? 1 : 0)); },
              [&](glm::ivec3 at) {
                return dims.w + (static_cast<std::uint32_t>(at.z) * dims.y + static_cast<std::uint32_t>(at.y)) * dims.x +
                       static_cast<std::uint32_t>(at.x);
              },
              glm::ivec3(dims), step, clip.t1);
  if (!g.Run(first, last)) return Unbounded();
  std::vector<std::size_t> sure_nodes;
  WalkBounds w = g.Summarise(clip.t0.hi <= clip.t1.lo, &sure_nodes);
  // Where the ray surely is inside each surely visited cell: after every crossing into it (and t0),
  // before every crossing out of it (and t1). Crossing intervals are monotone in the boundary, so
  // no earlier crossing's exceeds these.
  for (std::size_t k = 0; k < sure_nodes.size(); ++k) {
    const WalkGraph::Node& n = g.nodes()[sure_nodes[k]];
    float enter = clip.t0.hi, leave = clip.t1.lo;
    for (int a = 0; a < 3; ++a) {
      if (step[a] == 0) continue;
      enter = std::max(enter, crossing(a, n.at[a] + (step[a] > 0 ? 0 : 1)).hi);
      leave = std::min(leave, n.next[a].lo);
    }
    w.sure[k].enter_hi = enter;
    w.sure[k].leave_lo = leave;
  }
  return w;
}

// One face region of a 3D grid, between the permitted t0 and t1 of its range.
WalkBounds FaceBounds(const emu::call::GridTrace& c, std::uint32_t index, std::uint32_t s, WalkV3 oq, WalkV3 dir, R t0, R t1) {
  const glm::uvec4 g = c.light_grids[index];
  const std::uint32_t n = g.y, depth = g.z;
  const R near = R(c.origins[index].w) * R(layout::kGridNearShrink), half_n = R(static_cast<float>(n)) * R(0.5f);
  WalkV3 p0, p1;
  emu::grid::PerspectiveOf<R>(oq + dir * t0, s, half_n, near, p0);
  emu::grid::PerspectiveOf<R>(oq + dir * t1, s, half_n, near, p1);
  const WalkV3 delta = p1 - p0;
  glm::ivec3 step;
  for (int a = 0; a < 3; ++a) {
    if (delta[a].any || (delta[a].lo <= 0.0f && delta[a].hi >= 0.0f && !(delta[a].lo == 0.0f && delta[a].hi == 0.0f)))
      return Unbounded();  // the direction of the walk along an axis is not certain
    step[a] = delta[a].lo > 0.0f ? 1 : (delta[a].hi < 0.0f ? -1 : 0);
  }
  step.z = -step.z;  // away from the light r falls: the far boundary is the next slice's
  const float* bounds = &c.slices[g.w + s * (depth + 1u)];
  glm::uvec3 first, last;
  for (int a = 0; a < 2; ++a) std::tie(first[a], last[a]) = CellsOf(p0[a], n);
  first.z = last.z = 0;
  for (std::uint32_t j = 1; j < depth; ++j) {
    if (p0.z.any || p0.z.lo <= bounds[j]) ++last.z;
    if (!p0.z.any && p0.z.hi <= bounds[j]) ++first.z;
  }
  WalkGraph walk(
      [&](glm::ivec3 at, int a) {
        return a == 2 ? emu::grid::SliceCrossingOf<R>(R(bounds[at.z + (step.z > 0 ? 1 : 0)]), p0.z, delta.z)
                      : emu::grid::ColumnCrossingOf<R>(at[a], step[a], p0[a], delta[a]);
      },
      [&](glm::ivec3 at) {
        return g.x + s * n * n * depth + (static_cast<std::uint32_t>(at.z) * n + static_cast<std::uint32_t>(at.y)) * n +
               static_cast<std::uint32_t>(at.x);
      },
      glm::ivec3(n, n, depth), step, R(1.0f));
  if (!walk.Run(first, last)) return Unbounded();
  return walk.Summarise(true, nullptr);
}

// An area light's 3D grid (StepVolume): without hits, every region whose range is not empty is
// walked once, whatever their order.
WalkBounds VolumeBounds(const emu::call::GridTrace& c, const layout::Ray& r, std::uint32_t index) {
  const glm::vec4 o = c.origins[index];
  const WalkV3 org = WalkSpec3(r.origin_tmin), dir = WalkSpec3(r.direction_tmax), oq = org - WalkSpec3(o);
  R t0(r.origin_tmin.w), t1(r.direction_tmax.w);
  for (int a = 0; a < 3; ++a) {
    emu::grid::ClipLinearOf<R>(org[a] - R(c.volume[0][a]), dir[a], t0, t1);
    emu::grid::ClipLinearOf<R>(R(c.volume[3][a]) - org[a], -dir[a], t0, t1);
  }
  if (t0.any || t1.any) return Unbounded();
  if (!(t0.lo <= t1.hi)) return {};
  const bool must = t0.hi <= t1.lo;
  WalkBounds w;
  for (std::uint32_t s = 0; s <= layout::kGridFaces && !w.unbounded; ++s) {
    R r0 = t0, r1 = t1;
    emu::grid::RegionRangeOf<R>(oq, dir, R(o.w), s, r0, r1);
    if (r0.any || r1.any) return Unbounded();
    if (!(r0.lo <= r1.hi)) continue;
    const bool surely = must && r0.hi <= r1.lo;
    w.Add(s == layout::kGridFaces ? RegularBounds(c, r, r0, r1) : FaceBounds(c, index, s, oq, dir, r0, r1), surely);
  }
  for (WalkBounds::Sure& x : w.sure) x.enter_hi = INFINITY, x.leave_lo = -INFINITY;  // no t bound across regions
  return w.unbounded ? Unbounded() : w;
}

struct WalkCandidates {
  std::vector<Candidate> candidates;
  std::uint32_t sure_tests = 0, may_tests = 0;
};

// Every triangle of a cell some walk visits; definite where it surely hits and a surely visited cell
// lists it, and `found` (the device's hit) where its hit surely lies inside that cell.
WalkCandidates CandidatesOf(const emu::call::GridTrace& c, const layout::Ray& r, const WalkBounds& w, bool found, bool flush) {
  WalkCandidates out;
  std::map<std::uint32_t, std::size_t> at;
  for (std::uint32_t cell : w.may_cells)
    for (std::uint32_t k = c.first[cell]; k < c.first[cell + 1]; ++k) {
      const std::uint32_t t = c.cell_triangles[k];
      if (t == r.info.y) continue;
      ++out.may_tests;
      if (at.count(t)) continue;
      at[t] = out.candidates.size();
      out.candidates.push_back(ModelCandidate(r, c.triangles[t], t, flush));
    }
  std::vector<bool> listed(out.candidates.size(), false);
  for (const WalkBounds::Sure& s : w.sure)
    for (std::uint32_t k = c.first[s.cell]; k < c.first[s.cell + 1]; ++k) {
      const std::uint32_t t = c.cell_triangles[k];
      if (t == r.info.y) continue;
      ++out.sure_tests;
      const Candidate& cand = out.candidates[at.at(t)];
      if (!found || (cand.t.lo > s.enter_hi && cand.t.hi < s.leave_lo)) listed[at.at(t)] = true;
    }
  for (std::size_t k = 0; k < listed.size(); ++k) out.candidates[k].definite = out.candidates[k].definite && listed[k];
  return out;
}

}  // namespace

void CheckWalkingRay(const emu::call::GridTrace& c, std::size_t i, std::uint32_t volume, const TracedRay& a, bool flush, SpecTally& t) {
  const layout::Ray& r = c.rays[i];
  const bool shadow = c.shadow != 0;
  const bool found = shadow ? a.result != 0 : a.result != emu::kMissPacked;
  const char* grid = volume == layout::kGridNoLight ? "the regular grid" : "its 3D grid";
  const layout::Triangle* own = r.info.y < c.triangles.size() ? &c.triangles[r.info.y] : nullptr;
  if (volume != layout::kGridNoLight && shadow && c.closed && own) {
    // --closed-models: a surface facing away from the light is in shadow untraced.
    ScopedSpecTrace trace(flush);
    const bool away = emu::grid::FacesAwayOf(WalkSpec3(own->v0), WalkSpec3(own->v1), WalkSpec3(own->v2), WalkSpec3(r.origin_tmin));
    if ((away || trace.trace().ambiguous) && a.result == 1u && a.first == 0 && a.second == 0) {
      t.Within();
      return;
    }
    if (away && !trace.trace().ambiguous) {
      t.Beyond(fmt::format("ray {}: its surface faces away from the light on every device, so it is in shadow untraced", i));
      return;
    }
  }
  WalkBounds w;
  {
    ScopedSpecTrace trace(flush);
    w = volume == layout::kGridNoLight ? RegularBounds(c, r, R(r.origin_tmin.w), R(r.direction_tmax.w)) : VolumeBounds(c, r, volume);
  }
  if (w.unbounded) {
    t.Within();
    return;
  }
  // A 3D grid's stop at a hit bounds nothing beyond its own region: only a walk to the end does.
  const bool bounded_stop = volume == layout::kGridNoLight || !found;
  WalkCandidates k = CandidatesOf(c, r, w, found, flush);
  if (!bounded_stop)
    for (Candidate& cand : k.candidates) cand.definite = false;
  // Without a hit every device walks to an end; with one it may stop after any cell.
  const std::uint32_t steps_lo = found ? 1u : w.min_steps, tests_lo = found ? 1u : k.sure_tests;
  if (!ResultAllowed(shadow, shadow ? 0 : emu::kMissPacked, a.result, k.candidates, r))
    t.Beyond(fmt::format("{}[{}]: {:#x} is no result of the triangles of the cells its walk through {} may visit ({} of them, {} surely)",
                         shadow ? "occluded" : "hits", i, a.result, grid, w.may_cells.size(), w.sure.size()));
  else if (a.first < steps_lo || a.first > w.max_steps || a.second < tests_lo || a.second > k.may_tests)
    t.Beyond(fmt::format("ray {}: {} steps and {} tests, where its walk through {} takes {} to {} steps and {} to {} tests", i, a.first,
                         a.second, grid, steps_lo, w.max_steps, tests_lo, k.may_tests));
  else
    t.Within();
}

}  // namespace rayspace::verify
