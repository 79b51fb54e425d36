// The colour a shading point receives (thesis eq. 3.19), templated over the scalar like intersect.h:
// float in the emulated pass, verify::SpecReal when the diff bounds what a device may compute.
// Mirrors gpu/shaders/shade.comp.
#pragma once
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/light_sample.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

// The unweighted colour at `sf` from the light samples `lit(j)` says reach it (a shadow ray was cast
// and not occluded), j = a light's first shadow slot + its sample. Each sample of an area light is
// lit as a point light at the sample's position, its terms scaled by 1 / samples (1 for a point light,
// which leaves them unchanged).
template <typename S, typename LitFn>
Vec3<S> ShadeColorOf(const SceneBuffers& scene, const layout::Surface& sf, LitFn&& lit) {
  using V = Vec3<S>;
  const layout::Material& m = scene.materials[sf.info.z];
  const V p(Xyz(sf.position)), view(Xyz(sf.incoming));  // eq. 3.19d: view = incoming
  V n(Xyz(sf.normal));
  if (Dot(n, view) > S(0.0f)) n = -n;  // two-sided: light the side the ray arrived on
  const std::uint32_t shininess = static_cast<std::uint32_t>(m.specular_shininess.w);
  const std::uint32_t key = layout::SamplerKey(sf.info.y, sf.info.x);
  V color(S(0.0f), S(0.0f), S(0.0f));
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    const layout::Light& light = scene.lights[l];
    for (std::uint32_t k = 0; k < LightSamples(light); ++k) {
      if (!lit(light.sampling.z + k)) continue;  // no ray, or in shadow
      const V lv = LightSamplePoint<S>(light, static_cast<std::uint32_t>(l), key, k) - p;
      const S dist = Length(lv);                                              // eq. 3.19b
      const V ldir(lv.x / dist, lv.y / dist, lv.z / dist);                    // eq. 3.19a
      const S att = S(1.0f) / ((S(light.attenuation.x) + dist * S(light.attenuation.y)) +
                               (dist * dist) * S(light.attenuation.z));      // eq. 3.19c
      const S ndl = Dot(ldir, n);
      if (!(ndl > S(0.0f))) continue;  // light behind the surface: neither diffuse nor specular
      const S diffuse = Max(S(0.0f), Min(S(1.0f), ndl));                      // eq. 3.19f
      const V h = Normalize(ldir - view);                                     // eq. 3.19e
      const S specular = Max(S(0.0f), Min(S(1.0f), IntPowOf(Max(S(0.0f), Dot(h, n)), shininess)));  // eq. 3.19g
      const S share(light.attenuation.w);  // 1 / samples
      for (int c = 0; c < 3; ++c) {
        const S li(light.color_intensity[c]), w(light.color_intensity.w);
        color[c] = color[c] + (((S(m.diffuse_reflectivity[c]) * li) * diffuse * w) * att) * share;  // 3.19h
        color[c] = color[c] + (((S(m.specular_shininess[c]) * li) * specular * w) * att) * share;   // 3.19i
      }
    }
  }
  return color;
}

}  // namespace rayspace::emu
