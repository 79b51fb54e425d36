// Ray generation (thesis eqs. 3.1-3.7). Slots are sparse; trim compacts them in slot order.
#include <limits>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

bool Finite3(glm::vec3 v) {
  constexpr float kMax = std::numeric_limits<float>::max();
  return std::fabs(v.x) <= kMax && std::fabs(v.y) <= kMax && std::fabs(v.z) <= kMax;
}

}  // namespace

SparseRays PassRaygenShadow(const call::Raygen& c) {
  const layout::FrameConstants& fc = c.frame;
  const In<layout::Surface> surfaces = c.surfaces;
  const SceneBuffers& scene = *c.scene;
  const std::size_t lights = scene.lights.size();
  SparseRays out;
  out.rays.assign(surfaces.size() * lights, layout::Ray{});
  out.flags.assign(surfaces.size() * lights, 0u);
  ParallelFor(surfaces.size(), [&](std::size_t s) {
    const layout::Surface& sf = surfaces[s];
    if (sf.position.w == 0.0f) return;
    const glm::vec3 p = Xyz(sf.position);
    for (std::size_t l = 0; l < lights; ++l) {
      const glm::vec3 o = Xyz(scene.lights[l].position);  // eq. 3.1: the ray starts at the light
      const glm::vec3 v = p - o;
      const float dist = Length(v);
      if (!(dist > 0.0f) || !Finite3(v)) continue;     // light on the point: no direction
      const glm::vec3 d(v.x / dist, v.y / dist, v.z / dist);  // eq. 3.2
      layout::Ray r;
      r.origin_tmin = glm::vec4(o, fc.params.x);
      r.direction_tmax = glm::vec4(d, dist * fc.params.z);
      r.info = glm::uvec4(sf.info.y, sf.info.x, layout::kRayShadow, static_cast<std::uint32_t>(l));
      r.weight = sf.weight;
      out.rays[s * lights + l] = r;
      out.flags[s * lights + l] = 1u;
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
    const glm::vec3 i = Xyz(sf.incoming), n = Xyz(sf.normal);
    const float ni = Dot(n, i);
    const float k = 2.0f * ni;
    d = glm::vec3(i.x - n.x * k, i.y - n.y * k, i.z - n.z * k);  // eq. 3.4: i - 2 n (n.i)
    return true;
  });
}

SparseRays PassRaygenRefraction(const call::Raygen& c) {
  return SurfaceRays(c, layout::kRayRefraction, [](const layout::Surface& sf, const layout::Material& m, glm::vec3& d, float& kt) {
    kt = m.transparency_ior.x;
    if (!(kt > 0.0f)) return false;
    const glm::vec3 i = Xyz(sf.incoming);
    glm::vec3 n = Xyz(sf.normal);
    float cosi = Dot(i, n);
    // Entering when the ray meets the normal's front side; leaving flips the normal and the ratio.
    float ri = 1.0f / m.transparency_ior.y;
    if (cosi > 0.0f) {
      n = -n;
      cosi = -cosi;
      ri = m.transparency_ior.y;
    }
    const float k = 1.0f - (ri * ri) * (1.0f - cosi * cosi);  // eq. 3.6
    if (k < 0.0f) return false;                               // total internal reflection
    const float a = ri * cosi + std::sqrt(k);
    d = glm::vec3(i.x * ri - n.x * a, i.y * ri - n.y * a, i.z * ri - n.z * a);  // eq. 3.7
    return true;
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
