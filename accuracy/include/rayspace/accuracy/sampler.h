// `rayspace accuracy`, what is measured: cone-sphere and ray-triangle queries sampled uniformly
// from a CRSH frame's own work, and near-boundary variants of them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rayspace/emu/frame.h"
#include "rayspace/layout.h"
#include "rayspace/scene.h"

namespace rayspace::accuracy {

struct ConeQuery {
  layout::ConeNode node;
  glm::vec4 sphere;
};
struct TriQuery {
  layout::Ray ray;
  layout::Triangle tri;
};

// The queries of one scene: sampled from the frame, and moved to the boundary of the test.
struct Workload {
  std::vector<ConeQuery> cones, cones_edge;
  std::vector<TriQuery> tris, tris_edge;
  std::uint64_t cones_seen = 0, tris_seen = 0;  // queries the frame answered, of which the sample
};

// Renders the frame with the emulator's hierarchy passes, keeping up to `samples` queries of each
// kind, and builds their near-boundary variants (seeded: the same scene gives the same workload).
Workload SampleWorkload(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, std::size_t samples);

}  // namespace rayspace::accuracy
