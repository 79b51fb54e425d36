#include "rayspace/emu/frame.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include <unistd.h>

#include <fmt/format.h>

#include "rayspace/stopwatch.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/error.h"

namespace rayspace::emu {

const char* RayKindName(std::uint32_t kind) {
  switch (kind) {
    case layout::kRayShadow: return "shadow";
    case layout::kRayReflection: return "reflection";
    case layout::kRayRefraction: return "refraction";
    case layout::kRayPrimary: return "primary";
  }
  return "unknown";
}

namespace {

// The frame's progress on stderr: "pass k of n" with the pass's time, the elapsed time and an ETA
// (the mean time per pass so far times the passes left). A tracer's own passes (hash, sort, build,
// and traverse and reduce once per level) are folded into their pass's line, each name once with
// how often it ran, so that a level loop does not repeat a name.
class Progress {
 public:
  explicit Progress(const FrameOptions& opt) : on_(opt.progress), tty_(on_ && isatty(STDERR_FILENO)), label_(opt.progress_label) {}
  void SetTotal(std::size_t n) { total_ = n; }
  void Start(const std::string& name) {
    ++started_;
    if (tty_) Line(name, "...", Eta(), false);
  }
  void Finish(const std::string& name, std::size_t elements, double ms, const std::vector<SubPass>& sub) {
    if (!on_) return;
    finished_ = started_;
    Line(name, fmt::format("{} elements, {:.1f} ms{}", elements, ms, Folded(sub)), Eta(), !tty_);
  }
  void End() {
    if (tty_) std::fprintf(stderr, "\n");
  }

 private:
  std::string Eta() const {
    const double s = clock_.Ms() / 1000.0;
    if (finished_ == 0 || finished_ >= total_) return fmt::format("elapsed {:.1f} s", s);
    return fmt::format("elapsed {:.1f} s, ETA {:.1f} s", s,
                       s / static_cast<double>(finished_) * static_cast<double>(total_ - finished_));
  }
  static std::string Folded(const std::vector<SubPass>& sub) {
    std::vector<std::string> order;
    std::map<std::string, std::pair<std::size_t, double>> by_name;
    for (const SubPass& sp : sub) {
      auto [it, fresh] = by_name.try_emplace(sp.name, 0, 0.0);
      if (fresh) order.push_back(sp.name);
      ++it->second.first;
      it->second.second += sp.ms;
    }
    std::string s;
    for (const std::string& n : order) {
      const auto& [count, ms] = by_name[n];
      s += fmt::format("{}{}{} {:.1f} ms", s.empty() ? " (" : ", ", n, count > 1 ? fmt::format(" x{}", count) : "", ms);
    }
    return s.empty() ? s : s + ")";
  }
  void Line(const std::string& name, const std::string& what, const std::string& eta, bool newline) const {
    const std::string lead = label_.empty() ? "" : label_ + ": ";
    std::fprintf(stderr, "%s[rayspace] %s%zu of %zu %s %s; %s%s", tty_ ? "\r\033[K" : "", lead.c_str(), started_, total_,
                 name.c_str(), what.c_str(), eta.c_str(), newline ? "\n" : "");
    std::fflush(stderr);
  }

  bool on_, tty_;
  std::string label_;
  std::size_t total_ = 0, started_ = 0, finished_ = 0;
  Stopwatch clock_;
};

class Runner {
 public:
  Runner(const Scene& scene, const SceneBuffers& b, Tracer& tracer, const FrameOptions& opt, const BatchObserver& obs)
      : scene_(scene), b_(b), tracer_(tracer), opt_(opt), observer_(obs),
        checked_(opt.passes && opt.passes != &EmuFramePasses() ? CheckedFramePasses(*opt.passes) : nullptr),
        passes_(checked_ ? *checked_ : EmuFramePasses()) {}

