// Stages of the emulated raster, exposed for the known-answer tests in tests/raster_test.cpp.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

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

struct Fragment {
  bool discard = false;
  float depth = 1.0f;
  float t = 0.0f;
  glm::vec3 position{0};
};

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
