#include <cmath>
#include <limits>

#include "rayspace/error.h"
#include "rayspace/scene_buffers.h"

namespace rayspace {
namespace {

// The strata grid of n samples: cols x rows with cols the smallest divisor of n at least sqrt(n);
// the angle of a disk or sphere gets the larger count.
glm::uvec2 StrataGrid(std::uint32_t n, LightShape shape) {
  std::uint32_t big = 1;
  while (big * big < n || n % big != 0) ++big;
  const std::uint32_t small = n / big;
  return shape == LightShape::kRect ? glm::uvec2(big, small) : glm::uvec2(small, big);
}

// The light as the kernels read it (rayspace/layout.h). The shape's half-axes are computed in double
// and rounded once; a rect's width runs along normal x (0, 0, 1) (x for a light facing down), or
// normal x (1, 0, 0) when the normal is nearly z.
layout::Light MakeLight(const LightDesc& l, std::uint32_t first_slot) {
  layout::Light g{};
  g.position = glm::vec4(l.position, l.shape == LightShape::kSphere ? l.radius : (l.shape == LightShape::kPoint ? 1.0f : 0.0f));
  g.color_intensity = glm::vec4(l.color, l.intensity);
  const auto n = static_cast<std::uint32_t>(l.samples);
  g.attenuation = glm::vec4(l.attenuation, static_cast<float>(1.0 / n));
  const glm::uvec2 grid = StrataGrid(n, l.shape);
  const glm::dvec3 nn(l.normal);
  const glm::dvec3 e1 = glm::normalize(glm::cross(nn, std::abs(nn.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 e2 = glm::cross(nn, e1);
  glm::dvec3 u(0), v(0);
  if (l.shape == LightShape::kRect) u = e1 * (0.5 * l.size.x), v = e2 * (0.5 * l.size.y);
  if (l.shape == LightShape::kDisk) u = e1 * double(l.radius), v = e2 * double(l.radius);
  g.axis_u = glm::vec4(glm::vec3(u), static_cast<float>(1.0 / grid.x));
  g.axis_v = glm::vec4(glm::vec3(v), static_cast<float>(1.0 / grid.y));
  const std::uint32_t shape = l.shape == LightShape::kRect     ? layout::kLightRect
                              : l.shape == LightShape::kDisk   ? layout::kLightDisk
                              : l.shape == LightShape::kSphere ? layout::kLightSphere
                                                               : layout::kLightPoint;
  g.sampling = glm::uvec4(shape, n, first_slot, grid.x);
  return g;
}

}  // namespace

SceneBuffers FlattenScene(const Scene& scene) {
  SceneBuffers b;
  const std::size_t n = scene.TriangleCount();
  b.triangles.reserve(n);
  b.normals.reserve(n);
  b.info.reserve(n);
  b.lo = glm::vec3(std::numeric_limits<float>::infinity());
  b.hi = -b.lo;
  for (std::size_t oi = 0; oi < scene.objects.size(); ++oi) {
    const Object& o = scene.objects[oi];
    b.objects.emplace_back(static_cast<std::uint32_t>(b.triangles.size()), static_cast<std::uint32_t>(o.TriangleCount()), 0, 0);
    for (std::size_t t = 0; t < o.TriangleCount(); ++t) {
      layout::Triangle tri;
      layout::TriangleNormals nrm;
      glm::vec4* tv[3] = {&tri.v0, &tri.v1, &tri.v2};
      glm::vec4* nv[3] = {&nrm.n0, &nrm.n1, &nrm.n2};
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = o.positions[3 * t + k];
        *tv[k] = glm::vec4(p, 1.0f);
        *nv[k] = glm::vec4(o.normals[3 * t + k], 0.0f);
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
      }
      b.triangles.push_back(tri);
      b.normals.push_back(nrm);
      b.info.push_back({glm::uvec4(o.material[t], static_cast<std::uint32_t>(oi), 0, 0)});
    }
  }
  for (const MaterialDesc& m : scene.materials) {
    layout::Material g;
    g.diffuse_reflectivity = glm::vec4(m.diffuse, m.reflectivity);
    g.specular_shininess = glm::vec4(m.specular, m.shininess);
    g.transparency_ior = glm::vec4(m.transparency, m.ior, 0, 0);
    b.materials.push_back(g);
  }
  std::uint32_t first_slot = 0;
  for (const LightDesc& l : scene.lights) {
    b.lights.push_back(MakeLight(l, first_slot));
    first_slot += static_cast<std::uint32_t>(l.samples);
  }
  return b;
}

layout::FrameConstants MakeFrameConstants(const Scene& scene, const SceneBuffers& b, int width, int height) {
  RS_CHECK(width > 0 && height > 0);
  const CameraDesc& cam = scene.camera;
  const glm::dvec3 eye(cam.eye);
  const glm::dvec3 fwd = glm::normalize(glm::dvec3(cam.target) - eye);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, glm::dvec3(cam.up)));
  const glm::dvec3 up = glm::cross(right, fwd);
  const double ty = std::tan(glm::radians(static_cast<double>(cam.fov_y_deg)) * 0.5);
  const double tx = ty * width / height;

  // Far plane beyond every vertex (and the lights, for completeness); near at a fixed ratio.
  double far = 0.0;
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 corner((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
    far = std::max(far, glm::length(corner - eye));
  }
  // Relative margins only, so that scaling the scene by a power of two scales every constant exactly
  // (tests/metamorphic_test.cpp).
  far = far > 0.0 ? far * 1.01 : 1.0;
  const double near = far * 1e-4;

  // Clip space (Vulkan): x = xc/tx, y = -yc/ty (y points down), z = a*zc + b in [0, w], w = zc.
  const double a = far / (far - near), bz = -far * near / (far - near);
  glm::dmat4 m(0.0);  // column-major: m[col][row]
  for (int c = 0; c < 3; ++c) {
    m[c][0] = right[c] / tx;
    m[c][1] = -up[c] / ty;
    m[c][2] = a * fwd[c];
    m[c][3] = fwd[c];
  }
  m[3][0] = -glm::dot(right, eye) / tx;
  m[3][1] = glm::dot(up, eye) / ty;
  m[3][2] = -a * glm::dot(fwd, eye) + bz;
  m[3][3] = -glm::dot(fwd, eye);

  layout::FrameConstants fc{};
  fc.view_proj = glm::mat4(m);
  fc.eye = glm::vec4(glm::vec3(eye), 1.0f);
  const glm::dvec3 origin = fwd + (1.0 / width - 1.0) * tx * right + (1.0 - 1.0 / height) * ty * up;
  fc.pixel_origin = glm::vec4(glm::vec3(origin), 0.0f);
  fc.pixel_dx = glm::vec4(glm::vec3(2.0 * tx / width * right), 0.0f);
  fc.pixel_dy = glm::vec4(glm::vec3(-2.0 * ty / height * up), 0.0f);
  fc.scene_lo = glm::vec4(b.lo, 0.0f);
  fc.scene_hi = glm::vec4(b.hi, 0.0f);
  const double diag = glm::length(glm::dvec3(b.hi) - glm::dvec3(b.lo));
  fc.params = glm::vec4(static_cast<float>(std::max(diag, 1e-30) * kRayEpsilonRelative), static_cast<float>(1.0 / far),
                        kShadowTmaxFactor, 0.0f);
  fc.dims = glm::uvec4(width, height, static_cast<std::uint32_t>(b.triangles.size()),
                       static_cast<std::uint32_t>(b.lights.size()));
  return fc;
}

}  // namespace rayspace
