// Bounding spheres: per triangle (a kernel) and per object (host preprocessing with CGAL's
// implementation of Gaertner's / Fischer's exact minimal enclosing sphere of points).
#include <cmath>

#include <CGAL/Cartesian.h>
#include <CGAL/Min_sphere_of_points_d_traits_3.h>
#include <CGAL/Min_sphere_of_spheres_d.h>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {

// Outward margin on float radii: the distance computation below has a relative error of a few
// 2^-24, far below 2^-20.
constexpr float kRadiusMargin = 1.0f + 1.0f / (1 << 20);

std::vector<glm::vec4> PassTriangleSpheres(const std::vector<layout::Triangle>& triangles) {
  std::vector<glm::vec4> out(triangles.size());
  ParallelFor(triangles.size(), [&](std::size_t i) {
    const glm::vec3 a = Xyz(triangles[i].v0), b = Xyz(triangles[i].v1), c = Xyz(triangles[i].v2);
    // Edges scaled by a power of two (exact, and every decision below is scale-free) so that the
    // degree-4 terms neither overflow nor underflow for scenes from 2^-60 to 2^60.
    const glm::vec3 ab0 = b - a, ac0 = c - a;
    const float k = InversePowerOfTwo(MaxAbs(ab0, ac0));
    const glm::vec3 ab = ab0 * k, ac = ac0 * k, bc = (c - b) * k;
    const float dab = Dot(ab, ab), dac = Dot(ac, ac), dbc = Dot(bc, bc);
    glm::vec3 center;
    // An obtuse or right angle puts the minimal sphere on the longest edge's midpoint.
    if (dab >= dac + dbc) {
      center = (a + b) * 0.5f;
    } else if (dac >= dab + dbc) {
      center = (a + c) * 0.5f;
    } else if (dbc >= dab + dac) {
      center = (b + c) * 0.5f;
    } else {
      // Circumcentre: a + (|ac|^2 (ab x ac) x ab + |ab|^2 ac x (ab x ac)) / (2 |ab x ac|^2).
      const glm::vec3 n = Cross(ab, ac);
      const float nn = Dot(n, n);
      const glm::vec3 u = Cross(n, ab), v = Cross(ac, n);
      const float denom = 2.0f * nn;
      center = a + ((u * dac + v * dab) / denom) / k;
      if (!(nn > 0.0f) || !std::isfinite(center.x + center.y + center.z)) center = (a + b + c) / 3.0f;
    }
    const float r = Max(Max(ScaledLength(a - center), ScaledLength(b - center)), ScaledLength(c - center));
    out[i] = glm::vec4(center, r * kRadiusMargin);
  });
  return out;
}

std::vector<glm::vec4> PassObjectSpheres(const SceneBuffers& scene) {
  using K = CGAL::Cartesian<double>;
  using Traits = CGAL::Min_sphere_of_points_d_traits_3<K, double>;
  using MinSphere = CGAL::Min_sphere_of_spheres_d<Traits>;
  std::vector<glm::vec4> out(scene.objects.size());
  ParallelFor(scene.objects.size(), [&](std::size_t o) {
    const std::uint32_t first = scene.objects[o].x, count = scene.objects[o].y;
    std::vector<K::Point_3> pts;
    pts.reserve(3 * count);
    for (std::uint32_t t = first; t < first + count; ++t) {
      const layout::Triangle& tri = scene.triangles[t];
      for (const glm::vec4* v : {&tri.v0, &tri.v1, &tri.v2}) pts.emplace_back(v->x, v->y, v->z);
    }
    MinSphere ms(pts.begin(), pts.end());
    auto it = ms.center_cartesian_begin();
    const glm::dvec3 cd(it[0], it[1], it[2]);
    // The float centre differs from CGAL's: measure every vertex from the rounded centre in double
    // and round the radius up so the float sphere contains them all.
    const glm::vec3 cf(cd);
    double r = 0.0;
    for (const auto& p : pts) r = std::max(r, glm::length(glm::dvec3(p.x(), p.y(), p.z()) - glm::dvec3(cf)));
    float rf = static_cast<float>(r);
    if (static_cast<double>(rf) < r) rf = std::nextafter(rf, INFINITY);
    out[o] = glm::vec4(cf, rf);
  });
  return out;
}

}  // namespace rayspace::emu
