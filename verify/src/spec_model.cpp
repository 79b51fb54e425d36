#include "rayspace/verify/spec_model.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>

#include <fmt/format.h>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/hash_math.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/emu/raygen_math.h"
#include "rayspace/emu/shade_math.h"
#include "rayspace/emu/surface_math.h"
#include "rayspace/refs/exact_cone.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_real.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;
using V = emu::Vec3<SpecReal>;

V Spec3(glm::vec3 v) { return V(R(v.x), R(v.y), R(v.z)); }

std::string Show(float f) { return fmt::format("{:#010x} ({:g})", std::bit_cast<std::uint32_t>(f), f); }

using Tally = SpecTally;

// Calls fn(i, expected, actual) for every element where the two copies of output `name` differ (the
// emulator's and the device's), after requiring equal sizes, and `size` elements when given.
template <typename T, typename Fn>
SpecVerdict ForEachDiffering(const BufferSet& e, const BufferSet& a, const std::string& name, Fn&& fn,
                             std::size_t size = SIZE_MAX) {
  const std::vector<T> ev = e.Get<T>(name), av = a.Get<T>(name);
  Tally t;
  if (ev.size() != av.size() || (size != SIZE_MAX && ev.size() != size)) {
    t.Beyond(name + ": sizes differ");
    return t.Done();
  }
  for (std::size_t i = 0; i < ev.size(); ++i)
    if (std::memcmp(&ev[i], &av[i], sizeof(T)) != 0) fn(i, ev[i], av[i], t);
  return t.Done();
}

// One 32-bit word of a modelled element: an exact word, or a range of floats.
struct Word {
  bool exact = true;
  std::uint32_t bits = 0;
  SpecReal range;
  bool Allows(std::uint32_t actual) const {
    return exact ? bits == actual : range.Allows(std::bit_cast<float>(actual));
  }
  std::string Describe() const {
    if (exact) return fmt::format("{:#010x}", bits);
    if (range.any) return "anything";
    return fmt::format("[{}, {}]", Show(range.lo), Show(range.hi));
  }
};
Word Exact(float f) { return {true, std::bit_cast<std::uint32_t>(f), {}}; }
Word ExactU(std::uint32_t u) { return {true, u, {}}; }
Word Range(SpecReal r) { return {false, 0, r}; }

// ---- raygen ---------------------------------------------------------------------------------------

struct RayModel {
  bool spawn = false;
  std::array<Word, 16> words;  // origin_tmin, direction_tmax, info, weight
  std::uint32_t ambiguous = 0;
};

// The words of a ray that no rounding decides (origin, tmin, info and, for shadow rays, the weight)
// are exact; the direction and tmax stay unbounded until the model computes them, and are set back to
// unbounded when a decision on the way could have gone the other way.
// A modelled word: exact when no rounding choice reaches it (a point light's position, a rect's
// sample), else the range a device may produce (the square root of a disk's or sphere's sample).
Word Modelled(R x) { return (!x.any && x.lo == x.hi) ? Exact(x.lo) : Range(x); }

RayModel ModelShadowRay(const emu::call::Raygen& c, std::size_t slot) {
  RayModel m;
  const std::size_t per = ShadowSlots(c.scene->lights);
  const layout::Surface& sf = c.surfaces[slot / per];
  const std::uint32_t j = static_cast<std::uint32_t>(slot % per);
  std::uint32_t l = 0;
  while (j >= c.scene->lights[l].sampling.z + c.scene->lights[l].sampling.y) ++l;
  const layout::Light& light = c.scene->lights[l];
  if (sf.position.w == 0.0f) return m;
  const V o = emu::LightSamplePoint<R>(light, l, layout::SamplerKey(sf.info.y, sf.info.x), j - light.sampling.z);
  const Word any = Range(SpecReal::Unbounded(0.0f));
  m.words = {Modelled(o.x),      Modelled(o.y),      Modelled(o.z),                Exact(c.frame.params.x),
             any,                any,                any,                          any,
             ExactU(sf.info.y),  ExactU(sf.info.x),  ExactU(layout::kRayShadow),   ExactU(l),
             Exact(sf.weight.x), Exact(sf.weight.y), Exact(sf.weight.z),           Exact(sf.weight.w)};
  V d;
  R dist;
  m.spawn = emu::ShadowDirection(Spec3(emu::Xyz(sf.position)), o, d, dist);
  if (m.spawn && c.shadow_rule == layout::kShadowRuleLit)
    m.spawn = emu::LightInFront(d, Spec3(emu::Xyz(sf.normal)), Spec3(emu::Xyz(sf.incoming)));
  if (m.spawn) {
    m.words[4] = Range(d.x);
    m.words[5] = Range(d.y);
    m.words[6] = Range(d.z);
    m.words[7] = Range(dist * R(c.frame.params.z));
  }
  return m;
}

RayModel ModelSurfaceRay(const emu::call::Raygen& c, std::size_t slot) {
  RayModel m;
  const layout::Surface& sf = c.surfaces[slot];
  if (sf.position.w == 0.0f) return m;
  const layout::Material& mat = c.scene->materials[sf.info.z];
  const bool reflection = c.kind == layout::kRayReflection;
  const float k = reflection ? mat.diffuse_reflectivity.w : mat.transparency_ior.x;
  if (!(k > 0.0f)) return m;
  const glm::vec3 p = emu::Xyz(sf.position);
  const Word any = Range(SpecReal::Unbounded(0.0f));
  m.words = {Exact(p.x),         Exact(p.y),         Exact(p.z),        Exact(c.frame.params.x),
             any,                any,                any,               Exact(INFINITY),
             ExactU(sf.info.y),  ExactU(sf.info.x),  ExactU(c.kind),    ExactU(static_cast<std::uint32_t>(slot)),
             Range(R(sf.weight.x) * R(k)), Range(R(sf.weight.y) * R(k)), Range(R(sf.weight.z) * R(k)), Exact(0.0f)};
  V d;
  if (reflection)
    d = emu::ReflectionDirection(Spec3(emu::Xyz(sf.incoming)), Spec3(emu::Xyz(sf.normal)));
  else if (!emu::RefractionDirection(Spec3(emu::Xyz(sf.incoming)), Spec3(emu::Xyz(sf.normal)), R(mat.transparency_ior.y), d))
    return m;
  if (!(emu::Dot(d, d) > R(0.0f))) return m;
  m.spawn = true;
  m.words[4] = Range(d.x);
  m.words[5] = Range(d.y);
  m.words[6] = Range(d.z);
  return m;
}

