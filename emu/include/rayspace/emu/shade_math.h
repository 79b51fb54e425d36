// The colour a shading point receives (thesis eq. 3.19), templated over the scalar like intersect.h:
// float in the emulated pass, verify::SpecReal when the diff bounds what a device may compute.
// Mirrors gpu/shaders/shade.comp.
#pragma once
#include "rayspace/emu/intersect.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

// The unweighted colour at `sf` from the lights `lit(l)` says reach it (a shadow ray was cast and
// not occluded).
template <typename S, typename LitFn>
Vec3<S> ShadeColorOf(const SceneBuffers& scene, const layout::Surface& sf, LitFn&& lit) {
  using V = Vec3<S>;
  const layout::Material& m = scene.materials[sf.info.z];
  const V p(Xyz(sf.position)), view(Xyz(sf.incoming));  // eq. 3.19d: view = incoming
  V n(Xyz(sf.normal));
  if (Dot(n, view) > S(0.0f)) n = -n;  // two-sided: light the side the ray arrived on
  const std::uint32_t shininess = static_cast<std::uint32_t>(m.specular_shininess.w);
  V color(S(0.0f), S(0.0f), S(0.0f));
  for (std::size_t l = 0; l < scene.lights.size(); ++l) {
    if (!lit(l)) continue;  // no ray, or in shadow
    const layout::Light& light = scene.lights[l];
    const V lv = V(Xyz(light.position)) - p;
    const S dist = Length(lv);                                              // eq. 3.19b
    const V ldir(lv.x / dist, lv.y / dist, lv.z / dist);                    // eq. 3.19a
    const S att = S(1.0f) / ((S(light.attenuation.x) + dist * S(light.attenuation.y)) +
                             (dist * dist) * S(light.attenuation.z));      // eq. 3.19c
    const S ndl = Dot(ldir, n);
    if (!(ndl > S(0.0f))) continue;  // light behind the surface: neither diffuse nor specular
    const S diffuse = Max(S(0.0f), Min(S(1.0f), ndl));                      // eq. 3.19f
    const V h = Normalize(ldir - view);                                     // eq. 3.19e
    const S specular = Max(S(0.0f), Min(S(1.0f), IntPowOf(Max(S(0.0f), Dot(h, n)), shininess)));  // eq. 3.19g
    for (int k = 0; k < 3; ++k) {
      const S li(light.color_intensity[k]), w(light.color_intensity.w);
      color[k] = color[k] + ((S(m.diffuse_reflectivity[k]) * li) * diffuse * w) * att;  // 3.19h
      color[k] = color[k] + ((S(m.specular_shininess[k]) * li) * specular * w) * att;   // 3.19i
    }
  }
  return color;
}

}  // namespace rayspace::emu
