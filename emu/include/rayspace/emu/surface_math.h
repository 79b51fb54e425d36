// The shading normal of a hit (barycentric weights from signed sub-areas), templated over the scalar
// like intersect.h: float in the emulated passes, verify::SpecReal when the diff bounds what a device
// may compute. Mirrors gpu/shaders/shading_normal.glsl.
#pragma once
#include "rayspace/emu/intersect.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

template <typename S>
Vec3<S> ShadingNormalOf(const SceneBuffers& scene, std::uint32_t prim, Vec3<S> p) {
  using V = Vec3<S>;
  const layout::Triangle& t = scene.triangles[prim];
  const layout::TriangleNormals& tn = scene.normals[prim];
  const V v0(Xyz(t.v0)), v1(Xyz(t.v1)), v2(Xyz(t.v2));
  // Everything relative to p and scaled by one power of two: the weights are ratios of degree-4
  // products, unchanged by the scaling, which keeps them in range for scenes from 2^-60 to 2^60.
  const V e1 = v1 - v0, e2 = v2 - v0, q0 = v0 - p, q1 = v1 - p, q2 = v2 - p;
  const S k = InversePowerOfTwo(Max(Max(MaxAbs(e1, e2), MaxAbs(q0, q1)), MaxAbs(q2, q2)));
  const V n = Cross(e1 * k, e2 * k);
  // Signed sub-triangle areas (times |n|); their ratios are the barycentric weights. The thesis's
  // eq. 3.17 normalises these cross products, which loses the areas it needs.
  const S a0 = Dot(Cross(q1 * k, q2 * k), n);
  const S a1 = Dot(Cross(q2 * k, q0 * k), n);
  const S a2 = Dot(Cross(q0 * k, q1 * k), n);
  const S sum = (a0 + a1) + a2;
  V s(S(0.0f), S(0.0f), S(0.0f));
  if (sum != S(0.0f)) {
    const S w0 = a0 / sum, w1 = a1 / sum, w2 = a2 / sum;
    for (int j = 0; j < 3; ++j) s[j] = (S(tn.n0[j]) * w0 + S(tn.n1[j]) * w1) + S(tn.n2[j]) * w2;
  }
  const S len2 = SelfDot(s);
  if (!(len2 > S(0.0f)) || !(len2 <= S(3.0e38f))) {
    const S nl = SelfDot(n);
    if (!(nl > S(0.0f)) || !(nl <= S(3.0e38f))) return V(Xyz(tn.n0));  // degenerate triangle: stored normal
    return Normalize(n);
  }
  return Normalize(s);
}

}  // namespace rayspace::emu
