// The relaxed device model of the raster's fragment stage (docs/numerics.md, "The relaxed device
// model"): where both sides cover a pixel with the same triangle, the depth, the position and the
// shading normal are the fragment stage's arithmetic (a division, a root) and must lie in the
// intervals of that arithmetic in SpecReal (emu::raster::ShadeFragmentOf, emu::ShadingNormalOf); the
// material words and the normal's transparency are copies and must be equal. Pixels whose triangle
// differs on an edge are the coverage verdict's (raster_edges.h); inside both triangles, a depth
// test that a loosely rounded depth may turn (ClassifyRasterFlips).
#include <bit>
#include <cstdint>
#include <cstring>

#include <fmt/format.h>

#include "rayspace/emu/raster_detail.h"
#include "rayspace/emu/surface_math.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/raster_edges.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;

bool Same(const glm::vec4& a, const glm::vec4& b) { return std::memcmp(&a, &b, sizeof(glm::vec4)) == 0; }

// Why the device's words of pixel i are no fragment a conformant device computes, or "".
std::string CheckFragment(const emu::call::Raster& c, std::uint32_t prim, std::uint32_t px, std::uint32_t py, float depth,
                          const glm::vec4& position, const glm::vec4& normal, bool flush) {
  ScopedSpecTrace trace(flush);
  const layout::Triangle& t = c.scene->triangles[prim];
  const emu::Vec3<R> v0(R(t.v0.x), R(t.v0.y), R(t.v0.z)), v1(R(t.v1.x), R(t.v1.y), R(t.v1.z)), v2(R(t.v2.x), R(t.v2.y), R(t.v2.z));
  const emu::raster::FragmentOf<R> f = emu::raster::ShadeFragmentOf(c.frame, v0, v1, v2, emu::PixelDirectionOf<R>(c.frame, px, py));
  if (f.discard) return trace.trace().ambiguous ? "" : "a pixel every device discards";
  const emu::Vec3<R> n = emu::ShadingNormalOf(*c.scene, prim, f.position);
  // After a decision that may go either way (which region of the shading normal's weights) the
  // words are no longer bounded by this evaluation.
  if (trace.trace().ambiguous != 0) return "";
  if (!f.depth.Allows(depth)) return fmt::format("depth {:#x} outside [{}, {}]", std::bit_cast<std::uint32_t>(depth), f.depth.lo, f.depth.hi);
  for (int k = 0; k < 3; ++k) {
    if (!f.position[k].Allows(position[k])) return fmt::format("position[{}] {} outside [{}, {}]", k, position[k], f.position[k].lo, f.position[k].hi);
    if (!n[k].Allows(normal[k])) return fmt::format("normal[{}] {} outside [{}, {}]", k, normal[k], n[k].lo, n[k].hi);
  }
  return "";
}

// Could the depth test pick `b` over `a` at pixel (px, py) on a conformant device? Both fragments'
// depths (the stage's quotient, in SpecReal) must admit b's at or before a's, and b must cover the
// pixel or one beside it (its edge may pass within a pixel where a hides it).
std::string FlipWhy(const emu::call::Raster& c, const std::vector<emu::raster::Setup>& setups, std::uint32_t a, std::uint32_t b,
                    std::uint32_t px, std::uint32_t py, bool flush) {
  if (a >= c.scene->triangles.size() || b >= c.scene->triangles.size()) return "a triangle against the background, away from every edge";
  bool covers = false;
  for (const emu::raster::Setup& s : setups)
    for (int dy = -1; dy <= 1 && s.prim == b && !covers; ++dy)
      for (int dx = -1; dx <= 1 && !covers; ++dx) covers = emu::raster::Covers(s, static_cast<int>(px) + dx, static_cast<int>(py) + dy);
  if (!covers) return fmt::format("triangle {} does not cover it", b);
  ScopedSpecTrace trace(flush);
  const auto fragment = [&](std::uint32_t prim) {
    const layout::Triangle& t = c.scene->triangles[prim];
    const emu::Vec3<R> v0(R(t.v0.x), R(t.v0.y), R(t.v0.z)), v1(R(t.v1.x), R(t.v1.y), R(t.v1.z)), v2(R(t.v2.x), R(t.v2.y), R(t.v2.z));
    return emu::raster::ShadeFragmentOf(c.frame, v0, v1, v2, emu::PixelDirectionOf<R>(c.frame, px, py));
  };
  const emu::raster::FragmentOf<R> fa = fragment(a), fb = fragment(b);
  if (trace.trace().ambiguous != 0) return "";
  if (fb.discard) return fmt::format("triangle {}'s fragment is discarded on every device", b);
  if (!fa.discard && fb.depth.lo > fa.depth.hi)
    return fmt::format("triangle {} lies behind triangle {} on every device (depth [{}, {}] against [{}, {}])", b, a, fb.depth.lo, fb.depth.hi,
                       fa.depth.lo, fa.depth.hi);
  return "";
}

}  // namespace

