// Exact ray-triangle decisions (CGAL, exact rational arithmetic) that settle disagreements between
// the frame's tracer and the oracle. Every float input is taken as the exact rational it encodes.
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/scene_buffers.h"

namespace rayspace::refs {

// Does the ray meet the triangle at some t with tmin < t < tmax (exactly)?
bool ExactHits(const gpu::Ray& ray, const gpu::Triangle& tri);

// Exact answer for a shadow ray: is any triangle other than info.y hit with tmin < t < tmax?
bool ExactOccluded(const gpu::Ray& ray, const SceneBuffers& scene);

// Exact closest hit: every primitive (other than info.y) hit at the exactly smallest t, in id order;
// empty for a miss. More than one means an exact tie (shared edge or vertex).
std::vector<std::uint32_t> ExactClosest(const gpu::Ray& ray, const SceneBuffers& scene);

}  // namespace rayspace::refs
