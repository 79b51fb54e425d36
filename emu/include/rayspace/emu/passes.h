// The emulated GPU passes. Each function mirrors one kernel's main(): it reads and writes flat
// std430 buffers (layout.h) and runs its elements through ParallelFor.
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/layout.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

// ---- prep: bounding spheres ------------------------------------------------------------------
// Per-triangle bounding sphere (xyz centre, w radius): the smallest sphere through or around the
// three vertices, radius rounded outward so every vertex is inside in float arithmetic.
std::vector<glm::vec4> PassTriangleSpheres(const std::vector<gpu::Triangle>& triangles);
// Minimal bounding sphere per object (sub-mesh), conservative in float. Host-side preprocessing.
std::vector<glm::vec4> PassObjectSpheres(const SceneBuffers& scene);

// ---- raster: MRT G-buffer --------------------------------------------------------------------
struct GBuffer {
  int width = 0, height = 0;
  std::vector<glm::vec4> diffuse;   // rgb diffuse, a reflectivity
  std::vector<glm::vec4> specular;  // rgb specular, a shininess
  std::vector<glm::vec4> position;  // xyz world position, w 1 when covered
  std::vector<glm::vec4> normal;    // xyz shading normal, w transparency
  std::vector<std::uint32_t> prim;  // primitive id, kNoPrim when empty
  std::vector<float> depth;         // the depth attachment (1.0 clear value)
};
GBuffer PassRaster(const gpu::FrameConstants& fc, const SceneBuffers& scene);

// ---- surfaces: shading points of one generation --------------------------------------------------
std::vector<gpu::Surface> PassSurfacesFromGBuffer(const gpu::FrameConstants& fc, const GBuffer& g,
                                                   const SceneBuffers& scene);
// One surface per ray; rays that missed give empty slots.
std::vector<gpu::Surface> PassSurfacesFromHits(const std::vector<gpu::Ray>& rays,
                                               const std::vector<std::uint64_t>& hits, const SceneBuffers& scene);

// ---- raygen: sparse ray arrays with head flags -----------------------------------------------------
struct SparseRays {
  std::vector<gpu::Ray> rays;       // one slot per (surface[, light])
  std::vector<std::uint32_t> flags;  // 1 where the slot holds a ray
};
// Slot s * lights + l: shadow ray from light l towards surface s (thesis eqs. 3.1-3.2).
SparseRays PassRaygenShadow(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                            const SceneBuffers& scene);
// Slot s: mirror ray (eqs. 3.3-3.4) where the surface's material reflects.
SparseRays PassRaygenReflection(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                const SceneBuffers& scene);
// Slot s: refracted ray (eqs. 3.5-3.7) where the material is transparent; none on total internal reflection.
SparseRays PassRaygenRefraction(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                const SceneBuffers& scene);

// ---- trim: order-preserving compaction (exclusive scan of flags + scatter) ---------------------------
struct Trimmed {
  std::vector<gpu::Ray> rays;          // dense, in slot order
  std::vector<std::uint32_t> offsets;  // exclusive scan of flags: dense index of slot i when flags[i]
};
Trimmed PassTrim(const SparseRays& sparse);
// Exclusive scan with a fixed blocking (the result does not depend on the thread count).
std::vector<std::uint32_t> ExclusiveScan(const std::vector<std::uint32_t>& in, std::uint32_t* total);

// ---- shade: Phong/Lambert with attenuation (eq. 3.19) into a fixed-point accumulator --------------
// `shadow_offsets` / `shadow_flags` map slot s * lights + l to its shadow ray; `occluded` is per ray.
void PassShade(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
               const std::vector<std::uint32_t>& shadow_flags, const std::vector<std::uint32_t>& shadow_offsets,
               const std::vector<std::uint32_t>& occluded, const SceneBuffers& scene,
               std::vector<std::uint64_t>& accum);

// ---- resolve: fixed point -> 8-bit RGB with display gamma 2 (sqrt) --------------------------------
std::vector<std::uint8_t> PassResolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum);

}  // namespace rayspace::emu
