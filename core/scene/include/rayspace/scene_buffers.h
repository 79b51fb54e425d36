// The scene flattened into the std430 buffers every pass reads, and the per-frame constants.
#pragma once
#include <vector>

#include "rayspace/kernel_functions.h"
#include "rayspace/layout.h"
#include "rayspace/scene.h"

namespace rayspace {

struct SceneBuffers {
  std::vector<layout::Triangle> triangles;
  std::vector<layout::TriangleNormals> normals;
  std::vector<layout::TriangleInfo> info;
  std::vector<layout::Material> materials;
  std::vector<layout::Light> lights;
  std::vector<glm::uvec4> objects;  // x first triangle, y triangle count
  glm::vec3 lo{0}, hi{0};           // bounding box of all vertices
  // One-sided triangles (`--backface-cull on`): a ray meets a triangle only from its front, the side
  // its normal (v1 - v0) x (v2 - v0) points to. The Embree oracle and the exact judge read it; of the
  // frame's tracers only --algo tl traces it (its lists built with culling), and the command line
  // refuses it with any other.
  bool one_sided = false;
};

SceneBuffers FlattenScene(const Scene& scene);

// Shadow rays per shading point: every light's samples (a point light has one), in light order;
// light l's first is lights[l].sampling.z. Slot s * ShadowSlots + j holds surface s's ray j.
inline std::size_t ShadowSlots(const std::vector<layout::Light>& lights) {
  std::size_t n = 0;
  for (const layout::Light& l : lights) n += l.sampling.y;
  return n;
}

// Relative shadow-ray shortening: a shadow ray stops at (1 - 2^-12) of the light-surface distance so
// the surface it ends on, and coplanar neighbours within rounding, never shadow it.
inline constexpr float kShadowTmaxFactor = 1.0f - 1.0f / 4096.0f;
// Absolute ray epsilon relative to the scene's diagonal.
inline constexpr double kRayEpsilonRelative = 1.0 / (1 << 20);

// Camera, image size and scene-dependent epsilons for one frame (host double math, rounded once).
layout::FrameConstants MakeFrameConstants(const Scene& scene, const SceneBuffers& buffers, int width, int height);

// Direction of the ray through the centre of pixel (px, py), written once for the kernels and the
// emulator (rayspace/kernel_functions.h).
using layout::PixelDirection;

}  // namespace rayspace
