// `rayspace accuracy`, the traversal lists' sphere test (docs/traversal-lists.md): queries sampled
// from an `--algo tl` frame's walks, each mode against the exact answer, and the frame with each mode.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rayspace/accuracy/measure.h"
#include "rayspace/emu/frame.h"
#include "rayspace/scene.h"

namespace rayspace::accuracy {

// Does the ray's part [tmin, tlimit] meet the sphere?
struct SphereQuery {
  glm::vec3 org, dir;
  float tmin = 0, tlimit = 0;
  glm::vec4 sphere;
};

struct SphereWorkload {
  std::vector<SphereQuery> spheres, spheres_edge;
  std::uint64_t seen = 0;  // sphere tests the frame ran, of which the sample
};

// Renders the frame with the traversal lists, keeping up to `samples` sphere tests (seeded), and moves
// each sphere to touch the ray's part (radius within 2^-20 of the distance) for the near-boundary set.
SphereWorkload SampleSpheres(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, std::size_t samples);

// Each mode (float without margins, the conservative test, CGAL) on both sets; rows appended.
void MeasureSphereModes(const SphereWorkload& w, std::vector<Row>& rows, double min_time);
// The --algo tl frame with each mode in its walks, against the frame with the exact test.
std::vector<EndToEnd> SphereEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo);

}  // namespace rayspace::accuracy
