// Stages of the emulated raster, exposed for the known-answer tests in tests/raster_test.cpp.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/layout.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

// Interpolated shading normal at p on triangle prim (barycentric weights from signed sub-areas, the
// fix of the thesis's eq. 3.17); the face normal where the interpolation degenerates. Unit length.
glm::vec3 ShadingNormal(const SceneBuffers& scene, std::uint32_t prim, glm::vec3 p);

namespace raster {

inline constexpr int kMaxClipVerts = 9;  // a triangle clipped by 6 planes

// Fixed-point triangle after setup: edge functions E_e(x, y) = c - dcdx * x + dcdy * y (> 0 inside).
struct Setup {
  std::int64_t c[3], dcdx[3], dcdy[3];
  int x0, x1, y0, y1;  // pixel bounding box clamped to the framebuffer
  std::uint32_t prim;
};

// A fragment as the fragment stage computes it, templated over the scalar like the other kernel
// math (rayspace/emu/intersect.h): float is raster.frag's arithmetic; verify::SpecReal what a
// conformant device may compute (the relaxed raster model, docs/numerics.md).
template <typename S>
struct FragmentOf {
  bool discard = false;
  S depth{1.0f};
  S t{0.0f};
  Vec3<S> position{S(0.0f)};
};
using Fragment = FragmentOf<float>;

// The depth and position of pixel (px, py) on triangle (v0, v1, v2): the pixel-centre ray met with
// the triangle's plane. Edges and normal are scaled by powers of two (exact; tt unchanged) so scenes
// from 2^-60 to 2^60 neither overflow nor flush (the graphics path runs with FTZ/DAZ).
template <typename S>
FragmentOf<S> ShadeFragmentOf(const layout::FrameConstants& fc, Vec3<S> v0, Vec3<S> v1, Vec3<S> v2, Vec3<S> d) {
  FragmentOf<S> f;
  const Vec3<S> e1 = v1 - v0, e2 = v2 - v0;
  const S ke = InversePowerOfTwo(MaxAbs(e1, e2));
  const Vec3<S> n0 = Cross(e1 * ke, e2 * ke);
  const Vec3<S> n = n0 * InversePowerOfTwo(MaxAbs(n0, n0));
  const Vec3<S> eye(S(fc.eye.x), S(fc.eye.y), S(fc.eye.z));
  const S tt = Dot(v0 - eye, n) / Dot(d, n);
  if (!(tt > S(0.0f)) || !(tt <= S(3.40282347e38f))) {
    f.discard = true;
    return f;
  }
  f.depth = Min(tt * S(fc.params.y), S(1.0f));
  f.t = tt;
  f.position = Vec3<S>(eye.x + tt * d.x, eye.y + tt * d.y, eye.z + tt * d.z);
  return f;
}

glm::vec4 VertexStage(const glm::mat4& view_proj, glm::vec3 p);
glm::vec2 WindowFused(const glm::vec4& clip, float half_w, float half_h);
glm::vec2 WindowUnfused(const glm::vec4& clip, float half_w, float half_h);
// Clips against the view volume; returns the polygon's window positions (0 when culled).
int ClipTriangle(const std::array<glm::vec4, 3>& clip, float half_w, float half_h,
                 std::array<glm::vec2, kMaxClipVerts>& out);
// Snaps and sets up one triangle; false when culled (zero area) or outside the framebuffer.
bool SetupTriangle(glm::vec2 w0, glm::vec2 w1, glm::vec2 w2, int width, int height, Setup& s);
bool Covers(const Setup& s, int px, int py);
std::vector<Setup> SetupAll(const layout::FrameConstants& fc, const std::vector<layout::Triangle>& tris);
Fragment ShadeFragment(const layout::FrameConstants& fc, const SceneBuffers& scene, std::uint32_t prim, int px, int py);

}  // namespace raster
}  // namespace rayspace::emu
