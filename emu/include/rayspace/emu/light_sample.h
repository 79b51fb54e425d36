// Where sample k of a light lies for one shading point (docs/area-lights.md), templated over the
// scalar like intersect.h: float in the emulated passes, verify::SpecReal when the diff bounds what a
// device may compute. Mirrors gpu/shaders/light_sample.glsl; the stratified point and the unit circle
// are shared with the kernels (rayspace/kernel_functions.h).
#pragma once
#include "rayspace/emu/intersect.h"
#include "rayspace/kernel_functions.h"

namespace rayspace::emu {

// The sample count of a light (1 for a point light).
inline std::uint32_t LightSamples(const layout::Light& l) { return l.sampling.y; }

// Two corners of a box holding every sample point of the light (its position for a point light),
// widened by a relative 2^-20 against the rounding of the sample map.
inline void LightCorners(const layout::Light& l, glm::vec3& lo, glm::vec3& hi) {
  const glm::vec3 c(l.position.x, l.position.y, l.position.z);
  glm::vec3 half(0.0f);
  if (l.sampling.x == layout::kLightSphere) half = glm::vec3(l.position.w);
  if (l.sampling.x == layout::kLightRect || l.sampling.x == layout::kLightDisk)
    half = glm::abs(glm::vec3(l.axis_u)) + glm::abs(glm::vec3(l.axis_v));
  half = half + (glm::abs(c) + half) * 9.5367431640625e-07f;
  lo = c - half;
  hi = c + half;
}

// Sample k of light `index` at the shading point with sampler key `key`. A point light's one sample
// is its position, untouched.
template <typename S>
Vec3<S> LightSamplePoint(const layout::Light& light, std::uint32_t index, std::uint32_t key, std::uint32_t k) {
  using V = Vec3<S>;
  const V c(S(light.position.x), S(light.position.y), S(light.position.z));
  const std::uint32_t shape = light.sampling.x;
  if (shape == layout::kLightPoint) return c;
  const glm::vec2 ab = layout::StratifiedPoint(key, index, k, light.sampling.w, light.axis_u.w, light.axis_v.w);
  const V u(S(light.axis_u.x), S(light.axis_u.y), S(light.axis_u.z));
  const V v(S(light.axis_v.x), S(light.axis_v.y), S(light.axis_v.z));
  if (shape == layout::kLightRect) {
    const S x = S(ab.x * 2.0f) - S(1.0f), y = S(ab.y * 2.0f) - S(1.0f);
    return V((c.x + x * u.x) + y * v.x, (c.y + x * u.y) + y * v.y, (c.z + x * u.z) + y * v.z);
  }
  const glm::vec2 cs = layout::UnitCircle(ab.y);
  if (shape == layout::kLightDisk) {
    const S r = Sqrt(S(ab.x));
    const S x = r * S(cs.x), y = r * S(cs.y);
    return V((c.x + x * u.x) + y * v.x, (c.y + x * u.y) + y * v.y, (c.z + x * u.z) + y * v.z);
  }
  // kLightSphere: z uniform in [-1, 1] gives a uniform point of the sphere (Archimedes).
  const float z = 1.0f - ab.x * 2.0f;
  const S rr = Sqrt(S(1.0f - z * z));
  const S radius(light.position.w);
  return V(c.x + radius * (rr * S(cs.x)), c.y + radius * (rr * S(cs.y)), c.z + radius * S(z));
}

}  // namespace rayspace::emu
