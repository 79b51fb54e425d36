// The relaxed device model of the lists' windows, tl.heads and tl.cells (docs/numerics.md, "The
// relaxed device model"). A window is tl::ListWindow over one rejection decision per element; the
// decisions round (the planes through a triangle or a screen cell and the tests against them,
// tl/heads_math.h). More rejections never widen a window: the head only moves on and the tail back.
// So a device, whose rejections hold every sure one and only possible ones, writes a window inside
// the window of the sure rejections and around the window of the possible ones; a device's window
// is within the spec when it is (an empty window holds nothing to be around).
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/heads_math.h"
#include "rayspace/emu/tl/window.h"
#include "rayspace/verify/call_codec.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;
using WinV3 = emu::Vec3<R>;

WinV3 WinSpec3(glm::vec4 v) { return {R(v.x), R(v.y), R(v.z)}; }

// A rejection evaluated in SpecReal: may some device reject, does every one?
struct Rejection {
  bool may = false, sure = false;
};

// The two windows around every device's: the sure rejections' (widest) and the possible ones'
// (narrowest). `valid` is the planes' own decision (a sliver has none: the whole list).
struct Envelope {
  glm::uvec2 wide{0u}, narrow{0u};
};

template <typename Reject>
Envelope EnvelopeOf(std::span<const std::uint32_t> escapes, std::uint32_t begin, std::uint32_t end, bool may_valid, bool may_invalid,
                    Reject&& reject) {
  std::vector<std::optional<Rejection>> memo(end - begin);
  const auto at = [&](std::uint32_t i) -> const Rejection& {
    std::optional<Rejection>& r = memo[i - begin];
    if (!r) r = reject(i);
    return *r;
  };
  Envelope e;
  e.wide = may_invalid ? glm::uvec2(begin, end) : emu::tl::ListWindow(escapes, begin, end, [&](std::uint32_t i) { return at(i).sure; });
  e.narrow = may_valid ? emu::tl::ListWindow(escapes, begin, end, [&](std::uint32_t i) { return at(i).may; }) : glm::uvec2(begin, end);
  return e;
}

bool Empty(glm::uvec2 w) { return w.x >= w.y; }
bool Inside(glm::uvec2 inner, glm::uvec2 outer) { return Empty(inner) || (outer.x <= inner.x && inner.y <= outer.y); }

// Every differing window of a call: `envelope(g)` gives group-and-list g's.
template <typename EnvelopeFn>
SpecVerdict TallyWindows(const BufferSet& e, const BufferSet& a, EnvelopeFn&& envelope) {
  SpecTally t;
  const std::vector<std::uint32_t> ew = e.Get<std::uint32_t>("windows"), aw = a.Get<std::uint32_t>("windows");
  if (ew.size() != aw.size()) {
    t.Beyond("windows: sizes differ");
    return t.Done();
  }
  for (std::size_t g = 0; 2 * g + 1 < aw.size(); ++g) {
    if (ew[2 * g] == aw[2 * g] && ew[2 * g + 1] == aw[2 * g + 1]) continue;
    const glm::uvec2 w(aw[2 * g], aw[2 * g + 1]);
    const Envelope env = envelope(g);
    if (Inside(w, env.wide) && (Empty(env.narrow) || Inside(env.narrow, w)))
      t.Within();
    else
      t.Beyond(fmt::format("windows[{}]: [{}, {}) outside [{}, {}) or not around [{}, {}), the windows of the sure and the possible rejections",
                           g, w.x, w.y, env.wide.x, env.wide.y, env.narrow.x, env.narrow.y));
  }
  return t.Done();
}

