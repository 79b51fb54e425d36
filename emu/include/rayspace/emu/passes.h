// The emulated GPU passes of a frame. Each function mirrors one kernel's main(): it takes the pass's
// call (emu/calls.h), reads and writes flat std430 buffers (layout.h) and runs its elements through
// ParallelFor.
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/streams.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/layout.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

// ---- prep: bounding spheres ------------------------------------------------------------------
// Per-triangle bounding sphere (xyz centre, w radius): the smallest sphere through or around the
// three vertices, radius rounded outward so every vertex is inside in float arithmetic.
std::vector<glm::vec4> PassTriangleSpheres(const std::vector<layout::Triangle>& triangles);
// Minimal bounding sphere per object (sub-mesh), conservative in float. Host-side preprocessing.
std::vector<glm::vec4> PassObjectSpheres(const SceneBuffers& scene);

// ---- the frame's passes ------------------------------------------------------------------------
GBuffer PassRaster(const call::Raster& c);
std::vector<layout::Surface> PassSurfacesFromGBuffer(const call::SurfacesFromGBuffer& c);
std::vector<layout::Surface> PassSurfacesFromHits(const call::SurfacesFromHits& c);
// Three kernels, one per ray kind: PassRaygen runs the one for c.kind.
SparseRays PassRaygen(const call::Raygen& c);
SparseRays PassRaygenShadow(const call::Raygen& c);
SparseRays PassRaygenReflection(const call::Raygen& c);
SparseRays PassRaygenRefraction(const call::Raygen& c);
Trimmed PassTrim(const call::Trim& c);
// Exclusive scan as the kernels run it: reduce-then-scan over blocks, one workgroup a block
// (emu/workgroup_ops.h), for the pass `site` names (its dispatches, its planted faults).
std::vector<std::uint32_t> ExclusiveScan(In<std::uint32_t> in, std::uint32_t* total, const KernelSite& site = {"scan"});
void PassShade(const call::Shade& c);
std::vector<std::uint8_t> PassResolve(const call::Resolve& c);

// Call builders for the common cases (tests, benchmarks, the frame runner).
inline call::SurfacesFromGBuffer SurfacesCall(const layout::FrameConstants& fc, const GBuffer& g, const SceneBuffers& scene) {
  return {.frame = fc, .width = g.width, .height = g.height, .position = g.position, .normal = g.normal, .prim = g.prim,
          .scene = &scene};
}

}  // namespace rayspace::emu
