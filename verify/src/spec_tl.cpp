// The relaxed device model of tl.trace (docs/numerics.md, "The relaxed device model"). A ray walks its
// list in index order; what rounds is a sphere test, the ray's case on its triangle (which window it
// walks) and each triangle test. The model walks the list the way every conformant device's walk is
// bounded by: it enters every sphere some device may enter, and marks an element surely visited when
// every device visits it. A device's closest hit must then be a permitted hit of a triangle of that
// walk, with no surely visited triangle surely nearer; its counts of spheres and triangles tested lie
// between the surely visited elements and the whole walk.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/walk_math.h"
#include "rayspace/verify/call_codec.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;
using TlV = emu::Vec3<R>;
using emu::tl::Word;

TlV ToSpec(glm::vec3 v) { return TlV(R(v.x), R(v.y), R(v.z)); }
TlV ToSpec(glm::vec4 v) { return ToSpec(emu::Xyz(v)); }

// A sphere test: may some conformant device pass it, does every one? `limit` is the walk's bound on t.
struct TlSphereDecision {
  bool may_pass = false, surely_passes = false;
};

TlSphereDecision TlTestSphere(const layout::Ray& ray, const Word& w, float limit, bool flush) {
  ScopedSpecTrace trace(flush);
  const emu::Vec4<R> s(R(std::bit_cast<float>(w.x)), R(std::bit_cast<float>(w.y)), R(std::bit_cast<float>(w.z)),
                       R(std::bit_cast<float>(w.w)));
  const bool pass = emu::tl::SphereMayHitOf<R>(ToSpec(ray.origin_tmin), ToSpec(ray.direction_tmax), R(ray.origin_tmin.w), R(limit), s);
  const bool flip = trace.trace().ambiguous != 0;
  return {pass || flip, pass && !flip};
}

// A triangle element's final test (one-sided with cull: a hit counts only where det > 0).
Candidate TlTestTriangle(const emu::call::TlTrace& c, const layout::Ray& ray, const Word& w, bool flush) {
  ScopedSpecTrace trace(flush);
  R t{}, det{};
  bool hit = emu::IntersectWatertight(emu::SetupWatertight(ToSpec(ray.origin_tmin), ToSpec(ray.direction_tmax)), ToSpec(c.vertices[w.x]),
                                      ToSpec(c.vertices[w.y]), ToSpec(c.vertices[w.z]), R(ray.origin_tmin.w),
                                      R(ray.direction_tmax.w), t, &det);
  if (hit && c.cull != 0) hit = det > R(0.0f);
  const bool ambiguous = trace.trace().ambiguous != 0;
  return {w.w, hit || ambiguous, hit && !ambiguous, ambiguous ? SpecReal::Unbounded(t.v) : t};
}

// What every conformant device's walk of one ray lies within.
struct TlWalkBounds {
  std::vector<Candidate> candidates;  // definite only where the triangle is surely visited
  std::uint64_t spheres_lo = 0, spheres_hi = 0, triangles_lo = 0, triangles_hi = 0;
};

// Walks elements [i, end) entering every sphere some device may enter: its test at tmax may pass (a
// device's bound on t is its best hit so far, never above tmax, and the test only passes more with a
// larger bound). An element is surely visited when `sure` (the window is certain) and every sphere
// around it surely passes at `sure_limit`, which no device's bound goes below.
void TlWalkRange(const emu::call::TlTrace& c, const layout::Ray& ray, std::uint32_t i, std::uint32_t end, bool sure, float sure_limit,
          bool flush, TlWalkBounds& b) {
  std::vector<std::pair<std::uint32_t, bool>> open;  // entered spheres: where their subtree ends, surely entered
  std::uint32_t unsure = 0;
  while (i < end) {
    for (; !open.empty() && open.back().first <= i; open.pop_back()) unsure -= open.back().second ? 0u : 1u;
    const bool visited = sure && unsure == 0;
    const auto x = static_cast<emu::tl::Escape>(c.escapes[i]);
    const Word& w = c.words[i];
    if (emu::tl::IsTriangle(x)) {
      ++b.triangles_hi;
      b.triangles_lo += visited ? 1u : 0u;
      if (w.w != ray.info.y) {
        Candidate cd = TlTestTriangle(c, ray, w, flush);
        cd.definite = cd.definite && visited;
        b.candidates.push_back(cd);
      }
      if (x == emu::tl::kEscapeLast) return;
      ++i;
      continue;
    }
    ++b.spheres_hi;
    b.spheres_lo += visited ? 1u : 0u;
    const std::uint32_t subtree_end = x == emu::tl::kEscapeNone ? end : i + static_cast<std::uint32_t>(x);
    const TlSphereDecision wide = TlTestSphere(ray, w, ray.direction_tmax.w, flush);
    if (wide.may_pass) {
      // A shadow ray's or a missing ray's limit is tmax itself: the same test, not run again.
      const bool entered = (sure_limit == ray.direction_tmax.w ? wide : TlTestSphere(ray, w, sure_limit, flush)).surely_passes;
      open.emplace_back(subtree_end, entered);
      unsure += entered ? 0u : 1u;
      ++i;
    } else {
      i = subtree_end;
    }
  }
}