  FrameResult Run() {
    Stopwatch total;
    r_.width = opt_.width > 0 ? opt_.width : scene_.width;
    r_.height = opt_.height > 0 ? opt_.height : scene_.height;
    r_.triangles = b_.triangles.size();
    const int depth = scene_.max_depth;
    fc_ = MakeFrameConstants(scene_, b_, r_.width, r_.height);
    progress_.SetTotal(CountPasses());
    PrepAndRaster();

    std::vector<std::uint64_t> accum(static_cast<std::size_t>(r_.width) * r_.height * 3, 0);
    std::vector<layout::Surface> surfaces;
    Pass("surfaces.b0", [&] {
      surfaces = passes_.SurfacesFromGBuffer(SurfacesCall(fc_, r_.gbuffer, b_));
      r_.digest.Add("surfaces.b0", "surfaces", surfaces);
      return surfaces.size();
    });
    if (opt_.trace_primary) TracePrimary();

    for (const MaterialDesc& m : scene_.materials) {
      reflective_ |= m.reflectivity > 0.0f;
      transparent_ |= m.transparency > 0.0f;
    }
    // Bounces exist only when some material spawns secondary rays from a hit.
    const int last = (reflective_ || transparent_) ? depth : 0;
    for (auto& v : r_.rays) v.assign(static_cast<std::size_t>(last) + 1, 0);
    if (depth == 0) {
      for (const char* p : {"raygen.", "trim.", "trace.", "surfaces."}) {
        Skip(std::string(p) + "reflection", "max_depth is 0");
        Skip(std::string(p) + "refraction", "max_depth is 0");
      }
    }

    for (int bounce = 0; bounce <= last; ++bounce) {
      ShadowAndShade(bounce, surfaces, accum);
      if (bounce == last) {
        if (last == 0 && depth > 0) {
          for (const char* p : {"raygen.", "trim.", "trace.", "surfaces."}) {
            Skip(std::string(p) + "reflection", "no material has reflectivity > 0");
            Skip(std::string(p) + "refraction", "no material has transparency > 0");
          }
        }
        break;
      }
      surfaces = NextGeneration(bounce, surfaces);
    }
    Pass("resolve", [&] {
      r_.rgb = passes_.Resolve({.accum = accum});
      r_.accum = accum;
      r_.digest.Add("resolve", "rgb", r_.rgb);
      return r_.rgb.size() / 3;
    });
    r_.total_ms = total.Ms();
    progress_.End();
    return std::move(r_);
  }

 private:
  // The passes Run() will run, for the progress line's "k of n": prep, raster, the first surfaces,
  // per bounce the shadow rays (raygen, trim, trace) and the shading, per later generation and kind
  // raygen, trim, trace and surfaces, and the resolve.
  std::size_t CountPasses() const {
    bool reflective = false, transparent = false;
    for (const MaterialDesc& m : scene_.materials) {
      reflective |= m.reflectivity > 0.0f;
      transparent |= m.transparency > 0.0f;
    }
    const std::size_t last = (reflective || transparent) ? static_cast<std::size_t>(scene_.max_depth) : 0;
    const std::size_t shadow = b_.lights.empty() ? 0 : 3;  // raygen, trim and trace of one bounce
    const std::size_t shadow_bounces = opt_.shadow_first_bounce_only ? 1 : last + 1;
    const std::size_t per_generation = 4 * (static_cast<std::size_t>(reflective) + static_cast<std::size_t>(transparent));
    return 3 + (opt_.trace_primary ? 1 : 0) + shadow_bounces * shadow + (last + 1) + last * per_generation + 1;
  }

  // Bounding spheres of the triangles and objects, the tracer's preparation, and the G-buffer.
  void PrepAndRaster() {
    Pass("prep", [&] {
      r_.triangle_spheres = PassTriangleSpheres(b_.triangles);
      r_.object_spheres = PassObjectSpheres(b_);
      r_.digest.Add("prep", "triangle_spheres", r_.triangle_spheres);
      r_.digest.Add("prep", "object_spheres", r_.object_spheres);
      // The tracer's own preparation (object trees, its buffers) is part of prep's time.
      tracer_.Prepare(r_.triangle_spheres, r_.object_spheres);
      return b_.triangles.size();
    });
    Pass("raster", [&] {
      r_.gbuffer = passes_.Raster({.frame = fc_, .scene = &b_});
      const GBuffer& g = r_.gbuffer;
      r_.digest.Add("raster", "diffuse", g.diffuse);
      r_.digest.Add("raster", "specular", g.specular);
      r_.digest.Add("raster", "position", g.position);
      r_.digest.Add("raster", "normal", g.normal);
      r_.digest.Add("raster", "prim", g.prim);
      r_.digest.Add("raster", "depth", g.depth);
      return g.prim.size();
    });
  }

  // --primary tl: an eye ray per pixel (tl::EyeRays, on the host: PixelDirection, as the raster's
  // surfaces use it) traced beside the G-buffer; the pixels whose traced primitive differs from the
  // raster's are counted (coverage at edges and depth ties decide them differently).
  void TracePrimary() {
    std::vector<layout::Ray> rays;
    std::vector<std::uint64_t> hits;
    Pass("trace.primary.b0", [&] {
      rays = tl::EyeRays(fc_);
      Begin("primary.b0", layout::kRayPrimary, 0);
      tracer_.Closest(rays, hits);
      r_.digest.Add("trace.primary.b0", "hits", hits);
      return rays.size();
    });
    if (observer_) observer_({"primary.b0", layout::kRayPrimary, 0, &rays, &hits, nullptr});
    r_.primary_rays = rays.size();
    for (std::size_t i = 0; i < rays.size() && i < r_.gbuffer.prim.size(); ++i)
      r_.primary_differing += (hits[i] == kMissPacked ? layout::kNoPrim : HitPrim(hits[i])) != r_.gbuffer.prim[i];
  }