SpecVerdict Raygen(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::Raygen> d = DecodeCall<emu::call::Raygen>(in);
  const emu::call::Raygen& c = d.call;
  const auto er = e.Get<layout::Ray>("rays"), ar = a.Get<layout::Ray>("rays");
  const auto ef = e.Get<std::uint32_t>("flags"), af = a.Get<std::uint32_t>("flags");
  Tally t;
  if (er.size() != ar.size() || ef.size() != af.size()) {
    t.Beyond("the ray slot counts differ");
    return t.Done();
  }
  for (std::size_t s = 0; s < er.size(); ++s) {
    const auto ew = std::bit_cast<std::array<std::uint32_t, 16>>(er[s]), aw = std::bit_cast<std::array<std::uint32_t, 16>>(ar[s]);
    if (ew == aw && ef[s] == af[s]) continue;
    ScopedSpecTrace trace(flush);
    RayModel m = c.kind == layout::kRayShadow ? ModelShadowRay(c, s) : ModelSurfaceRay(c, s);
    // A decision a permitted rounding may take the other way (a zero distance, total internal
    // reflection): the slot may or may not spawn, with any direction, but its exact words still hold.
    const bool flips = trace.trace().ambiguous != 0;
    if (flips)
      for (std::size_t w = 4; w < 7; ++w) m.words[w] = Range(SpecReal::Unbounded(0.0f));
    const bool spawn = flips ? af[s] == 1u : m.spawn;
    if (af[s] != (spawn ? 1u : 0u)) {
      t.Beyond(fmt::format("flags[{}]: {} where every conformant device gives {}", s, af[s], m.spawn ? 1 : 0));
      continue;
    }
    std::size_t bad = 16;
    for (std::size_t w = 0; w < 16 && bad == 16; ++w)
      if (spawn ? !m.words[w].Allows(aw[w]) : aw[w] != 0u) bad = w;  // an empty slot is all zeros
    if (bad == 16) {
      t.Within();
    } else {
      t.Beyond(fmt::format("rays[{}] word {}: {} outside {}", s, bad, Show(std::bit_cast<float>(aw[bad])),
                           spawn ? m.words[bad].Describe() : std::string("0x00000000 (an empty slot)")));
    }
  }
  return t.Done();
}

// ---- intersect ------------------------------------------------------------------------------------

// The largest packed hit a candidate that surely hits may report.
std::uint64_t LatestPacked(const Candidate& c) {
  return c.t.any ? emu::kMissPacked : emu::PackHit(c.t.hi, c.prim);
}

}  // namespace

Candidate ModelCandidate(const layout::Ray& r, const layout::Triangle& tri, std::uint32_t prim, bool flush) {
  ScopedSpecTrace trace(flush);
  R t{};
  const bool hit = emu::IntersectWatertight(emu::SetupWatertight(Spec3(emu::Xyz(r.origin_tmin)), Spec3(emu::Xyz(r.direction_tmax))),
                                            Spec3(emu::Xyz(tri.v0)), Spec3(emu::Xyz(tri.v1)), Spec3(emu::Xyz(tri.v2)),
                                            R(r.origin_tmin.w), R(r.direction_tmax.w), t);
  const bool ambiguous = trace.trace().ambiguous != 0;
  return {prim, hit || ambiguous, hit && !ambiguous, ambiguous ? SpecReal::Unbounded(t.v) : t};
}

// A reported t passed the device's own range check, which compares exactly: tmin < t < tmax.
bool ClosestAllowed(std::uint64_t h0, std::uint64_t a, const std::vector<Candidate>& cands, const layout::Ray& ray) {
  for (const Candidate& c : cands)
    if (c.definite && LatestPacked(c) < a) return false;  // that candidate's hit is surely nearer
  if (a == h0) return true;
  if (a > h0) return false;  // a minimum never rises
  const float t = emu::HitT(a);
  if (!(t > ray.origin_tmin.w && t < ray.direction_tmax.w)) return false;
  for (const Candidate& c : cands)
    if (c.prim == emu::HitPrim(a) && c.possible && c.t.Allows(t)) return true;
  return false;
}

bool ResultAllowed(bool shadow, std::uint64_t before, std::uint64_t result, const std::vector<Candidate>& cands, const layout::Ray& ray) {
  if (!shadow) return ClosestAllowed(before, result, cands, ray);
  bool possible = before != 0, definite = before != 0;
  for (const Candidate& cd : cands) possible |= cd.possible, definite |= cd.definite;
  return result == 1 ? possible : (result == 0 && !definite);
}

std::vector<TracedRay> TracedRays(const BufferSet& s, bool shadow, const char* first, const char* second) {
  std::vector<std::uint64_t> result;
  if (shadow)
    for (std::uint32_t v : s.Get<std::uint32_t>("occluded")) result.push_back(v);
  else
    result = s.Get<std::uint64_t>("hits");
  const std::vector<std::uint32_t> a = s.Get<std::uint32_t>(first), b = s.Get<std::uint32_t>(second);
  std::vector<TracedRay> out;
  if (a.size() != result.size() || b.size() != result.size()) return out;
  for (std::size_t i = 0; i < result.size(); ++i) out.push_back({result[i], a[i], b[i]});
  return out;
}