// Interior pixels whose triangle differs: a depth test a loosely rounded depth may turn, the device's
// words then the other triangle's fragment.
SpecVerdict ClassifyRasterFlips(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::Raster> d = DecodeCall<emu::call::Raster>(in);
  const emu::call::Raster& c = d.call;
  SpecTally t;
  const auto ep = e.View<std::uint32_t>("prim"), ap = a.View<std::uint32_t>("prim");
  const auto depth = a.View<float>("depth");
  const auto diffuse = a.View<glm::vec4>("diffuse"), specular = a.View<glm::vec4>("specular");
  const auto position = a.View<glm::vec4>("position"), normal = a.View<glm::vec4>("normal");
  const std::uint32_t w = c.frame.dims.x, h = c.frame.dims.y;
  const std::size_t n = std::size_t{w} * h;
  if (ep.size() != n || ap.size() != n || depth.size() != n || diffuse.size() != n || specular.size() != n || position.size() != n ||
      normal.size() != n) {
    t.Beyond("prim, depth, diffuse, specular, position, normal: a word per pixel");
    return t.Done();
  }
  std::vector<emu::raster::Setup> setups;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t px = static_cast<std::uint32_t>(i % w), py = static_cast<std::uint32_t>(i / w);
    if (ep[i] == ap[i] || OnTriangleEdge(w, h, ep, ap, px, py)) continue;
    if (setups.empty()) setups = emu::raster::SetupAll(c.frame, c.scene->triangles);
    std::string why = FlipWhy(c, setups, ep[i], ap[i], px, py, flush);
    if (why.empty()) {
      const layout::Material& m = c.scene->materials[c.scene->info[ap[i]].ids.x];
      if (!Same(diffuse[i], m.diffuse_reflectivity) || !Same(specular[i], m.specular_shininess) ||
          std::bit_cast<std::uint32_t>(normal[i].w) != std::bit_cast<std::uint32_t>(m.transparency_ior.x))
        why = "a material word or a w, which the fragment stage copies";
      else
        why = CheckFragment(c, ap[i], px, py, depth[i], position[i], normal[i], flush);
    }
    if (why.empty())
      t.Within();
    else
      t.Beyond(fmt::format("pixel {} (interior, triangle {} where the emulator has {}): {}", i, ap[i], ep[i], why));
  }
  return t.Done();
}

SpecVerdict ClassifyRasterFragments(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::Raster> d = DecodeCall<emu::call::Raster>(in);
  const emu::call::Raster& c = d.call;
  SpecTally t;
  const auto ep = e.Get<std::uint32_t>("prim"), ap = a.Get<std::uint32_t>("prim");
  const auto ed = e.Get<float>("depth"), ad = a.Get<float>("depth");
  const auto diffuse = [&](const BufferSet& s) { return s.Get<glm::vec4>("diffuse"); };
  const auto specular = [&](const BufferSet& s) { return s.Get<glm::vec4>("specular"); };
  const auto ef = diffuse(e), af = diffuse(a), es = specular(e), as = specular(a);
  const auto epos = e.Get<glm::vec4>("position"), apos = a.Get<glm::vec4>("position");
  const auto en = e.Get<glm::vec4>("normal"), an = a.Get<glm::vec4>("normal");
  const std::size_t n = std::size_t{c.frame.dims.x} * c.frame.dims.y;
  if (ep.size() != n || ap.size() != n || ed.size() != n || ad.size() != n || ef.size() != n || af.size() != n || es.size() != n || as.size() != n || epos.size() != n ||
      apos.size() != n || en.size() != n || an.size() != n) {
    t.Beyond("depth, diffuse, specular, position, normal: a word per pixel");
    return t.Done();
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (ep[i] != ap[i] || ep[i] >= c.scene->triangles.size()) continue;  // coverage, or an empty pixel on both sides
    if (std::bit_cast<std::uint32_t>(ed[i]) == std::bit_cast<std::uint32_t>(ad[i]) && Same(epos[i], apos[i]) && Same(en[i], an[i]) &&
        Same(ef[i], af[i]) && Same(es[i], as[i]))
      continue;
    std::string why;
    if (!Same(ef[i], af[i]) || !Same(es[i], as[i]) || std::bit_cast<std::uint32_t>(en[i].w) != std::bit_cast<std::uint32_t>(an[i].w) ||
        std::bit_cast<std::uint32_t>(apos[i].w) != std::bit_cast<std::uint32_t>(epos[i].w))
      why = "a material word or a w, which the fragment stage copies";
    else
      why = CheckFragment(c, ap[i], static_cast<std::uint32_t>(i % c.frame.dims.x), static_cast<std::uint32_t>(i / c.frame.dims.x), ad[i],
                          apos[i], an[i], flush);
    if (why.empty())
      t.Within();
    else
      t.Beyond(fmt::format("pixel {}: {}", i, why));
  }
  return t.Done();
}

}  // namespace rayspace::verify
