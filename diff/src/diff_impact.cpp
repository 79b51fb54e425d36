#include "rayspace/diff/diff_impact.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <unordered_map>
#include <utility>

#include <fmt/format.h>

#include "rayspace/emu/intersect.h"
#include "rayspace/refs/oracle.h"

namespace rayspace::app {
namespace {

// Exact judgement costs a pass over every triangle per ray; a fault that changes most of a large
// frame is judged on a prefix, and the report says how many.
constexpr std::size_t kMaxJudged = 5000;
constexpr std::size_t kMaxListed = 10;
constexpr std::size_t kNone = ~std::size_t{0};

// One traced batch: closest-hit batches keep the primitive (kNoPrim for a miss), shadow batches
// 1 for occluded and 0 for lit; the distance is left out, so that a ray moved by an earlier
// change counts only when it meets another triangle.
struct Captured {
  std::vector<layout::Ray> rays;
  std::vector<std::uint32_t> hits;
  bool shadow = false;
  std::vector<std::uint64_t> tests;  // the batch's final tests as (ray << 32 | triangle), sorted, unique
};

struct SideFrame {
  emu::FrameResult result;
  std::vector<std::pair<std::string, Captured>> batches;  // in the frame's order
  bool logged = false;  // the tracer logged final tests
};

Captured Capture(const emu::Batch& b) {
  Captured c;
  c.rays = *b.rays;
  c.shadow = b.occluded != nullptr;
  if (c.shadow) {
    for (std::uint32_t o : *b.occluded) c.hits.push_back(o != 0);
  } else {
    for (std::uint64_t h : *b.hits) c.hits.push_back(h == emu::kMissPacked ? layout::kNoPrim : emu::HitPrim(h));
  }
  return c;
}

SideFrame RenderSide(const Scene& scene, const SceneBuffers& buffers, emu::FrameOptions fo, const ImpactTracerFactory& make,
                     ImpactSide side) {
  SideFrame f;
  fo.passes = side.frame;
  std::vector<std::uint64_t> log;
  const std::unique_ptr<Tracer> tracer = make(*side.hierarchy, &log);
  // The observer sees each batch right after its trace: the log since the last batch is this one's.
  std::size_t logged = 0;
  f.result = emu::RenderFrame(scene, buffers, *tracer, fo, [&](const emu::Batch& b) {
    Captured c = Capture(b);
    c.tests.assign(log.begin() + static_cast<std::ptrdiff_t>(logged), log.end());
    std::sort(c.tests.begin(), c.tests.end());
    c.tests.erase(std::unique(c.tests.begin(), c.tests.end()), c.tests.end());
    logged = log.size();
    f.batches.emplace_back(b.name, std::move(c));
  });
  f.logged = !log.empty();
  return f;
}

// The Vulkan side's ray for each emulator ray: the one of the same pixel and light (shadow) or
// surface slot, the n-th such with the n-th, so that a ray one side dropped or added shifts no other.
std::vector<std::size_t> MatchRays(const std::vector<layout::Ray>& e, const std::vector<layout::Ray>& v) {
  const auto key = [](const layout::Ray& r) { return (static_cast<std::uint64_t>(r.info.x) << 32) | r.info.w; };
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> by_key;
  for (std::size_t i = 0; i < v.size(); ++i) by_key[key(v[i])].push_back(i);
  std::unordered_map<std::uint64_t, std::size_t> seen;
  std::vector<std::size_t> match(e.size(), kNone);
  for (std::size_t i = 0; i < e.size(); ++i) {
    const auto it = by_key.find(key(e[i]));
    const std::size_t n = seen[key(e[i])]++;
    if (it != by_key.end() && n < it->second.size()) match[i] = it->second[n];
  }
  return match;
}

// A faulty kernel's ray may be garbage (not finite, or beyond what exact arithmetic takes): no
// answer for it is right. Reflection and refraction rays run to tmax = +inf.
refs::Answer Judge(const Captured& c, std::size_t i, const SceneBuffers& scene) {
  const layout::Ray& r = c.rays[i];
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(r.origin_tmin[k]) || !std::isfinite(r.direction_tmax[k])) return refs::Answer::kWrong;
  if (std::isnan(r.origin_tmin.w) || std::isnan(r.direction_tmax.w)) return refs::Answer::kWrong;  // tmax may be +inf
  try {
    return c.shadow ? refs::JudgeOccluded(r, c.hits[i] != 0, scene) : refs::JudgeClosest(r, c.hits[i], scene);
  } catch (const std::exception&) {
    return refs::Answer::kWrong;
  }
}

// Which side the exact oracle says is right: one of them, both (exactly, as at a tie or when each
// is right for its own ray), both only within rounding, or neither.
std::string Verdict(refs::Answer e, refs::Answer v) {
  const bool er = e != refs::Answer::kWrong, vr = v != refs::Answer::kWrong;
  if (er && vr) return e == refs::Answer::kExact && v == refs::Answer::kExact ? "both" : "within_rounding";
  return er ? "emulator" : vr ? "vulkan" : "neither";
}

// Would the final pass's test of `ray` against triangle `prim` hit? (PassIntersect's test and its
// rule that a ray never hits the surface it leaves.)
bool TestHits(const layout::Ray& r, std::uint32_t prim, const SceneBuffers& scene) {
  if (prim >= scene.triangles.size() || prim == r.info.y) return false;
  const layout::Triangle& t = scene.triangles[prim];
  float th = 0.0f;
  return emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax)), emu::Xyz(t.v0),
                                  emu::Xyz(t.v1), emu::Xyz(t.v2), r.origin_tmin.w, r.direction_tmax.w, th);
}