namespace {

bool TestMayFlip(const layout::ConeNode& n, glm::vec4 sphere, float eps, std::uint32_t cone_test, bool flush);

// --leaf-test ray-sphere: a pair's count may be any between the rays whose sphere test passes on every
// conformant device and those whose test passes on some (the one-ray node as lavapipe builds it).
void TallyLeafTests(const emu::call::Intersect& c, const std::vector<std::uint32_t>& et, const std::vector<std::uint32_t>& at,
                    bool flush, Tally& t) {
  for (std::size_t p = 0; p < et.size() && p < at.size(); ++p) {
    if (et[p] == at[p]) continue;
    const std::uint32_t node = c.base1 + (c.pairs[p] >> emu::kPairTriangleBits), prim = c.b0 + (c.pairs[p] & emu::kPairTriangleMask);
    std::uint32_t lo = 0, hi = 0;
    for (std::uint32_t j = c.first1[node]; j < c.first1[node + 1]; ++j) {
      const layout::Ray& r = c.rays[c.order[j]];
      layout::ConeNode n = emu::cone::FromRay(emu::Xyz(r.origin_tmin), emu::Normalize(emu::Xyz(r.direction_tmax)));
      emu::cone::Finish(n);
      const bool pass = emu::cone::Test(n, c.tri_spheres[prim], c.eps), flip = TestMayFlip(n, c.tri_spheres[prim], c.eps, layout::kConeTestConservative, flush);
      lo += pass && !flip;
      hi += pass || flip;
    }
    if (lo <= at[p] && at[p] <= hi)
      t.Within();
    else
      t.Beyond(fmt::format("tests[{}]: {} outside the {} to {} rays whose sphere test may pass", p, at[p], lo, hi));
  }
}

// The closest hits (or shadow flags) of a final-test call: every ray whose word differs must hold a
// result the device may reach from its candidates, the triangles `each_pair_ray(visit)` pairs it with
// (visit(ray, prim), the ray's own surface skipped).
template <typename EachPairRay>
void TallyHits(const std::vector<std::uint32_t>* occluded, const std::vector<std::uint64_t>* hits, const emu::In<layout::Ray>& rays,
               const SceneBuffers& scene, const BufferSet& e, const BufferSet& a, bool flush, Tally& t, EachPairRay&& each_pair_ray) {
  const bool shadow = occluded != nullptr;
  const std::string out = shadow ? "occluded" : "hits";
  std::vector<std::uint64_t> eh, ah;
  if (shadow) {
    for (std::uint32_t v : e.Get<std::uint32_t>(out)) eh.push_back(v);
    for (std::uint32_t v : a.Get<std::uint32_t>(out)) ah.push_back(v);
  } else {
    eh = e.Get<std::uint64_t>(out);
    ah = a.Get<std::uint64_t>(out);
  }
  if (eh.size() != ah.size()) {
    t.Beyond(out + ": sizes differ");
    return;
  }
  std::unordered_map<std::uint32_t, std::vector<Candidate>> cands;
  for (std::size_t i = 0; i < eh.size(); ++i)
    if (eh[i] != ah[i]) cands[static_cast<std::uint32_t>(i)];
  if (cands.empty()) return;
  each_pair_ray([&](std::uint32_t ray, std::uint32_t prim) {
    auto it = cands.find(ray);
    if (it == cands.end() || prim == rays[ray].info.y) return;
    it->second.push_back(ModelCandidate(rays[ray], scene.triangles[prim], prim, flush));
  });
  for (const auto& [ray, cs] : cands) {
    const std::uint64_t before = shadow ? std::uint64_t{(*occluded)[ray]} : (*hits)[ray];
    if (ResultAllowed(shadow, before, ah[ray], cs, rays[ray]))
      t.Within();
    else
      t.Beyond(fmt::format("{}[{}]: {:#018x} is no permitted result of its {} candidate triangles", out, ray, ah[ray], cs.size()));
  }
}

SpecVerdict Intersect(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::Intersect> d = DecodeCall<emu::call::Intersect>(in);
  const emu::call::Intersect& c = d.call;
  Tally t;
  const std::vector<std::uint32_t> et = e.Get<std::uint32_t>("tests"), at = a.Get<std::uint32_t>("tests");
  if (et.size() != at.size() || (et != at && c.leaf_test != layout::kLeafTestRaySphere))
    t.Beyond("tests: the per-pair test counts are integers");
  else if (et != at)
    TallyLeafTests(c, et, at, flush, t);
  TallyHits(c.occluded, c.hits, c.rays, *c.scene, e, a, flush, t, [&](auto&& visit) {
    for (std::size_t p = 0; p < c.pairs.size(); ++p) {
      const std::uint32_t node = c.base1 + (c.pairs[p] >> emu::kPairTriangleBits), prim = c.b0 + (c.pairs[p] & emu::kPairTriangleMask);
      for (std::uint32_t j = c.first1[node]; j < c.first1[node + 1]; ++j) visit(c.order[j], prim);
    }
  });
  return t.Done();
}

// intersect.tree: the object tree's final pairs, a level-1 node's rays (or level 0's one ray) against
// a triangle of the tree's list; the hits as intersect's, the per-pair ray counts exact.
SpecVerdict IntersectTree(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::IntersectTree> d = DecodeCall<emu::call::IntersectTree>(in);
  const emu::call::IntersectTree& c = d.call;
  Tally t;
  if (e.Get<std::uint32_t>("tests") != a.Get<std::uint32_t>("tests")) t.Beyond("tests: the per-pair ray counts are integers");
  TallyHits(c.occluded, c.hits, c.rays, *c.scene, e, a, flush, t, [&](auto&& visit) {
    for (std::size_t p = 0; p < c.pair_cone.size(); ++p) {
      const auto [j0, j1] = emu::TreeFinalRays(c.first1, c.pair_cone[p], c.pair_item[p]);
      const std::uint32_t prim = c.tree_triangles[c.pair_item[p] & ~layout::kTreeItemTriangle];
      for (std::uint32_t j = j0; j < j1; ++j) visit(c.order[j], prim);
    }
  });
  return t.Done();
}

// ---- hash ---------------------------------------------------------------------------------------

// The low `bits` bits set, and a key above its low `bits` bits (both defined for bits = 32).
std::uint32_t LowBits(int bits) { return bits >= 32 ? ~0u : (1u << bits) - 1u; }
std::uint32_t High(std::uint32_t key, int bits) { return bits >= 32 ? 0u : key >> bits; }

struct CellRange {
  std::uint32_t lo = 0, hi = 0;
  bool Holds(std::uint32_t c) const { return lo <= c && c <= hi; }
};

// The cells (emu Cell: f * 2^bits clamped to [0, 2^bits - 1], truncated) of every permitted f.
CellRange Cells(SpecReal f, int bits, bool any) {
  // Beyond 24 bits the cell count minus one is not a float: no bound is derived there.
  if (any || f.any || bits > 24) return {0, LowBits(bits)};
  const float cells = static_cast<float>(1u << bits);
  const SpecReal v = Min(Max(f * R(cells), R(0.0f)), R(cells - 1.0f));
  return {static_cast<std::uint32_t>(v.lo), static_cast<std::uint32_t>(v.hi)};
}

// Splits a direction key (emu DirectionKey: polar bit above azimuth bit, from the top, or all polar
// bits above the azimuth's) into its cells.
void SplitDirection(std::uint32_t key, int polar_bits, int azimuth_bits, std::uint32_t order, std::uint32_t& p,
                    std::uint32_t& a) {
  if (order == layout::kHashOrderPolarFirst) {
    p = (key >> azimuth_bits) & LowBits(polar_bits);
    a = key & LowBits(azimuth_bits);
    return;
  }
  int pos = polar_bits + azimuth_bits;
  p = a = 0;
  for (int b = std::max(polar_bits, azimuth_bits) - 1; b >= 0; --b) {
    if (b < polar_bits) p |= ((key >> --pos) & 1u) << b;
    if (b < azimuth_bits) a |= ((key >> --pos) & 1u) << b;
  }
}

// The direction part of a key: are its cells those of some permitted unit direction?
bool DirectionAllowed(std::uint32_t key, glm::vec3 dir, int polar_bits, int azimuth_bits, std::uint32_t order) {
  ScopedSpecTrace trace(CurrentSpecTrace().flush_denormals);
  const V d = emu::Normalize(Spec3(dir));
  const SpecReal polar = emu::PolarArgument(d.z);
  const SpecReal azimuth = emu::DiamondAngle(d.x, d.y) * R(0.25f);
  const bool branch_flips = trace.trace().ambiguous != 0;  // the azimuth's quadrant is not certain
  std::uint32_t p, a;
  SplitDirection(key, polar_bits, azimuth_bits, order, p, a);
  return Cells(polar, polar_bits, false).Holds(p) && Cells(azimuth, azimuth_bits, branch_flips).Holds(a);
}

SpecVerdict Hash(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::Hash> d = DecodeCall<emu::call::Hash>(in);
  const emu::call::Hash& c = d.call;
  const emu::HashConfig& h = c.hash;
  return ForEachDiffering<std::uint32_t>(e, a, "keys", [&](std::size_t i, std::uint32_t expected, std::uint32_t key, Tally& t) {
    ScopedSpecTrace trace(flush);
    const layout::Ray& r = c.rays[i];
    bool ok;
    if (c.quadtree_width != 0) {
      ok = false;  // quadtree keys are integers: exact on every device
    } else if (r.info.z == layout::kRayShadow) {
      const int dir_bits = h.polar_bits + h.azimuth_bits;
      const std::uint32_t light = std::min(r.info.w, LowBits(h.light_bits));
      ok = High(key, dir_bits) == light &&
           DirectionAllowed(key & LowBits(dir_bits), emu::Xyz(r.direction_tmax), h.polar_bits, h.azimuth_bits, h.order);
    } else {
      const int dir_bits = 2 * h.direction_bits;
      const V lo = Spec3(c.scene->lo), ext = Spec3(c.scene->hi) - lo, rel = Spec3(emu::Xyz(r.origin_tmin)) - lo;
      const std::uint32_t cells = High(key, dir_bits);
      ok = High(cells, 3 * h.origin_bits) == 0u &&
           DirectionAllowed(key & LowBits(dir_bits), emu::Xyz(r.direction_tmax), h.direction_bits, h.direction_bits, h.order);
      for (int axis = 0; axis < 3; ++axis) {
        std::uint32_t cell = 0;  // emu Interleave3: x, y, z bits from the top
        for (int b = h.origin_bits - 1; b >= 0; --b) cell |= ((cells >> (3 * b + 2 - axis)) & 1u) << b;
        ok = ok && Cells(rel[axis] / ext[axis], h.origin_bits, false).Holds(cell);
      }
    }
    if (ok)
      t.Within();
    else
      t.Beyond(fmt::format("keys[{}]: {:#010x} names cells no permitted evaluation reaches (emulator {:#010x})", i, key, expected));
  }, c.rays.size());
}

// ---- surfaces -----------------------------------------------------------------------------------

using SurfaceWords = std::array<std::uint32_t, 20>;  // position, normal, incoming, weight, info

// A differing surface: every word is the emulator's except those a device computes with rounding,
// which `ranges` bounds (index -> interval).
void TallySurface(std::size_t i, const SurfaceWords& ew, const SurfaceWords& aw,
                  const std::vector<std::pair<std::size_t, SpecReal>>& ranges, Tally& t) {
  std::array<Word, 20> words;
  for (std::size_t w = 0; w < 20; ++w) words[w] = ExactU(ew[w]);
  for (const auto& [w, r] : ranges) {
    // The model's exact evaluation must be the emulator's: otherwise it no longer mirrors the pass.
    if (!r.any && std::bit_cast<std::uint32_t>(r.v) != ew[w]) {
      t.Beyond(fmt::format("surfaces[{}] word {}: the relaxed model disagrees with the emulator", i, w));
      return;
    }
    words[w] = Range(r);
  }
  for (std::size_t w = 0; w < 20; ++w)
    if (!words[w].Allows(aw[w])) {
      t.Beyond(fmt::format("surfaces[{}] word {}: {} outside {}", i, w, Show(std::bit_cast<float>(aw[w])), words[w].Describe()));
      return;
    }
  t.Within();
}

template <typename ModelFn>
SpecVerdict Surfaces(const BufferSet& e, const BufferSet& a, bool flush, ModelFn&& model) {
  return ForEachDiffering<layout::Surface>(e, a, "surfaces", [&](std::size_t i, const layout::Surface& es,
                                                                 const layout::Surface& as, Tally& t) {
    ScopedSpecTrace trace(flush);
    std::vector<std::pair<std::size_t, SpecReal>> ranges = model(i);
    if (trace.trace().ambiguous)  // a decision may go the other way: the computed words are unbounded
      for (auto& r : ranges) r.second = SpecReal::Unbounded(r.second.v);
    TallySurface(i, std::bit_cast<SurfaceWords>(es), std::bit_cast<SurfaceWords>(as), ranges, t);
  });
}

void AddVector(std::vector<std::pair<std::size_t, SpecReal>>& ranges, std::size_t first, const V& v) {
  for (int k = 0; k < 3; ++k) ranges.emplace_back(first + static_cast<std::size_t>(k), v[k]);
}

SpecVerdict SurfacesFromGBuffer(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::SurfacesFromGBuffer> d = DecodeCall<emu::call::SurfacesFromGBuffer>(in);
  const emu::call::SurfacesFromGBuffer& c = d.call;
  const layout::FrameConstants& f = c.frame;
  return Surfaces(e, a, flush, [&](std::size_t i) {
    std::vector<std::pair<std::size_t, SpecReal>> ranges;
    if (c.prim[i] == layout::kNoPrim) return ranges;
    // PixelDirection (rayspace/kernel_functions.h) in SpecReal: (origin + px dx) + py dy.
    const R fx(static_cast<float>(i % f.dims.x)), fy(static_cast<float>(i / f.dims.x));
    V dir;
    for (int k = 0; k < 3; ++k) dir[k] = (R(f.pixel_origin[k]) + fx * R(f.pixel_dx[k])) + fy * R(f.pixel_dy[k]);
    AddVector(ranges, 8, emu::Normalize(dir));
    return ranges;
  });
}

SpecVerdict SurfacesFromHits(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::SurfacesFromHits> d = DecodeCall<emu::call::SurfacesFromHits>(in);
  const emu::call::SurfacesFromHits& c = d.call;
  return Surfaces(e, a, flush, [&](std::size_t i) {
    std::vector<std::pair<std::size_t, SpecReal>> ranges;
    const std::uint64_t h = c.hits[i];
    if (h == emu::kMissPacked) return ranges;
    const layout::Ray& r = c.rays[i];
    const R t(emu::HitT(h));
    const V o = Spec3(emu::Xyz(r.origin_tmin)), dir = Spec3(emu::Xyz(r.direction_tmax));
    const V p(o.x + t * dir.x, o.y + t * dir.y, o.z + t * dir.z);
    AddVector(ranges, 0, p);
    AddVector(ranges, 4, emu::ShadingNormalOf(*c.scene, emu::HitPrim(h), p));
    AddVector(ranges, 8, emu::Normalize(dir));
    return ranges;
  });
}

// ---- traverse -----------------------------------------------------------------------------------

// Could some conformant device decide the cone-sphere test the other way? (Only then may its flag
// differ: a test whose every decision is certain gives lavapipe's answer everywhere.)
bool TestMayFlip(const layout::ConeNode& n, glm::vec4 sphere, float eps, std::uint32_t cone_test, bool flush) {
  ScopedSpecTrace trace(flush);
  if (cone_test == layout::kConeTestPrinted)
    (void)emu::cone::PrintedTestOf<SpecReal>(n, sphere, eps);
  else if (cone_test == layout::kConeTestPrintedSigned)
    (void)emu::cone::PrintedTestOf<SpecReal, true>(n, sphere, eps);
  else
    (void)emu::cone::TestOf<SpecReal>(n, sphere, eps);
  return trace.trace().ambiguous != 0;
}

// Differing flags of one traversal call: `test_of(slot, node, sphere)` names the test a slot ran,
// or returns false when the slot runs none (its flag must then be 0 on every device).
template <typename TestOfSlot>
void TallyFlags(const std::vector<std::uint8_t>& ef, const std::vector<std::uint8_t>& af, float eps, std::uint32_t cone_test,
                bool flush, Tally& t, const std::string& name, TestOfSlot&& test_of) {
  if (ef.size() != af.size()) {
    t.Beyond(name + ": sizes differ");
    return;
  }
  for (std::size_t i = 0; i < ef.size(); ++i) {
    if (ef[i] == af[i]) continue;
    const layout::ConeNode* node = nullptr;
    glm::vec4 sphere;
    const bool runs = test_of(i, node, sphere);
    if (runs && af[i] <= 1u && TestMayFlip(*node, sphere, eps, cone_test, flush))
      t.Within();
    else
      t.Beyond(fmt::format("{}[{}]: {} where every conformant device gives {}", name, i, af[i], ef[i]));
  }
}

// The integer outputs of a traversal call (pair values, tests run) are exact on every device.
void TallyExact(const BufferSet& e, const BufferSet& a, Tally& t) {
  if (e.Has("values") && e.Get<std::uint32_t>("values") != a.Get<std::uint32_t>("values")) t.Beyond("values: pair ids are integers");
  if (e.Has("tested") && e.Get<std::uint8_t>("tested") != a.Get<std::uint8_t>("tested")) t.Beyond("tested: counts are integers");
}

SpecVerdict TraverseTop(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TraverseTop> d = DecodeCall<emu::call::TraverseTop>(in);
  const emu::call::TraverseTop& c = d.call;
  Tally t;
  TallyExact(e, a, t);
  const std::uint32_t tris = c.b1 - c.b0;
  TallyFlags(e.Get<std::uint8_t>("flags"), a.Get<std::uint8_t>("flags"), c.eps, c.cone_test, flush, t, "flags",
             [&](std::size_t slot, const layout::ConeNode*& node, glm::vec4& sphere) {
               const std::uint32_t n = c.t0 + static_cast<std::uint32_t>(slot / tris), tri = c.b0 + static_cast<std::uint32_t>(slot % tris);
               if (!emu::TopSlotTested(c, n, tri)) return false;
               node = &c.top[n];
               sphere = c.tri_spheres[tri];
               return true;
             });
  return t.Done();
}

SpecVerdict TraverseLevel(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TraverseLevel> d = DecodeCall<emu::call::TraverseLevel>(in);
  const emu::call::TraverseLevel& c = d.call;
  Tally t;
  TallyExact(e, a, t);
  TallyFlags(e.Get<std::uint8_t>("flags"), a.Get<std::uint8_t>("flags"), c.eps, c.cone_test, flush, t, "flags",
             [&](std::size_t slot, const layout::ConeNode*& node, glm::vec4& sphere) {
               const std::size_t p = slot / c.children_max;
               const std::uint32_t parent = c.base_up + (c.pairs[p] >> emu::kPairTriangleBits);
               const std::uint32_t k = c.first[parent] + static_cast<std::uint32_t>(slot % c.children_max);
               if (k >= c.first[parent + 1]) return false;
               node = &c.nodes[k];
               sphere = c.tri_spheres[c.b0 + (c.pairs[p] & emu::kPairTriangleMask)];
               return true;
             });
  return t.Done();
}

// The survivors of a fused traversal call (traverse.compact.*): a compacted list in slot order, where
// traverse.top/level keep a flag per slot. `each_slot(visit)` calls visit(pair, node, sphere) for
// every slot that runs a test, in slot order. The device's list must hold, in that order, every pair
// the emulator keeps and no other, except that a slot whose test some conformant device decides the
// other way may be in or out; the count of tests run is an integer, exact everywhere.
template <typename EachSlot>
SpecVerdict TallyCompacted(const BufferSet& e, const BufferSet& a, float eps, std::uint32_t cone_test, bool flush, EachSlot&& each_slot) {
  Tally t;
  if (e.Has("tested") && e.Get<std::uint64_t>("tested") != a.Get<std::uint64_t>("tested")) t.Beyond("tested: counts are integers");
  const std::vector<std::uint32_t> ep = e.Get<std::uint32_t>("pairs"), ap = a.Get<std::uint32_t>("pairs");
  std::size_t i = 0, j = 0;
  each_slot([&](std::uint32_t pair, const layout::ConeNode& node, glm::vec4 sphere) {
    const bool kept = i < ep.size() && ep[i] == pair, device = j < ap.size() && ap[j] == pair;
    i += kept, j += device;
    if (kept == device) return;
    if (TestMayFlip(node, sphere, eps, cone_test, flush))
      t.Within();
    else
      t.Beyond(fmt::format("pairs: {:#x} {} where every conformant device {} it", pair, device ? "kept" : "dropped",
                           device ? "drops" : "keeps"));
  });
  if (j < ap.size()) t.Beyond(fmt::format("pairs[{}]: {:#x} is no tested slot's pair in slot order", j, ap[j]));
  if (i < ep.size()) t.Beyond(fmt::format("pairs: the emulator's pair {:#x} is no tested slot's in slot order", ep[i]));
  return t.Done();
}

SpecVerdict TraverseTopCompacted(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TraverseTop> d = DecodeCall<emu::call::TraverseTop>(in);
  const emu::call::TraverseTop& c = d.call;
  return TallyCompacted(e, a, c.eps, c.cone_test, flush, [&](auto&& visit) {
    for (std::uint32_t node = c.t0; node < c.t1; ++node)
      for (std::uint32_t tri = c.b0; tri < c.b1; ++tri)
        if (emu::TopSlotTested(c, node, tri))
          visit(((node - c.t0) << emu::kPairTriangleBits) | (tri - c.b0), c.top[node], c.tri_spheres[tri]);
  });
}

SpecVerdict TraverseLevelCompacted(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TraverseLevel> d = DecodeCall<emu::call::TraverseLevel>(in);
  const emu::call::TraverseLevel& c = d.call;
  return TallyCompacted(e, a, c.eps, c.cone_test, flush, [&](auto&& visit) {
    for (const std::uint32_t pair : c.pairs) {
      const std::uint32_t parent = c.base_up + (pair >> emu::kPairTriangleBits), tri_local = pair & emu::kPairTriangleMask;
      for (std::uint32_t k = c.first[parent]; k < c.first[parent + 1]; ++k)
        visit(((k - c.base) << emu::kPairTriangleBits) | tri_local, c.nodes[k], c.tri_spheres[c.b0 + tri_local]);
    }
  });
}

SpecVerdict ObjectMask(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::ObjectMask> d = DecodeCall<emu::call::ObjectMask>(in);
  const emu::call::ObjectMask& c = d.call;
  Tally t;
  const std::size_t objects = c.object_spheres.size();
  TallyFlags(e.Get<std::uint8_t>("mask"), a.Get<std::uint8_t>("mask"), c.eps, c.cone_test, flush, t, "mask",
             [&](std::size_t slot, const layout::ConeNode*& node, glm::vec4& sphere) {
               node = &c.top[slot / objects];
               sphere = c.object_spheres[slot % objects];
               return true;
             });
  return t.Done();
}

// ---- build ---------------------------------------------------------------------------------------

using SpecNode = emu::cone::NodeOf<SpecReal>;
using NodeWords = std::array<std::uint32_t, 12>;  // sphere, cone, extra

SpecNode ToSpec(const layout::ConeNode& n) {
  SpecNode s;
  for (int k = 0; k < 4; ++k) {
    s.sphere[k] = R(n.sphere[k]);
    s.cone[k] = R(n.cone[k]);
    s.extra[k] = R(n.extra[k]);
  }
  return s;
}

// Differing nodes of a build call, each modelled by `model(i)` (the emulator's fold in SpecReal).
// After a decision a permitted rounding may flip (a ray on the cone's edge, a child on the sphere's
// surface) the fold no longer bounds the words; the device's node must then still do what a node
// is for, decided exactly (refs/ exact_cone.h): `contains(i, node)` holds every ray or child below.
template <typename ModelFn, typename ContainsFn>
SpecVerdict Nodes(const BufferSet& e, const BufferSet& a, bool flush, ModelFn&& model, ContainsFn&& contains) {
  return ForEachDiffering<layout::ConeNode>(e, a, "nodes", [&](std::size_t i, const layout::ConeNode& en,
                                                               const layout::ConeNode& an, Tally& t) {
    const auto ew = std::bit_cast<NodeWords>(en), aw = std::bit_cast<NodeWords>(an);
    ScopedSpecTrace trace(flush);
    const SpecNode m = model(i);
    const bool flips = trace.trace().ambiguous != 0;
    std::string bad;
    for (std::size_t w = 0; w < 12 && bad.empty(); ++w) {
      const SpecReal r = w < 4 ? m.sphere[static_cast<int>(w)] : (w < 8 ? m.cone[static_cast<int>(w - 4)] : m.extra[static_cast<int>(w - 8)]);
      const bool exact_word = w >= 9;  // the ray count and the unused words
      if (!flips && !r.any && std::bit_cast<std::uint32_t>(r.v) != ew[w])
        bad = fmt::format("nodes[{}] word {}: the relaxed model disagrees with the emulator", i, w);
      else if (exact_word ? aw[w] != ew[w] : !(flips || r.Allows(std::bit_cast<float>(aw[w]))))
        bad = fmt::format("nodes[{}] word {}: {} outside {}", i, w, Show(std::bit_cast<float>(aw[w])),
                          exact_word ? fmt::format("{:#010x}", ew[w]) : Range(r).Describe());
    }
    std::string why;
    if (bad.empty() && flips && !contains(i, an, why))
      bad = fmt::format("nodes[{}]: a decision may flip, but the node does not hold what is below it: {}", i, why);
    if (bad.empty())
      t.Within();
    else
      t.Beyond(bad);
  });
}

SpecVerdict BuildLeaves(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::BuildLeaves> d = DecodeCall<emu::call::BuildLeaves>(in);
  const emu::call::BuildLeaves& c = d.call;
  return Nodes(
      e, a, flush,
      [&](std::size_t i) {
        return emu::cone::LeafNodeOf<SpecReal>(c.first[i + 1] - c.first[i],
                                               [&](std::uint32_t k) -> const layout::Ray& { return c.rays[c.order[c.first[i] + k]]; });
      },
      [&](std::size_t i, const layout::ConeNode& n, std::string& why) {
        for (std::uint32_t k = c.first[i]; k < c.first[i + 1]; ++k) {
          const layout::Ray& r = c.rays[c.order[k]];
          if (!refs::ExactNodeContainsRay(n, emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax), &why)) return false;
        }
        return true;
      });
}

