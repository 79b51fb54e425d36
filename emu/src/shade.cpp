// Shading (thesis eq. 3.19) into the fixed-point accumulator. Mirrors gpu/shaders/shade.comp.
#include <atomic>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

// Converts a contribution to fixed point. Integer sums do not depend on the order of addition.
std::uint64_t ToFixed(float c) {
  const float v = Clamp(c, 0.0f, layout::kAccumMax);
  return static_cast<std::uint64_t>(v * layout::kAccumScale);
}

}  // namespace

void PassShade(const call::Shade& c) {
  const SceneBuffers& scene = *c.scene;
  const In<layout::Surface> surfaces = c.surfaces;
  const In<std::uint32_t> shadow_flags = c.shadow_flags, shadow_offsets = c.shadow_offsets, occluded = c.occluded;
  std::vector<std::uint64_t>& accum = *c.accum;
  const std::size_t lights = scene.lights.size();
  ParallelFor(surfaces.size(), [&](std::size_t s) {
    const layout::Surface& sf = surfaces[s];
    if (sf.position.w == 0.0f) return;
    const layout::Material& m = scene.materials[sf.info.z];
    const glm::vec3 p = Xyz(sf.position), view = Xyz(sf.incoming);  // eq. 3.19d: view = incoming
    glm::vec3 n = Xyz(sf.normal);
    if (Dot(n, view) > 0.0f) n = -n;  // two-sided: light the side the ray arrived on
    const std::uint32_t shininess = static_cast<std::uint32_t>(m.specular_shininess.w);
    glm::vec3 color(0.0f);
    for (std::size_t l = 0; l < lights; ++l) {
      const std::size_t slot = s * lights + l;
      if (!shadow_flags[slot] || occluded[shadow_offsets[slot]]) continue;  // no ray, or in shadow
      const layout::Light& light = scene.lights[l];
      const glm::vec3 lv = Xyz(light.position) - p;
      const float dist = Length(lv);                                          // eq. 3.19b
      const glm::vec3 ldir(lv.x / dist, lv.y / dist, lv.z / dist);            // eq. 3.19a
      const float att = 1.0f / ((light.attenuation.x + dist * light.attenuation.y) +
                                (dist * dist) * light.attenuation.z);         // eq. 3.19c
      const float ndl = Dot(ldir, n);
      if (!(ndl > 0.0f)) continue;  // light behind the surface: neither diffuse nor specular
      const float diffuse = Max(0.0f, Min(1.0f, ndl));                        // eq. 3.19f
      const glm::vec3 h = Normalize(ldir - view);                             // eq. 3.19e
      const float specular = Max(0.0f, Min(1.0f, IntPow(Max(0.0f, Dot(h, n)), shininess)));  // eq. 3.19g
      for (int k = 0; k < 3; ++k) {
        const float li = light.color_intensity[k];
        color[k] = color[k] + (((m.diffuse_reflectivity[k] * li) * diffuse) * light.color_intensity.w) * att;  // 3.19h
        color[k] = color[k] + (((m.specular_shininess[k] * li) * specular) * light.color_intensity.w) * att;   // 3.19i
      }
    }
    const std::uint32_t pixel = sf.info.y;
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t q = ToFixed(color[k] * sf.weight[k]);
      if (q != 0) std::atomic_ref<std::uint64_t>(accum[3 * static_cast<std::size_t>(pixel) + k]).fetch_add(q, std::memory_order_relaxed);
    }
  });
}

}  // namespace rayspace::emu
