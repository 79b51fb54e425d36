// The relaxed device model of a ray's walk through the regular grid (grid.trace's StepRegular; the
// arithmetic is rayspace/emu/grid/walk_math.h). A device's rounding moves the box clip, the entry
// cell and each crossing by a few ULP (each is computed from its boundary, never accumulated), so it
// may step along another axis where two crossings nearly tie, start one cell over where the ray
// enters near a boundary, or stop one crossing earlier or later near the ray's end. The model
// follows every such choice at once: a graph of the cells some device's walk (without hits) reaches,
// in which a cell on every path from the entry to an end is surely visited. A triangle listed in a
// surely visited cell whose hit surely lies inside that cell is tested by every device that gets
// there, and a device that stops earlier stopped at a nearer hit: it bounds the answer as the
// final tests' rule does (spec_tally.h, ResultAllowed).
#include <algorithm>
#include <cstdint>
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

struct WalkNode {
  glm::ivec3 at;
  R next[3];
  std::vector<std::size_t> succ;
  bool ends = false;  // some device's walk may end after this cell
};

// What every device's hit-free walk of one ray through the regular grid may and must do.
struct RegularWalk {
  bool unbounded = false;
  std::vector<std::uint32_t> may_cells;
  struct Sure {
    std::uint32_t cell;
    float enter_hi, leave_lo;  // the ray surely lies in the cell strictly between these
  };
  std::vector<Sure> sure;
  std::uint32_t min_steps = 0, max_steps = 0;
};

class RegularWalkBuilder {
 public:
  RegularWalkBuilder(const emu::call::GridTrace& c, const layout::Ray& r)
      : lo_(WalkSpec3(c.volume[0])), cell_(WalkSpec3(c.volume[1])), inv_cell_(WalkSpec3(c.volume[2])), hi_(WalkSpec3(c.volume[3])),
        dims_(c.volume_dims[0]), org_(WalkSpec3(r.origin_tmin)), dir_(WalkSpec3(r.direction_tmax)),
        clip_(emu::grid::BoxClip<R>(lo_, hi_, org_, dir_, R(r.origin_tmin.w), R(r.direction_tmax.w))) {
    for (int a = 0; a < 3; ++a) step_[a] = r.direction_tmax[a] > 0.0f ? 1 : (r.direction_tmax[a] < 0.0f ? -1 : 0);
  }

  RegularWalk Build() {
    RegularWalk w;
    if (clip_.t0.any || clip_.t1.any) return Unbounded();
    if (clip_.outside || !(clip_.t0.lo <= clip_.t1.hi)) return w;  // no device's walk starts
    const bool must_start = clip_.t0.hi <= clip_.t1.lo;
    std::uint32_t first[3], last[3];
    for (int a = 0; a < 3; ++a) {
      const R x = emu::grid::EntryCoordinateOf<R>(org_[a], dir_[a], clip_.t0, lo_[a], inv_cell_[a]);
      const float top = static_cast<float>(dims_[a] - 1u);
      const auto cell = [top](float v) { return static_cast<std::uint32_t>(std::min(std::max(v, 0.0f), top)); };
      first[a] = x.any ? 0u : cell(x.lo);
      last[a] = x.any ? dims_[a] - 1u : cell(x.hi);
    }
    for (std::uint32_t z = first[2]; z <= last[2]; ++z)
      for (std::uint32_t y = first[1]; y <= last[1]; ++y)
        for (std::uint32_t x = first[0]; x <= last[0]; ++x) starts_.push_back(NodeOf(glm::ivec3(x, y, z)));
    for (std::size_t k = 0; k < nodes_.size() && !unbounded_; ++k) Expand(k);
    if (unbounded_) return Unbounded();
    Summarise(must_start, w);
    return w;
  }