  // Shadow rays of this generation's surfaces, then shading into `accum`.
  void ShadowAndShade(int bounce, const std::vector<layout::Surface>& surfaces, std::vector<std::uint64_t>& accum) {
    const std::string bs = fmt::format("b{}", bounce);
    SparseRays shadow;
    Trimmed shadow_trim;
    std::vector<std::uint32_t> occluded;
    if (!b_.lights.empty() && bounce > 0 && opt_.shadow_first_bounce_only) {
      for (const char* p : {"raygen.", "trim.", "trace."}) Skip(p + ("shadow." + bs), "--shadow-bounces first");
      Unoccluded(surfaces.size(), shadow, shadow_trim, occluded);
    } else if (!b_.lights.empty()) {
      RaygenAndTrim(layout::kRayShadow, "shadow." + bs, [&] { return passes_.Raygen({.kind = layout::kRayShadow, .frame = fc_, .surfaces = surfaces, .scene = &b_, .shadow_rule = opt_.shadow_rule}); }, shadow, shadow_trim);
      r_.rays[layout::kRayShadow][bounce] = shadow_trim.rays.size();
      Pass("trace.shadow." + bs, [&] {
        Begin("shadow." + bs, layout::kRayShadow, bounce);
        tracer_.Occluded(shadow_trim.rays, occluded);
        r_.digest.Add("trace.shadow." + bs, "occluded", occluded);
        return shadow_trim.rays.size();
      });
      if (observer_) observer_({"shadow." + bs, layout::kRayShadow, bounce, &shadow_trim.rays, nullptr, &occluded});
      r_.unoccluded_shadow_rays.resize(std::max<std::size_t>(r_.unoccluded_shadow_rays.size(), bounce + 1), 0);
      r_.unoccluded_shadow_rays[bounce] += static_cast<std::uint64_t>(std::count(occluded.begin(), occluded.begin() + static_cast<std::ptrdiff_t>(shadow_trim.rays.size()), 0u));
      CountSoftShadows(bounce, surfaces.size(), shadow.flags, shadow_trim.offsets, occluded);
    } else {
      Skip("raygen.shadow." + bs, "the scene has no lights");
      Skip("trim.shadow." + bs, "the scene has no lights");
      Skip("trace.shadow." + bs, "the scene has no lights");
    }
    Pass("shade." + bs, [&] {
      passes_.Shade({.frame = fc_, .surfaces = surfaces, .shadow_flags = shadow.flags, .shadow_offsets = shadow_trim.offsets,
                    .occluded = occluded, .accum = &accum, .scene = &b_});
      r_.digest.Add("shade." + bs, "accum", accum);
      return surfaces.size();
    });
  }

  // Penumbra and umbra points of this generation (FrameResult): per surface and area light, how many of
  // the light's cast samples arrive.
  void CountSoftShadows(int bounce, std::size_t surfaces, const std::vector<std::uint32_t>& flags,
                        const std::vector<std::uint32_t>& offsets, const std::vector<std::uint32_t>& occluded) {
    const std::size_t per = ShadowSlots(b_.lights);
    r_.penumbra_points.resize(std::max<std::size_t>(r_.penumbra_points.size(), bounce + 1), 0);
    r_.umbra_points.resize(r_.penumbra_points.size(), 0);
    for (std::size_t s = 0; s < surfaces; ++s) {
      bool penumbra = false, umbra = false;
      for (const layout::Light& l : b_.lights) {
        if (l.sampling.x == layout::kLightPoint) continue;
        std::uint32_t cast = 0, lit = 0;
        for (std::uint32_t k = 0; k < l.sampling.y; ++k) {
          const std::size_t slot = s * per + l.sampling.z + k;
          if (!flags[slot]) continue;
          ++cast;
          lit += occluded[offsets[slot]] == 0u;
        }
        penumbra |= lit > 0 && lit < cast;
        umbra |= cast > 0 && lit == 0;
      }
      r_.penumbra_points[bounce] += penumbra;
      r_.umbra_points[bounce] += umbra;
    }
  }

  // The shade pass's shadow inputs when no shadow ray was traced (--shadow-bounces first after bounce
  // 0): every slot flagged, each its own dense ray, none occluded, so every light reaches every point
  // it faces.
  void Unoccluded(std::size_t surfaces, SparseRays& shadow, Trimmed& trim, std::vector<std::uint32_t>& occluded) const {
    const std::size_t slots = surfaces * ShadowSlots(b_.lights);
    shadow.flags.assign(slots, 1u);
    trim.offsets.resize(slots);
    for (std::size_t i = 0; i < slots; ++i) trim.offsets[i] = static_cast<std::uint32_t>(i);
    occluded.assign(slots, 0u);
  }

