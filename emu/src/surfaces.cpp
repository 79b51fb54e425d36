// Shading points of one generation: from the G-buffer (generation 0) or from ray hits.
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/raster_detail.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

glm::vec3 ShadingNormal(const SceneBuffers& scene, std::uint32_t prim, glm::vec3 p) {
  const layout::Triangle& t = scene.triangles[prim];
  const layout::TriangleNormals& tn = scene.normals[prim];
  const glm::vec3 v0 = Xyz(t.v0), v1 = Xyz(t.v1), v2 = Xyz(t.v2);
  // Everything relative to p and scaled by one power of two: the weights are ratios of degree-4
  // products, unchanged by the scaling, which keeps them in range for scenes from 2^-60 to 2^60.
  const glm::vec3 e1 = v1 - v0, e2 = v2 - v0, q0 = v0 - p, q1 = v1 - p, q2 = v2 - p;
  const float k = InversePowerOfTwo(Max(Max(MaxAbs(e1, e2), MaxAbs(q0, q1)), MaxAbs(q2, q2)));
  const glm::vec3 n = Cross(e1 * k, e2 * k);
  // Signed sub-triangle areas (times |n|); their ratios are the barycentric weights. The thesis's
  // eq. 3.17 normalises these cross products, which loses the areas it needs.
  const float a0 = Dot(Cross(q1 * k, q2 * k), n);
  const float a1 = Dot(Cross(q2 * k, q0 * k), n);
  const float a2 = Dot(Cross(q0 * k, q1 * k), n);
  const float sum = (a0 + a1) + a2;
  glm::vec3 s(0.0f);
  if (sum != 0.0f) {
    const float w0 = a0 / sum, w1 = a1 / sum, w2 = a2 / sum;
    for (int k = 0; k < 3; ++k) s[k] = (tn.n0[k] * w0 + tn.n1[k] * w1) + tn.n2[k] * w2;
  }
  const float len2 = Dot(s, s);
  if (!(len2 > 0.0f) || !(len2 <= 3.0e38f)) {
    const float nl = Dot(n, n);
    if (!(nl > 0.0f) || !(nl <= 3.0e38f)) return Xyz(tn.n0);  // degenerate triangle: stored normal
    return Normalize(n);
  }
  return Normalize(s);
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