// The emulator's final tests the Vulkan side did not run on the matched ray, and the other way round.
void CompareTests(const std::string& name, const Captured& e, const Captured& v, const std::vector<std::size_t>& match,
                  const SceneBuffers& scene, LostTests& out) {
  std::vector<std::uint64_t> mapped;  // the emulator's tests under the Vulkan side's ray indices
  std::vector<bool> matched(v.rays.size(), false);
  for (std::size_t i = 0; i < match.size(); ++i)
    if (match[i] != kNone) matched[match[i]] = true;
  for (const std::uint64_t t : e.tests) {
    const std::size_t i = t >> 32, j = i < match.size() ? match[i] : kNone;
    if (j == kNone) continue;  // a ray on one side only is counted as such
    const std::uint64_t key = (static_cast<std::uint64_t>(j) << 32) | (t & 0xffffffffu);
    mapped.push_back(key);
    if (std::binary_search(v.tests.begin(), v.tests.end(), key)) continue;
    ++out.lost;
    const auto prim = static_cast<std::uint32_t>(t);
    if (!TestHits(e.rays[i], prim, scene)) continue;
    if (out.lost_hitting++ == 0) out.first_hitting = fmt::format("{} ray {}, triangle {}", name, i, prim);
  }
  std::sort(mapped.begin(), mapped.end());
  for (const std::uint64_t t : v.tests)
    if ((t >> 32) < matched.size() && matched[t >> 32] && !std::binary_search(mapped.begin(), mapped.end(), t)) ++out.added;
}

bool SameRay(const layout::Ray& a, const layout::Ray& b) { return std::memcmp(&a, &b, sizeof(layout::Ray)) == 0; }

void CompareBatch(const std::string& name, const Captured& e, const Captured& v, const SceneBuffers& scene, DiffImpact& out) {
  const std::vector<std::size_t> match = MatchRays(e.rays, v.rays);
  std::size_t matched = 0;
  for (std::size_t i = 0; i < e.rays.size(); ++i) {
    const std::size_t j = match[i];
    if (j == kNone) continue;
    ++matched;
    if (e.hits[i] == v.hits[j]) continue;
    ++out.rays_changed;
    if (out.judged == kMaxJudged) continue;
    ++out.judged;
    ChangedRay c{name, i, e.hits[i], v.hits[j], SameRay(e.rays[i], v.rays[j]), {}};
    c.verdict = Verdict(Judge(e, i, scene), Judge(v, j, scene));
    ++out.verdicts[c.verdict];
    if (out.first.size() < kMaxListed) out.first.push_back(std::move(c));
  }
  const std::size_t one_side = (e.rays.size() - matched) + (v.rays.size() - matched);
  out.one_side_only += one_side;
  out.rays_changed += one_side;
  CompareTests(name, e, v, match, scene, out.tests);
}

std::size_t CountDiffering(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
  return n;
}

