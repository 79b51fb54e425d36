// Ray generation (thesis eqs. 3.1-3.7). Slots are sparse; trim compacts them in slot order.
#include <limits>

#include "rayspace/emu/light_sample.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/raygen_math.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

SparseRays PassRaygenShadow(const call::Raygen& c) {
  const layout::FrameConstants& fc = c.frame;
  const In<layout::Surface> surfaces = c.surfaces;
  const SceneBuffers& scene = *c.scene;
  const std::size_t lights = scene.lights.size(), slots = ShadowSlots(scene.lights);
  const bool lit_only = c.shadow_rule == layout::kShadowRuleLit;
  SparseRays out;
  out.rays.assign(surfaces.size() * slots, layout::Ray{});
  out.flags.assign(surfaces.size() * slots, 0u);
  ParallelFor(surfaces.size(), [&](std::size_t s) {
    const layout::Surface& sf = surfaces[s];
    if (sf.position.w == 0.0f) return;
    const glm::vec3 p = Xyz(sf.position);
    const std::uint32_t key = layout::SamplerKey(sf.info.y, sf.info.x);
    for (std::size_t l = 0; l < lights; ++l) {
      const layout::Light& light = scene.lights[l];
      for (std::uint32_t k = 0; k < LightSamples(light); ++k) {
        // eq. 3.1: the ray starts at the light (at one of an area light's sample points)
        const glm::vec3 o = LightSamplePoint<float>(light, static_cast<std::uint32_t>(l), key, k);
        glm::vec3 d;
        float dist;
        if (!ShadowDirection(p, o, d, dist)) continue;
        // --shadow-rule lit: no ray where the shade pass would not light the point anyway.
        if (lit_only && !LightInFront(d, Xyz(sf.normal), Xyz(sf.incoming))) continue;
        layout::Ray r;
        r.origin_tmin = glm::vec4(o, fc.params.x);
        r.direction_tmax = glm::vec4(d, dist * fc.params.z);
        r.info = glm::uvec4(sf.info.y, sf.info.x, layout::kRayShadow, static_cast<std::uint32_t>(l));
        r.weight = sf.weight;
        const std::size_t slot = s * slots + light.sampling.z + k;
        out.rays[slot] = r;
        out.flags[slot] = 1u;
      }
    }
  });
  return out;
}

namespace {

// One ray slot per surface (reflection and refraction, like their kernels): `direction(sf, m, d,
// k)` gives the new direction d and weight factor k of a covered surface, or false for no ray.
template <typename DirectionFn>
SparseRays SurfaceRays(const call::Raygen& c, std::uint32_t kind, DirectionFn&& direction) {
  const In<layout::Surface> surfaces = c.surfaces;
  SparseRays out;
  out.rays.assign(surfaces.size(), layout::Ray{});
  out.flags.assign(surfaces.size(), 0u);
  ParallelFor(surfaces.size(), [&](std::size_t s) {
    const layout::Surface& sf = surfaces[s];
    if (sf.position.w == 0.0f) return;
    glm::vec3 d;
    float k;
    if (!direction(sf, c.scene->materials[sf.info.z], d, k) || !(Dot(d, d) > 0.0f)) return;
    layout::Ray r;
    r.origin_tmin = glm::vec4(Xyz(sf.position), c.frame.params.x);  // eqs. 3.3, 3.5
    r.direction_tmax = glm::vec4(d, std::numeric_limits<float>::infinity());
    r.info = glm::uvec4(sf.info.y, sf.info.x, kind, static_cast<std::uint32_t>(s));
    r.weight = glm::vec4(sf.weight.x * k, sf.weight.y * k, sf.weight.z * k, 0.0f);
    out.rays[s] = r;
    out.flags[s] = 1u;
  });
  return out;
}

}  // namespace

SparseRays PassRaygenReflection(const call::Raygen& c) {
  return SurfaceRays(c, layout::kRayReflection, [](const layout::Surface& sf, const layout::Material& m, glm::vec3& d, float& kr) {
    kr = m.diffuse_reflectivity.w;
    if (!(kr > 0.0f)) return false;
    d = ReflectionDirection(Xyz(sf.incoming), Xyz(sf.normal));
    return true;
  });
}

SparseRays PassRaygenRefraction(const call::Raygen& c) {
  return SurfaceRays(c, layout::kRayRefraction, [](const layout::Surface& sf, const layout::Material& m, glm::vec3& d, float& kt) {
    kt = m.transparency_ior.x;
    if (!(kt > 0.0f)) return false;
    return RefractionDirection(Xyz(sf.incoming), Xyz(sf.normal), m.transparency_ior.y, d);
  });
}

SparseRays PassRaygen(const call::Raygen& c) {
  switch (c.kind) {
    case layout::kRayShadow: return PassRaygenShadow(c);
    case layout::kRayReflection: return PassRaygenReflection(c);
    case layout::kRayRefraction: return PassRaygenRefraction(c);
  }
  RS_CHECK_MSG(false, "unknown ray kind {}", c.kind);
  return {};
}

}  // namespace rayspace::emu