// An element's rejection: its sphere (a sphere element) or its triangle's vertices.
template <typename Call, typename SphereTest, typename TriangleTest>
Rejection RejectElement(const Call& c, std::uint32_t i, bool flush, SphereTest&& sphere, TriangleTest&& triangle) {
  ScopedSpecTrace trace(flush);
  const glm::uvec4 w = c.words[i];
  bool rejected;
  if (!emu::tl::IsTriangle(static_cast<emu::tl::Escape>(c.escapes[i])))
    rejected = sphere(emu::Vec4<R>(R(std::bit_cast<float>(w.x)), R(std::bit_cast<float>(w.y)), R(std::bit_cast<float>(w.z)),
                                   R(std::bit_cast<float>(w.w))));
  else
    rejected = triangle(WinSpec3(c.vertices[w.x]), WinSpec3(c.vertices[w.y]), WinSpec3(c.vertices[w.z]));
  const bool flip = trace.trace().ambiguous != 0;
  return {rejected || flip, rejected && !flip};
}

}  // namespace

SpecVerdict ClassifyTlHeads(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush) {
  const DecodedCall<emu::call::TlHeads> d = DecodeCall<emu::call::TlHeads>(in);
  const emu::call::TlHeads& c = d.call;
  const auto K = static_cast<std::uint32_t>(c.first.size() - 1);
  return TallyWindows(expected, actual, [&](std::size_t g) {
    const auto k = static_cast<std::uint32_t>(g % K), cs = static_cast<std::uint32_t>(g / K % layout::kTlCases);
    const glm::uvec4 tw = c.tri_words[g / K / layout::kTlCases];
    emu::tl::HeadPlanesOf<R> p;
    bool flip;
    {
      ScopedSpecTrace trace(flush);
      p = emu::tl::MakePlanesOf<R>(WinSpec3(c.vertices[tw.x]), WinSpec3(c.vertices[tw.y]), WinSpec3(c.vertices[tw.z]), cs, K, k, c.mode,
                                   R(c.margin));
      flip = trace.trace().ambiguous != 0;  // the sliver test, the only decision of the planes
    }
    return EnvelopeOf(c.escapes, c.first[k], c.first[k + 1], p.valid || flip, !p.valid || flip, [&](std::uint32_t i) {
      return RejectElement(
          c, i, flush, [&](const emu::Vec4<R>& s) { return emu::tl::SphereRejectedOf(p, s); },
          [&](const WinV3& a, const WinV3& b, const WinV3& v) { return emu::tl::TriangleRejectedOf(p, a, b, v); });
    });
  });
}

SpecVerdict ClassifyTlCells(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush) {
  const DecodedCall<emu::call::TlCells> d = DecodeCall<emu::call::TlCells>(in);
  const emu::call::TlCells& c = d.call;
  const auto K = static_cast<std::uint32_t>(c.first.size() - 1);
  return TallyWindows(expected, actual, [&](std::size_t g) {
    const auto k = static_cast<std::uint32_t>(g % K), cell = static_cast<std::uint32_t>(g / K);
    const std::uint32_t cx = cell % emu::tl::CellsX(c.frame), cy = cell / emu::tl::CellsX(c.frame);
    const std::uint32_t x0 = cx * layout::kTlCellPixels, y0 = cy * layout::kTlCellPixels;
    const std::uint32_t x1 = std::min(x0 + layout::kTlCellPixels, c.frame.dims.x) - 1;
    const std::uint32_t y1 = std::min(y0 + layout::kTlCellPixels, c.frame.dims.y) - 1;
    emu::tl::CellPlanesOf<R> p;
    bool flip;
    {
      ScopedSpecTrace trace(flush);
      p = emu::tl::MakeCellPlanesOf<R>(c.frame, x0, y0, x1, y1, R(c.margin));
      flip = trace.trace().ambiguous != 0;  // a normal that may face the other way: any window in the list
    }
    if (flip) return Envelope{glm::uvec2(c.first[k], c.first[k + 1]), glm::uvec2(0u)};
    return EnvelopeOf(c.escapes, c.first[k], c.first[k + 1], true, false, [&](std::uint32_t i) {
      return RejectElement(
          c, i, flush, [&](const emu::Vec4<R>& s) { return emu::tl::CellSphereRejectedOf(p, s); },
          [&](const WinV3& a, const WinV3& b, const WinV3& v) { return emu::tl::CellTriangleRejectedOf(p, a, b, v); });
    });
  });
}

}  // namespace rayspace::verify