 private:
  static RegularWalk Unbounded() {
    RegularWalk w;
    w.unbounded = true;
    return w;
  }
  std::uint32_t CellOf(glm::ivec3 at) const {
    return dims_.w + (static_cast<std::uint32_t>(at.z) * dims_.y + static_cast<std::uint32_t>(at.y)) * dims_.x + static_cast<std::uint32_t>(at.x);
  }
  R Crossing(int a, int k) const { return emu::grid::CrossingOf<R>(lo_[a], cell_[a], k, org_[a], clip_.inv[a]); }
  std::size_t NodeOf(glm::ivec3 at) {
    const auto [it, added] = index_.emplace(CellOf(at), nodes_.size());
    if (!added) return it->second;
    WalkNode n;
    n.at = at;
    for (int a = 0; a < 3; ++a) n.next[a] = step_[a] == 0 ? R(INFINITY) : Crossing(a, at[a] + (step_[a] > 0 ? 1 : 0));
    nodes_.push_back(n);
    if (nodes_.size() > 4096) unbounded_ = true;
    return nodes_.size() - 1;
  }
  // Every axis a device's argmin may pick, every end it may take.
  void Expand(std::size_t k) {
    const WalkNode n = nodes_[k];
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
      if (exit.hi > clip_.t1.lo) nodes_[k].ends = true;  // past the ray's end on some device
      if (!(exit.lo <= clip_.t1.hi)) continue;
      glm::ivec3 to = n.at;
      to[a] += step_[a];
      // An axis the ray does not move along (its crossing infinite, an unbounded ray's end) stays in
      // the cell until the walk's guard: taken as an end.
      if (step_[a] == 0 || to[a] < 0 || to[a] >= static_cast<int>(dims_[a])) {
        nodes_[k].ends = true;
        continue;
      }
      const std::size_t s = NodeOf(to);
      nodes_[k].succ.push_back(s);
    }
  }
  // The cells on every path (dominators of the end, in the order the walk's steps give), the
  // shortest and longest walks.
  void Summarise(bool must_start, RegularWalk& w) const {
    const std::size_t n = nodes_.size();
    std::vector<std::size_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = k;
    const auto key = [&](std::size_t k) { return step_[0] * nodes_[k].at.x + step_[1] * nodes_[k].at.y + step_[2] * nodes_[k].at.z; };
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return key(x) < key(y); });
    std::vector<std::vector<bool>> dom(n);
    std::vector<bool> reached(n, false);
    std::vector<std::uint32_t> shortest(n, ~0u), longest(n, 0);
    for (std::size_t s : starts_) reached[s] = true, dom[s] = std::vector<bool>(n, false), dom[s][s] = true, shortest[s] = longest[s] = 1;
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
        if (reached[s]) dom[s][s] = true;
        reached[s] = true;
        shortest[s] = std::min(shortest[s], shortest[k] + 1);
        longest[s] = std::max(longest[s], longest[k] + 1);
      }
    }
    w.min_steps = min_steps == ~0u ? 0u : min_steps;
    w.max_steps = max_steps;
    for (std::size_t k = 0; k < n; ++k)
      if (reached[k]) w.may_cells.push_back(CellOf(nodes_[k].at));
    if (!must_start || !any_end) return;  // a walk of no cell is one of the paths
    for (std::size_t k = 0; k < n; ++k)
      if (end_dom[k]) w.sure.push_back({CellOf(nodes_[k].at), EnterHi(nodes_[k]), LeaveLo(nodes_[k])});
  }
  static std::vector<bool> Meet(const std::vector<bool>& x, const std::vector<bool>& y) {
    std::vector<bool> m(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) m[k] = x[k] && y[k];
    return m;
  }
  float EnterHi(const WalkNode& n) const {
    float t = clip_.t0.hi;
    for (int a = 0; a < 3; ++a)
      if (step_[a] != 0) t = std::max(t, Crossing(a, n.at[a] + (step_[a] > 0 ? 0 : 1)).hi);
    return t;
  }
  float LeaveLo(const WalkNode& n) const {
    float t = clip_.t1.lo;
    for (const R& x : n.next) t = std::min(t, x.lo);
    return t;
  }

  WalkV3 lo_, cell_, inv_cell_, hi_;
  glm::uvec4 dims_;
  WalkV3 org_, dir_;
  emu::grid::BoxClipOf<R> clip_;
  int step_[3]{};
  std::vector<WalkNode> nodes_;
  std::map<std::uint32_t, std::size_t> index_;
  std::vector<std::size_t> starts_;
  bool unbounded_ = false;
};