std::size_t PixelsDiffering(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size()) / 3;
  std::size_t n = 0;
  for (std::size_t p = 0; p + 2 < a.size(); p += 3) n += a[p] != b[p] || a[p + 1] != b[p + 1] || a[p + 2] != b[p + 2];
  return n;
}

void Compare(const SideFrame& e, const SideFrame& v, const SceneBuffers& scene, DiffImpact& out) {
  out.tests.logged = e.logged && v.logged;
  std::unordered_map<std::string, const Captured*> vb;
  for (const auto& [name, c] : v.batches) vb[name] = &c;
  for (const auto& [name, c] : e.batches) {
    out.rays += c.rays.size();
    const auto it = vb.find(name);
    if (it == vb.end()) {
      out.one_side_only += c.rays.size();
      out.rays_changed += c.rays.size();
      continue;
    }
    CompareBatch(name, c, *it->second, scene, out);
    vb.erase(it);
  }
  for (const auto& [name, c] : vb) {
    out.one_side_only += c->rays.size();
    out.rays_changed += c->rays.size();
  }
  out.primary_changed = CountDiffering(e.result.gbuffer.prim, v.result.gbuffer.prim);
  out.pixels_changed = PixelsDiffering(e.result.rgb, v.result.rgb);
}

// One side's frame, or "" in `failed` with why it could not be made (a faulty kernel may leave the
// frame's host side indices it refuses).
bool TryRenderSide(const char* who, const Scene& scene, const SceneBuffers& buffers, emu::FrameOptions fo,
                   const ImpactTracerFactory& make, ImpactSide side, SideFrame& f, std::string& failed) {
  fo.progress_label = fmt::format("impact, the {} alone", who);
  try {
    f = RenderSide(scene, buffers, fo, make, side);
    return true;
  } catch (const std::exception& e) {
    failed = fmt::format("the {}'s frame failed: {}", who, e.what());
    return false;
  }
}

std::string HitText(std::uint32_t hit, bool shadow) {
  if (shadow) return hit ? "occluded" : "lit";
  return hit == layout::kNoPrim ? "miss" : fmt::format("triangle {}", hit);
}

std::string VerdictText(const std::string& verdict, const std::string& actual) {
  if (verdict == "emulator") return "the emulator is right";
  if (verdict == "vulkan") return actual + " is right";  // the actual side, whichever backend it is
  if (verdict == "both") return "both are right";
  if (verdict == "within_rounding") return "both are right within rounding";
  return "neither is right";
}

bool IsShadow(const ChangedRay& c) { return c.batch.rfind("shadow.", 0) == 0; }

}  // namespace

DiffImpact MeasureImpact(const Scene& scene, const SceneBuffers& buffers, emu::FrameOptions fo, const ImpactTracerFactory& tracer,
                         ImpactSide emu_side, ImpactSide vulkan_side) {
  DiffImpact out;
  out.actual = vulkan_side.frame->Name();
  SideFrame e, v;
  if (!TryRenderSide("emulator", scene, buffers, fo, tracer, emu_side, e, out.failed)) return out;
  if (!TryRenderSide((out.actual + " backend").c_str(), scene, buffers, fo, tracer, vulkan_side, v, out.failed)) return out;
  Compare(e, v, buffers, out);
  return out;
}

namespace {

// "final ray-triangle tests: ..." when the Vulkan side's frame ran fewer or other final tests than the emulator's.
void PrintLostTests(std::FILE* out, const LostTests& t, bool no_hit_changed, const std::string& actual) {
  if (!t.logged || (t.lost == 0 && t.added == 0)) return;
  std::fprintf(out, "    final ray-triangle tests: the %s side's frame lost %zu of the emulator's and added %zu; ", actual.c_str(), t.lost,
               t.added);
  if (t.lost == 0)
    std::fprintf(out, "none lost\n");
  else if (t.lost_hitting == 0)
    std::fprintf(out, "no lost test meets its triangle, so the loss changes no hit in this frame\n");
  else
    std::fprintf(out, "%zu lost tests meet their triangle (first: %s): hits the loss can take away%s\n", t.lost_hitting,
                 t.first_hitting.c_str(), no_hit_changed ? ", hidden in this frame by closer hits or other occluders" : "");
}

}  // namespace

