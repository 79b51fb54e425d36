// Shading points of one generation: from the G-buffer (generation 0) or from ray hits.
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/raster_detail.h"
#include "rayspace/emu/surface_math.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

glm::vec3 ShadingNormal(const SceneBuffers& scene, std::uint32_t prim, glm::vec3 p) {
  return ShadingNormalOf<float>(scene, prim, p);
}

std::vector<layout::Surface> PassSurfacesFromGBuffer(const call::SurfacesFromGBuffer& c) {
  const layout::FrameConstants& fc = c.frame;
  const SceneBuffers& scene = *c.scene;
  const std::size_t npix = c.prim.size();
  std::vector<layout::Surface> out(npix);
  const std::uint32_t width = fc.dims.x;
  ParallelFor(npix, [&](std::size_t i) {
    layout::Surface s{};
    const std::uint32_t prim = c.prim[i];
    if (prim != layout::kNoPrim) {
      const glm::vec3 d = PixelDirection(fc, static_cast<std::uint32_t>(i % width), static_cast<std::uint32_t>(i / width));
      s.position = glm::vec4(Xyz(c.position[i]), 1.0f);
      s.normal = glm::vec4(Xyz(c.normal[i]), 0.0f);
      s.incoming = glm::vec4(Normalize(d), 0.0f);
      s.weight = glm::vec4(1.0f, 1.0f, 1.0f, 0.0f);
      s.info = glm::uvec4(prim, static_cast<std::uint32_t>(i), scene.info[prim].ids.x, 0);
    } else {
      s.info = glm::uvec4(layout::kNoPrim, static_cast<std::uint32_t>(i), 0, 0);
    }
    out[i] = s;
  });
  return out;
}

std::vector<layout::Surface> PassSurfacesFromHits(const call::SurfacesFromHits& c) {
  const In<layout::Ray> rays = c.rays;
  const In<std::uint64_t> hits = c.hits;
  const SceneBuffers& scene = *c.scene;
  std::vector<layout::Surface> out(rays.size());
  ParallelFor(rays.size(), [&](std::size_t i) {
    const layout::Ray& r = rays[i];
    layout::Surface s{};
    const std::uint64_t h = hits[i];
    if (h != kMissPacked) {
      const std::uint32_t prim = HitPrim(h);
      const float t = HitT(h);
      const glm::vec3 o = Xyz(r.origin_tmin), d = Xyz(r.direction_tmax);
      const glm::vec3 p(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
      s.position = glm::vec4(p, 1.0f);
      s.normal = glm::vec4(ShadingNormal(scene, prim, p), 0.0f);
      s.incoming = glm::vec4(Normalize(d), 0.0f);
      s.weight = r.weight;
      s.info = glm::uvec4(prim, r.info.x, scene.info[prim].ids.x, 0);
    } else {
      s.info = glm::uvec4(layout::kNoPrim, r.info.x, 0, 0);
    }
    out[i] = s;
  });
  return out;
}

}  // namespace rayspace::emu