SpecVerdict BuildParents(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::BuildParents> d = DecodeCall<emu::call::BuildParents>(in);
  const emu::call::BuildParents& c = d.call;
  return Nodes(
      e, a, flush,
      [&](std::size_t i) {
        std::vector<SpecNode> children;
        for (std::uint32_t k = c.first[i]; k < c.first[i + 1]; ++k) children.push_back(ToSpec(c.below[k]));
        return emu::cone::ParentNode(children.data(), static_cast<std::uint32_t>(children.size()), c.child_merge);
      },
      [&](std::size_t i, const layout::ConeNode& n, std::string& why) {
        for (std::uint32_t k = c.first[i]; k < c.first[i + 1]; ++k)
          if (!refs::ExactNodeContains(n, c.below[k], &why)) return false;
        return true;
      });
}

// ---- shade ---------------------------------------------------------------------------------------

// The fixed-point contribution (emu ToFixed: clamp to [0, kAccumMax], scale by 2^32, truncate) of
// every permitted colour value: [lo, hi], or nothing known.
bool FixedRange(SpecReal c, std::uint64_t& lo, std::uint64_t& hi) {
  const SpecReal v = Clamp(c, R(0.0f), R(layout::kAccumMax)) * R(layout::kAccumScale);
  if (v.any) return false;
  lo = static_cast<std::uint64_t>(v.lo);
  hi = static_cast<std::uint64_t>(v.hi);
  return true;
}