// The bounds of one ray's walk. The list is the direction's (an exact decision on the input); the
// window is tl.cells' for the ray's cell, or tl.heads' for the ray's case on its triangle, a rounded
// decision: where it may go another way, every case's window and the whole list are walked, none
// surely.
TlWalkBounds TlBoundWalk(const emu::call::TlTrace& c, const layout::Ray& ray, float sure_limit, bool flush) {
  const auto K = static_cast<std::uint32_t>(c.first.size() - 1);
  const std::uint32_t k = emu::tl::ListFor(K, emu::Xyz(ray.direction_tmax));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> windows = {{c.first[k], c.first[k + 1]}};
  bool sure = true;
  const auto window = [&](std::size_t row) { return std::pair{c.windows[2 * (row * K + k)], c.windows[2 * (row * K + k) + 1]}; };
  if (c.heads == layout::kTlHeadsCells) {
    if (ray.info.w < c.windows.size() / (2 * K)) windows = {window(ray.info.w)};
  } else if (c.heads != layout::kTlHeadsOff && ray.info.y < c.tri_words.size()) {
    const Word& tw = c.tri_words[ray.info.y];
    glm::vec3 m[4];
    const std::uint32_t facets = c.heads == layout::kTlHeadsRegular ? emu::tl::Facets(K, k, m) : 0u;
    ScopedSpecTrace trace(flush);
    const std::uint32_t cs = emu::tl::RayCaseOf<R>(ToSpec(c.vertices[tw.x]), ToSpec(c.vertices[tw.y]), ToSpec(c.vertices[tw.z]),
                                                   ToSpec(ray.origin_tmin), ToSpec(ray.direction_tmax), R(ray.direction_tmax.w),
                                                   c.shadow != 0, m, facets, emu::tl::kNoCase);
    const std::size_t row = std::size_t{ray.info.y} * layout::kTlCases;
    if (trace.trace().ambiguous != 0) {
      sure = false;
      for (std::uint32_t j = 0; j < layout::kTlCases; ++j) windows.push_back(window(row + j));
    } else if (cs != emu::tl::kNoCase) {
      windows = {window(row + cs)};
    }
  }
  TlWalkBounds b;
  for (const auto& [i, end] : windows) {
    TlWalkBounds one;
    TlWalkRange(c, ray, i, end, sure, sure_limit, flush, one);
    b.candidates.insert(b.candidates.end(), one.candidates.begin(), one.candidates.end());
    b.spheres_lo = sure ? one.spheres_lo : 0;
    b.triangles_lo = sure ? one.triangles_lo : 0;
    b.spheres_hi = std::max(b.spheres_hi, one.spheres_hi);
    b.triangles_hi = std::max(b.triangles_hi, one.triangles_hi);
  }
  return b;
}

// One differing ray: is the device's result one some conformant device's walk reaches?
void TlCheckRay(const emu::call::TlTrace& c, std::size_t r, const TracedRay& e, const TracedRay& a, bool flush, SpecTally& t) {
  const layout::Ray& ray = c.rays[r];
  const bool shadow = c.shadow != 0;
  // A shadow walk bounds t by tmax until its first hit ends it; a closest-hit walk by its best hit so far.
  const float sure_limit = shadow || a.result == emu::kMissPacked ? ray.direction_tmax.w : emu::HitT(a.result);
  TlWalkBounds b = TlBoundWalk(c, ray, sure_limit, flush);
  if (shadow && a.result != 0) b.spheres_lo = b.triangles_lo = 0;  // a device's walk may end at any hit it may take
  if (!ResultAllowed(shadow, shadow ? 0 : emu::kMissPacked, a.result, b.candidates, ray)) {
    t.Beyond(fmt::format("{}[{}]: {:#x} is no result of a walk a conformant device may take ({} triangles it may test)",
                         shadow ? "occluded" : "hits", r, a.result, b.candidates.size()));
    return;
  }
  const auto inside = [](std::uint64_t x, std::uint64_t lo, std::uint64_t hi) { return lo <= x && x <= hi; };
  if (!inside(e.first, b.spheres_lo, b.spheres_hi) || !inside(e.second, b.triangles_lo, b.triangles_hi)) {
    t.Beyond(fmt::format("ray {}: the model's bounds miss the emulator's own counts (a model error)", r));
    return;
  }
  if (!inside(a.first, b.spheres_lo, b.spheres_hi) || !inside(a.second, b.triangles_lo, b.triangles_hi)) {
    t.Beyond(fmt::format("ray {}: {} spheres and {} triangles tested, outside the walks' {} to {} and {} to {}", r, a.first,
                         a.second, b.spheres_lo, b.spheres_hi, b.triangles_lo, b.triangles_hi));
    return;
  }
  t.Within();
}

}  // namespace

SpecVerdict ClassifyTlTrace(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush) {
  const DecodedCall<emu::call::TlTrace> d = DecodeCall<emu::call::TlTrace>(in);
  const emu::call::TlTrace& c = d.call;
  SpecTally t;
  const std::vector<TracedRay> e = TracedRays(expected, c.shadow != 0, "spheres", "triangles"), a = TracedRays(actual, c.shadow != 0, "spheres", "triangles");
  if (e.size() != c.rays.size() || a.size() != c.rays.size()) {
    t.Beyond("hits or occluded, spheres, triangles: a word per ray");
    return t.Done();
  }
  for (std::size_t r = 0; r < e.size(); ++r)
    if (e[r].result != a[r].result || e[r].first != a[r].first || e[r].second != a[r].second) TlCheckRay(c, r, e[r], a[r], flush, t);
  return t.Done();
}

}  // namespace rayspace::verify
