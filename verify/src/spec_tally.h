// What the relaxed models share (spec_model.cpp, spec_tree.cpp, spec_tl.cpp): the tally of one call's
// differing elements, and the closest-hit rule of the final tests.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/layout.h"
#include "rayspace/verify/spec_model.h"
#include "rayspace/verify/spec_real.h"

namespace rayspace::verify {

class SpecTally {
 public:
  SpecTally() { v_.modelled = true; }
  void Within() { ++v_.within; }
  void Beyond(const std::string& why) {
    if (v_.beyond++ == 0) v_.first_beyond = why;
  }
  SpecVerdict Done() { return v_; }

 private:
  SpecVerdict v_;
};

// A triangle a ray's final test may meet: whether some conformant device's test hits it (possible),
// whether every device's does (definite), and the t a hit may report.
struct Candidate {
  std::uint32_t prim = 0;
  bool possible = false, definite = false;
  SpecReal t{};
};

// A triangle's watertight test against a ray (the final tests' and the grids'), in SpecReal.
Candidate ModelCandidate(const layout::Ray& r, const layout::Triangle& tri, std::uint32_t prim, bool flush);

// Can the 64-bit atomic minimum of the packed hits (t, prim) end at `a`, starting from `h0`, given the
// candidates' permitted hits? Not when a definite candidate's hit is surely nearer, nor when `a` is
// no permitted hit of a possible candidate (or `h0` itself).
bool ClosestAllowed(std::uint64_t h0, std::uint64_t a, const std::vector<Candidate>& cands, const layout::Ray& ray);
// A final test's result: a shadow flag (`shadow`) set only where some candidate may hit (or it was
// set before), clear only where none surely hits; else a closest hit ClosestAllowed permits.
// `before` is the flag or packed hit the call started from.
bool ResultAllowed(bool shadow, std::uint64_t before, std::uint64_t result, const std::vector<Candidate>& cands, const layout::Ray& ray);

// A tracer's words per ray (tl.trace, grid.trace): the packed closest hit or the shadow flag, and the
// two counts it reports.
struct TracedRay {
  std::uint64_t result;
  std::uint32_t first, second;
};
// The rays of a trace call's outputs: `hits` (or `occluded` for shadow rays) and the count buffers
// `first` and `second`; empty when their sizes differ.
std::vector<TracedRay> TracedRays(const BufferSet& s, bool shadow, const char* first, const char* second);

// The models of the object-tree descent's passes (tree.roots, tree.expand, tree.test, tree.step), or
// an unmodelled verdict for another method.
SpecVerdict ClassifyTree(const std::string& method, const BufferSet& in, const BufferSet& expected, const BufferSet& actual,
                         bool flush_denormals);

// tl.lists' model (spec_tl_lists.cpp), the windows' (spec_tl_windows.cpp) and tl.trace's (spec_tl.cpp).
SpecVerdict ClassifyTlLists(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);
SpecVerdict ClassifyTlHeads(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);
SpecVerdict ClassifyTlCells(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);
// The raster's fragment stage where both sides cover a pixel with the same triangle (spec_raster.cpp).
SpecVerdict ClassifyRasterFragments(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);
// Its depth test where the triangle differs away from every edge (spec_raster.cpp).
SpecVerdict ClassifyRasterFlips(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);

// A ray walking a grid in a grid.trace call (spec_grid_walk.cpp): the regular grid, or (`volume`
// not kGridNoLight) that 3D grid; its words `a` judged.
void CheckWalkingRay(const emu::call::GridTrace& c, std::size_t i, std::uint32_t volume, const TracedRay& a, bool flush, SpecTally& t);
// grid.count's model (spec_grid_build.cpp).
SpecVerdict ClassifyGridCount(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);
// grid.trace's model of the perspective cells (spec_grid.cpp).
SpecVerdict ClassifyGridTrace(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);
SpecVerdict ClassifyTlTrace(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush_denormals);

}  // namespace rayspace::verify