SpecVerdict Shade(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::Shade> d = DecodeCall<emu::call::Shade>(in);
  const emu::call::Shade& c = d.call;
  const auto ea = e.Get<std::uint64_t>("accum"), aa = a.Get<std::uint64_t>("accum");
  const std::vector<std::uint64_t>& before = *c.accum;
  Tally t;
  if (ea.size() != aa.size() || ea.size() != before.size()) {
    t.Beyond("accum: sizes differ");
    return t.Done();
  }
  // The surfaces shading each differing pixel (integer sums: the order of addition does not matter).
  std::unordered_map<std::uint32_t, std::vector<std::size_t>> by_pixel;
  for (std::size_t i = 0; i < ea.size(); ++i)
    if (ea[i] != aa[i]) by_pixel[static_cast<std::uint32_t>(i / 3)];
  for (std::size_t s = 0; s < c.surfaces.size(); ++s)
    if (c.surfaces[s].position.w != 0.0f)
      if (auto it = by_pixel.find(c.surfaces[s].info.y); it != by_pixel.end()) it->second.push_back(s);
  const std::size_t slots = ShadowSlots(c.scene->lights);
  for (std::size_t i = 0; i < ea.size(); ++i) {
    if (ea[i] == aa[i]) continue;
    std::uint64_t lo = before[i], hi = before[i];
    bool bounded = true;
    for (std::size_t s : by_pixel[static_cast<std::uint32_t>(i / 3)]) {
      ScopedSpecTrace trace(flush);
      const layout::Surface& sf = c.surfaces[s];
      const V color = emu::ShadeColorOf<SpecReal>(*c.scene, sf, [&](std::size_t j) {
        const std::size_t slot = s * slots + j;
        return c.shadow_flags[slot] && !c.occluded[c.shadow_offsets[slot]];
      });
      std::uint64_t qlo, qhi;
      const int k = static_cast<int>(i % 3);
      if (trace.trace().ambiguous || !FixedRange(color[k] * R(sf.weight[k]), qlo, qhi)) {
        bounded = false;  // a decision may go the other way: any non-negative contribution
        break;
      }
      lo += qlo;
      hi += qhi;
    }
    // Contributions are never negative, so the sum never falls below what was there.
    if (bounded ? (lo <= aa[i] && aa[i] <= hi) : aa[i] >= before[i])
      t.Within();
    else
      t.Beyond(fmt::format("accum[{}]: {} outside [{}, {}]", i, aa[i], lo, hi));
  }
  return t.Done();
}