struct WalkCandidates {
  std::vector<Candidate> candidates;
  std::uint32_t sure_tests = 0, may_tests = 0;
};

// Every triangle of a cell some walk visits; definite where it surely hits inside a surely visited
// cell that lists it.
WalkCandidates CandidatesOf(const emu::call::GridTrace& c, const layout::Ray& r, const RegularWalk& w, bool flush) {
  WalkCandidates out;
  std::map<std::uint32_t, std::size_t> at;
  const emu::WatertightRayOf<R> ray = emu::SetupWatertight(WalkSpec3(r.origin_tmin), WalkSpec3(r.direction_tmax));
  for (std::uint32_t cell : w.may_cells)
    for (std::uint32_t k = c.first[cell]; k < c.first[cell + 1]; ++k) {
      const std::uint32_t t = c.cell_triangles[k];
      if (t == r.info.y) continue;
      ++out.may_tests;
      if (at.count(t)) continue;
      const layout::Triangle& tr = c.triangles[t];
      ScopedSpecTrace trace(flush);
      R th{};
      const bool hit = emu::IntersectWatertight(ray, WalkSpec3(tr.v0), WalkSpec3(tr.v1), WalkSpec3(tr.v2), R(r.origin_tmin.w),
                                                R(r.direction_tmax.w), th);
      const bool ambiguous = trace.trace().ambiguous != 0;
      at[t] = out.candidates.size();
      out.candidates.push_back({t, hit || ambiguous, false, ambiguous ? SpecReal::Unbounded(th.v) : th});
      out.candidates.back().definite = hit && !ambiguous;  // narrowed below to hits inside a sure cell
    }
  std::vector<bool> inside(out.candidates.size(), false);
  for (const RegularWalk::Sure& s : w.sure)
    for (std::uint32_t k = c.first[s.cell]; k < c.first[s.cell + 1]; ++k) {
      const std::uint32_t t = c.cell_triangles[k];
      if (t == r.info.y) continue;
      ++out.sure_tests;
      const Candidate& cand = out.candidates[at.at(t)];
      if (cand.t.lo > s.enter_hi && cand.t.hi < s.leave_lo) inside[at.at(t)] = true;
    }
  for (std::size_t k = 0; k < inside.size(); ++k) out.candidates[k].definite = out.candidates[k].definite && inside[k];
  return out;
}

}  // namespace

void CheckRegularRay(const emu::call::GridTrace& c, std::size_t i, const TracedRay& a, bool flush, SpecTally& t) {
  const layout::Ray& r = c.rays[i];
  const bool shadow = c.shadow != 0;
  RegularWalk w;
  {
    ScopedSpecTrace trace(flush);
    w = RegularWalkBuilder(c, r).Build();
  }
  if (w.unbounded) {
    t.Within();
    return;
  }
  const WalkCandidates k = CandidatesOf(c, r, w, flush);
  const bool found = shadow ? a.result != 0 : a.result != emu::kMissPacked;
  // Without a hit every device walks to an end; with one it may stop after any cell.
  const std::uint32_t steps_lo = found ? 1u : w.min_steps, tests_lo = found ? 1u : k.sure_tests;
  if (!ResultAllowed(shadow, shadow ? 0 : emu::kMissPacked, a.result, k.candidates, r))
    t.Beyond(fmt::format("{}[{}]: {:#x} is no result of the triangles of the cells its walk through the regular grid may visit ({} of "
                         "them, {} surely)",
                         shadow ? "occluded" : "hits", i, a.result, w.may_cells.size(), w.sure.size()));
  else if (a.first < steps_lo || a.first > w.max_steps || a.second < tests_lo || a.second > k.may_tests)
    t.Beyond(fmt::format("ray {}: {} steps and {} tests, where its walk through the regular grid takes {} to {} steps and {} to {} tests", i,
                         a.first, a.second, steps_lo, w.max_steps, tests_lo, k.may_tests));
  else
    t.Within();
}

}  // namespace rayspace::verify