  // Next generation: reflection and refraction rays; their hits are the surfaces returned.
  std::vector<layout::Surface> NextGeneration(int bounce, const std::vector<layout::Surface>& surfaces) {
    const std::string next = fmt::format("b{}", bounce + 1);
    std::vector<layout::Surface> next_surfaces;
    const struct {
      std::uint32_t kind;
      bool enabled;
      const char* reason;
    } kinds[2] = {{layout::kRayReflection, reflective_, "no material has reflectivity > 0"},
                  {layout::kRayRefraction, transparent_, "no material has transparency > 0"}};
    for (const auto& k : kinds) {
      const std::string kn = RayKindName(k.kind);
      const std::string sfx = kn + "." + next;
      if (!k.enabled) {
        for (const char* p : {"raygen.", "trim.", "trace.", "surfaces."}) Skip(p + sfx, k.reason);
        continue;
      }
      SparseRays sparse;
      Trimmed trimmed;
      std::vector<std::uint64_t> hits;
      RaygenAndTrim(
          k.kind, sfx,
          [&] {
            return passes_.Raygen({.kind = k.kind, .frame = fc_, .surfaces = surfaces, .scene = &b_});
          },
          sparse, trimmed);
      r_.rays[k.kind][bounce + 1] = trimmed.rays.size();
      Pass("trace." + sfx, [&] {
        Begin(sfx, k.kind, bounce + 1);
        tracer_.Closest(trimmed.rays, hits);
        r_.digest.Add("trace." + sfx, "hits", hits);
        return trimmed.rays.size();
      });
      if (observer_) observer_({sfx, k.kind, bounce + 1, &trimmed.rays, &hits, nullptr});
      Pass("surfaces." + sfx, [&] {
        std::vector<layout::Surface> s = passes_.SurfacesFromHits({.rays = trimmed.rays, .hits = hits, .scene = &b_});
        r_.digest.Add("surfaces." + sfx, "surfaces", s);
        next_surfaces.insert(next_surfaces.end(), s.begin(), s.end());
        return s.size();
      });
    }
    return next_surfaces;
  }

  // The raygen pass of one batch (`suffix` = kind.bounce) and its compaction.
  template <typename F>
  void RaygenAndTrim(std::uint32_t kind, const std::string& suffix, F&& raygen, SparseRays& sparse, Trimmed& trimmed) {
    Pass("raygen." + suffix, [&] {
      sparse = raygen();
      r_.digest.Add("raygen." + suffix, "rays", sparse.rays);
      r_.digest.Add("raygen." + suffix, "flags", sparse.flags);
      return sparse.rays.size();
    });
    Pass("trim." + suffix, [&] {
      trimmed = passes_.Trim({.kind = kind, .rays = sparse.rays, .flags = sparse.flags});
      r_.digest.Add("trim." + suffix, "rays", trimmed.rays);
      r_.digest.Add("trim." + suffix, "offsets", trimmed.offsets);
      return trimmed.rays.size();
    });
  }

  void Begin(const std::string& batch, std::uint32_t kind, int bounce) {
    subpasses_.clear();
    tracer_.BeginBatch({batch, kind, bounce, &r_.digest, &subpasses_, &fc_});
  }

  template <typename F>
  void Pass(const std::string& name, F&& body) {
    Stopwatch c;
    subpasses_.clear();
    passes_.Label(name);
    progress_.Start(name);
    const std::size_t n = body();
    // A tracer's own passes (hash, sort, build, traverse, ...) are listed before the trace pass.
    for (const SubPass& sp : subpasses_) r_.passes.push_back({sp.name, true, {}, sp.ms, sp.elements, true});
    PassRecord rec{name, true, {}, c.Ms(), n, false};
    progress_.Finish(name, n, rec.ms, subpasses_);
    subpasses_.clear();
    r_.passes.push_back(std::move(rec));
  }
  void Skip(const std::string& name, const std::string& reason) { r_.passes.push_back({name, false, reason, 0.0, 0, false}); }

  const Scene& scene_;
  const SceneBuffers& b_;
  Tracer& tracer_;
  const FrameOptions& opt_;
  const BatchObserver& observer_;
  // A backend other than the emulator's own hands back outputs checked where it returns them.
  std::unique_ptr<FramePasses> checked_;
  FramePasses& passes_;
  layout::FrameConstants fc_{};
  FrameResult r_;
  std::vector<SubPass> subpasses_;
  Progress progress_{opt_};
  bool reflective_ = false, transparent_ = false;  // some material spawns reflection, refraction rays
};

}  // namespace

FrameResult RenderFrame(const Scene& scene, const SceneBuffers& buffers, Tracer& tracer, const FrameOptions& options,
                        const BatchObserver& observer) {
  RS_CHECK(!buffers.triangles.empty());
  return Runner(scene, buffers, tracer, options, observer).Run();
}

}  // namespace rayspace::emu