void PrintImpact(std::FILE* out, const DiffImpact& m) {
  if (!m.failed.empty()) {
    std::fprintf(out, "  impact: not measured: %s\n", m.failed.c_str());
    return;
  }
  if (m.NoVisibleChange()) {
    std::fprintf(out, "  impact: no ray's final hit and no pixel changes in this frame (the frame on each backend alone); "
                      "not proven benign: %s%s\n",
                 m.differed.empty() ? "the divergent call's outputs differ" : m.differed.front().c_str(),
                 m.differed.size() > 1 ? fmt::format(" (and {} more buffers)", m.differed.size() - 1).c_str() : "");
    PrintLostTests(out, m.tests, true, m.actual);
    return;
  }
  const auto count = [&m](const char* k) { return m.verdicts.count(k) ? m.verdicts.at(k) : std::size_t{0}; };
  std::string others;
  for (const char* k : {"both", "within_rounding", "neither"})
    if (count(k)) others += fmt::format(", {} on {}", k == std::string("within_rounding") ? "within rounding" : k, count(k));
  if (m.rays_changed == 0)
    std::fprintf(out, "  impact: no ray's final hit changes, %zu pixels change", m.pixels_changed);
  else
    std::fprintf(out, "  impact: %zu of %zu rays change their final hit (emulator right on %zu, %s on %zu%s), %zu pixels change",
                 m.rays_changed, m.rays, count("emulator"), m.actual.c_str(), count("vulkan"), others.c_str(), m.pixels_changed);
  if (m.primary_changed) std::fprintf(out, ", %zu primary hits (raster) change", m.primary_changed);
  if (m.one_side_only) std::fprintf(out, "; %zu rays traced by one side only", m.one_side_only);
  if (m.judged + m.one_side_only < m.rays_changed) std::fprintf(out, "; the oracle judged the first %zu", m.judged);
  std::fprintf(out, "\n");
  if (!m.first.empty()) {
    const ChangedRay& c = m.first.front();
    std::fprintf(out, "    first: %s ray %zu: emulator %s, %s %s: %s\n", c.batch.c_str(), c.ray, HitText(c.emu, IsShadow(c)).c_str(),
                 m.actual.c_str(), HitText(c.vulkan, IsShadow(c)).c_str(), VerdictText(c.verdict, m.actual).c_str());
  }
  PrintLostTests(out, m.tests, false, m.actual);
}

namespace {

nlohmann::json FinalTestsJson(const LostTests& t) {
  if (!t.logged) return nullptr;
  return {{"lost", t.lost}, {"added", t.added}, {"lost_meeting_triangle", t.lost_hitting},
          {"first_lost_meeting_triangle", t.first_hitting.empty() ? nlohmann::json(nullptr) : nlohmann::json(t.first_hitting)}};
}

}  // namespace

nlohmann::json ImpactJson(const DiffImpact& m) {
  if (!m.failed.empty()) return {{"measured", false}, {"actual", m.actual}, {"failed", m.failed}};
  nlohmann::json first = nlohmann::json::array();
  for (const ChangedRay& c : m.first) {
    const auto hit = [&c](std::uint32_t h) {
      return IsShadow(c) ? nlohmann::json{{"occluded", h != 0}}
                         : nlohmann::json{{"prim", h == layout::kNoPrim ? nlohmann::json(nullptr) : nlohmann::json(h)}};
    };
    first.push_back({{"batch", c.batch}, {"ray", c.ray}, {"emulator", hit(c.emu)}, {"vulkan", hit(c.vulkan)},
                     {"same_ray", c.same_ray}, {"verdict", c.verdict}});
  }
  nlohmann::json verdicts = {{"emulator", 0}, {"vulkan", 0}, {"both", 0}, {"within_rounding", 0}, {"neither", 0}};
  for (const auto& [k, n] : m.verdicts) verdicts[k] = n;
  return {{"measured", true},           {"actual", m.actual}, {"no_visible_change", m.NoVisibleChange()}, {"differed", m.differed}, {"rays", m.rays},
          {"rays_changed", m.rays_changed}, {"one_side_only", m.one_side_only}, {"primary_hits_changed", m.primary_changed},
          {"pixels_changed", m.pixels_changed}, {"judged", m.judged},  {"verdicts", verdicts},
          {"changed_rays", first}, {"final_tests", FinalTestsJson(m.tests)}};
}

}  // namespace rayspace::app