// ---- resolve --------------------------------------------------------------------------------------

SpecVerdict Resolve(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const auto accum = in.Get<std::uint64_t>("accum");
  return ForEachDiffering<std::uint8_t>(
      e, a, "rgb",
      [&](std::size_t i, std::uint8_t, std::uint8_t actual, Tally& t) {
        ScopedSpecTrace trace(flush);
        const R v = SpecReal::FromInteger(accum[i]) / R(layout::kAccumScale);
        const R x = Sqrt(Clamp(v, R(0.0f), R(1.0f))) * R(255.0f) + R(0.5f);
        // uint(x) truncates: the permitted bytes are those of every float in [lo, hi].
        if (x.any || (std::floor(x.lo) <= actual && actual <= std::floor(x.hi)))
          t.Within();
        else
          t.Beyond(fmt::format("rgb[{}]: {} outside [{}, {}]", i, actual, std::floor(x.lo), std::floor(x.hi)));
      },
      accum.size());
}

}  // namespace

std::string SpecVerdict::Summary() const {
  if (!modelled) return "no relaxed model: every word must match";
  std::string s = fmt::format("{} element(s) within the spec's precision, {} beyond", within, beyond);
  if (beyond) s += "; first: " + first_beyond;
  return s;
}

SpecVerdict ClassifyWithinSpec(const std::string& method, const BufferSet& in, const BufferSet& expected,
                               const BufferSet& actual, bool flush_denormals) {
  if (method == "raygen") return Raygen(in, expected, actual, flush_denormals);
  if (method == "intersect") return Intersect(in, expected, actual, flush_denormals);
  if (method == "intersect.tree") return IntersectTree(in, expected, actual, flush_denormals);
  if (method == "resolve") return Resolve(in, expected, actual, flush_denormals);
  if (method == "hash") return Hash(in, expected, actual, flush_denormals);
  if (method == "shade") return Shade(in, expected, actual, flush_denormals);
  if (method == "build.leaves") return BuildLeaves(in, expected, actual, flush_denormals);
  if (method == "build.parents") return BuildParents(in, expected, actual, flush_denormals);
  if (method == "surfaces") return SurfacesFromGBuffer(in, expected, actual, flush_denormals);
  if (method == "surfaces.hits") return SurfacesFromHits(in, expected, actual, flush_denormals);
  if (method == "traverse.top") return TraverseTop(in, expected, actual, flush_denormals);
  if (method == "traverse.level") return TraverseLevel(in, expected, actual, flush_denormals);
  if (method == "traverse.compact.top") return TraverseTopCompacted(in, expected, actual, flush_denormals);
  if (method == "traverse.compact.level") return TraverseLevelCompacted(in, expected, actual, flush_denormals);
  if (method == "traverse.objects") return ObjectMask(in, expected, actual, flush_denormals);
  if (method.starts_with("tree.")) return ClassifyTree(method, in, expected, actual, flush_denormals);
  if (method == "tl.lists") return ClassifyTlLists(in, expected, actual, flush_denormals);
  if (method == "tl.heads") return ClassifyTlHeads(in, expected, actual, flush_denormals);
  if (method == "tl.cells") return ClassifyTlCells(in, expected, actual, flush_denormals);
  // The raster's fragment words alone (the differ adds the coverage verdict on edges).
  if (method == "raster.fragments") return ClassifyRasterFragments(in, expected, actual, flush_denormals);
  if (method == "raster.flips") return ClassifyRasterFlips(in, expected, actual, flush_denormals);
  if (method == "grid.trace") return ClassifyGridTrace(in, expected, actual, flush_denormals);
  if (method == "grid.count") return ClassifyGridCount(in, expected, actual, flush_denormals);
  if (method == "tl.trace") return ClassifyTlTrace(in, expected, actual, flush_denormals);
  return {};
}

}  // namespace rayspace::verify
