// The relaxed device model of grid.count (docs/numerics.md, "The relaxed device model"): per triangle
// and face the span of cells, the (u, v) rectangle and a 2D grid's least distance, computed in
// double, which Vulkan lets a device compute at single precision. The binning runs on SpecDouble
// (rayspace/emu/grid/bin_math.h): each cell bound may be any index between the floors of its
// permitted values, each rectangle corner and the distance any float a permitted value converts to;
// the count is the sum of the device's own spans. A triangle whose clipping, culling or distance
// region a permitted rounding could decide the other way is unbounded. grid.emit and grid.cells
// compute only integers from these words: a difference there is a bug on any device.
#include <cstdint>
#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/grid/bin_math.h"
#include "rayspace/emu/grid/grid.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_double.h"
#include "spec_tally.h"

namespace rayspace::verify {

struct SpecBin {
  using D = SpecDouble;
  using F = SpecReal;
  using Index = IndexRange;
};

namespace {

namespace bin = emu::grid::bin;

// LeastDistance's float: with margins the greatest float at or below the device's double (a
// conversion either way, then a step toward zero where it rounded up), times the slack; without,
// the conversion.
SpecReal LeastDistanceSpec(const layout::GridBuildGrid& g, const layout::Triangle& tr) {
  const bool margins = (g.flags.x & layout::kGridBuildMargins) != 0u;
  const SpecDouble d = bin::PointTriangleDistanceOf<SpecBin>(bin::Vertex<SpecBin>(g.centre), bin::Vertex<SpecBin>(tr.v0),
                                                             bin::Vertex<SpecBin>(tr.v1), bin::Vertex<SpecBin>(tr.v2));
  if (!margins) return ToFloat(d);
  if (d.any) return SpecReal::Unbounded(0.0f);
  const auto below = [](double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) f = std::nextafter(f, -INFINITY);
    return f;
  };
  return SpecReal::Between(below(d.v), below(d.lo), below(d.hi)) * SpecReal(layout::kGridDistanceSlack);
}

std::string SpanText(glm::uvec4 w) {
  const bin::SpanOf<bin::Exact> s = bin::Unpack(w);
  if (!s.valid) return "none";
  return fmt::format("[{}, {}] x [{}, {}] x [{}, {}]", s.i0, s.i1, s.j0, s.j1, s.k0, s.k1);
}

std::string RangeText(const bin::SpanOf<SpecBin>& m) {
  if (!m.valid) return "none";
  const auto r = [](IndexRange x) { return x.lo == x.hi ? fmt::format("{}", x.lo) : fmt::format("{}..{}", x.lo, x.hi); };
  return fmt::format("[{}, {}] x [{}, {}] x [{}, {}]", r(m.i0), r(m.i1), r(m.j0), r(m.j1), r(m.k0), r(m.k1));
}

struct CountWords {
  std::vector<std::uint32_t> counts;
  std::vector<glm::uvec4> spans;
  std::vector<glm::vec4> boxes;
  std::vector<float> dist;
  explicit CountWords(const BufferSet& s)
      : counts(s.Get<std::uint32_t>("counts")), spans(s.Get<glm::uvec4>("spans")), boxes(s.Get<glm::vec4>("span_boxes")),
        dist(s.Get<float>("dist")) {}
  bool Same(const CountWords& o, std::size_t t, bool perspective) const {
    if (counts[t] != o.counts[t] || (perspective && FloatBits(dist[t]) != FloatBits(o.dist[t]))) return false;
    for (std::size_t f = t * layout::kGridFaces; f < (t + 1) * layout::kGridFaces; ++f) {
      if (spans[f] != o.spans[f]) return false;
      if (perspective && glm::any(glm::notEqual(glm::floatBitsToUint(boxes[f]), glm::floatBitsToUint(o.boxes[f])))) return false;
    }
    return true;
  }
  static std::uint32_t FloatBits(float x) { return glm::floatBitsToUint(x); }
};

// One face of triangle t: the device's span and rectangle against the model's.
bool FaceWithin(const bin::SpanOf<SpecBin>& m, glm::uvec4 word, const glm::vec4* box, std::uint64_t& count) {
  const bin::SpanOf<bin::Exact> a = bin::Unpack(word);
  if (a.valid != m.valid) return false;
  if (!a.valid) return word == glm::uvec4(0u) && (!box || *box == glm::vec4(0.0f));
  if (!m.i0.Holds(a.i0) || !m.i1.Holds(a.i1) || !m.j0.Holds(a.j0) || !m.j1.Holds(a.j1) || !m.k0.Holds(a.k0) || !m.k1.Holds(a.k1))
    return false;
  if (a.i0 > a.i1 || a.j0 > a.j1 || a.k0 > a.k1) return false;
  if (box)
    for (int k = 0; k < 4; ++k)
      if (!m.box[k].Allows((*box)[k])) return false;
  count += a.Size();
  return true;
}

void CheckTriangle(const emu::call::GridCount& c, const layout::GridBuildGrid& g, const CountWords& a, std::size_t t, bool flush,
                   SpecTally& tally) {
  const bool perspective = g.shape.x == layout::kGridKindPerspective;
  const layout::Triangle& tr = c.triangles[t];
  ScopedSpecTrace trace(flush);
  const bin::SpansOfT<SpecBin> spans = bin::SpansOfTriangle<SpecBin>(g, c.slices.data(), tr);
  const SpecReal dist = perspective ? LeastDistanceSpec(g, tr) : SpecReal(0.0f);
  if (trace.trace().ambiguous != 0) {  // a decision may go the other way: the words are unbounded
    tally.Within();
    return;
  }
  std::uint64_t count = 0;
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    const std::size_t w = t * layout::kGridFaces + f;
    if (!FaceWithin(spans[f], a.spans[w], perspective ? &a.boxes[w] : nullptr, count)) {
      tally.Beyond(fmt::format("triangle {} face {}: span {} where a conformant device gives {}{}", t, f, SpanText(a.spans[w]),
                               RangeText(spans[f]), perspective ? " (or its (u, v) rectangle is beyond the permitted floats)" : ""));
      return;
    }
  }
  if (a.counts[t] != count) {
    tally.Beyond(fmt::format("counts[{}]: {}, where the device's own spans hold {} cells", t, a.counts[t], count));
    return;
  }
  if (perspective && !dist.Allows(a.dist[t])) {
    tally.Beyond(fmt::format("dist[{}]: {} is no least distance a conformant device computes (within [{}, {}])", t, a.dist[t], dist.lo,
                             dist.hi));
    return;
  }
  tally.Within();
}

}  // namespace

SpecVerdict ClassifyGridCount(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush) {
  const DecodedCall<emu::call::GridCount> d = DecodeCall<emu::call::GridCount>(in);
  const emu::call::GridCount& c = d.call;
  const layout::GridBuildGrid g = emu::grid::FromDescriptor(c.grid, c.shape);
  const bool perspective = g.shape.x == layout::kGridKindPerspective;
  const CountWords e(expected), a(actual);
  const std::size_t n = c.triangles.size(), faces = n * layout::kGridFaces;
  SpecTally t;
  for (const CountWords* w : {&e, &a})
    if (w->counts.size() != n || w->spans.size() != faces || w->boxes.size() != (perspective ? faces : 0) ||
        w->dist.size() != (perspective ? n : 0)) {
      t.Beyond("counts, spans, span_boxes, dist: a word per triangle and face as the grid's kind has them");
      return t.Done();
    }
  for (std::size_t i = 0; i < n; ++i)
    if (!e.Same(a, i, perspective)) CheckTriangle(c, g, a, i, flush, t);
  return t.Done();
}

}  // namespace rayspace::verify
