#include "kernel_cases.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "rayspace/emu/calls.h"
#include "rayspace/verify/call_codec.h"

namespace rayspace::mutate {
namespace {

using glm::vec4;
using layout::ConeNode;

// A node of one ray or of parallel rays: its axis, cosine 1 and the given sine, one ray below.
ConeNode Node(vec4 sphere, glm::vec3 axis, float cosine, float sine, float rays = 1.0f) {
  return {sphere, vec4(axis, cosine), vec4(sine, rays, 0.0f, 0.0f)};
}

// Parents whose children meet every boundary of the cone union: identical degenerate cones (the
// union's sine is exactly 0), opposite axes (the axes' sum is zero), a full-sphere child, two cones
// that together exceed a hemisphere on both sides (the sine goes negative), a sine of 2^-149.
verify::BufferSet ParentsCall(std::uint32_t child_merge) {
  const float tiny = std::numeric_limits<float>::denorm_min();
  const glm::vec3 z(0, 0, 1);
  const std::vector<ConeNode> below = {
      Node({0, 0, 0, 0}, z, 1, 0), Node({1, 0, 0, 0}, z, 1, 0),                                 // sine 0 exactly
      Node({0, 0, 0, 0}, z, 1, 0), Node({0, 1, 0, 0}, -z, 1, 0),                                // x1 + x2 = 0
      Node({0, 0, 0, 2}, {1, 0, 0}, -1, 0, 4), Node({3, 0, 0, 1}, z, 0.5f, 0.8660254f),        // a full child
      Node({0, 0, 0, 1}, z, -0.5f, 0.8660254f), Node({0, 0, 1, 1}, {0, 0.6f, -0.8f}, 0.9f, 0.43588989f),  // sine < 0
      Node({0, 0, 0, 0}, z, 1, tiny), Node({2, 0, 0, 0}, z, 1, tiny), Node({4, 0, 0, 0}, z, 1, 0),       // sine 2^-149
      Node({0, 0, 0, 1}, {1, 0, 0}, 0, 1), Node({0, 0, 0, 1}, {-1, 0, 0}, 0, 1),              // two hemispheres
  };
  const std::vector<std::uint32_t> first = {0, 2, 4, 6, 8, 11, 13};
  emu::call::BuildParents c;
  c.below = below;
  c.first = first;
  c.child_merge = child_merge;
  return verify::EncodeCall(c);
}

layout::Ray RayAt(glm::vec3 o, glm::vec3 d) {
  layout::Ray r{};
  r.origin_tmin = vec4(o, 0.0f);
  r.direction_tmax = vec4(d, std::numeric_limits<float>::max());
  r.info = glm::uvec4(0, layout::kNoPrim, layout::kRayReflection, 0);
  r.weight = vec4(1, 1, 1, 0);
  return r;
}

// A unit direction (normalised in float as the kernels do) whose float dot with itself is above 1:
// the cosines computed from it leave [-1, 1] by one ulp, which the clamps must catch.
glm::vec3 LongUnit() {
  for (int i = 1; i < 100000; ++i) {
    const glm::vec3 v(1.0f, static_cast<float>(i) * 1.0e-3f, 0.5f);
    const float l = std::sqrt((v.x * v.x + v.y * v.y) + v.z * v.z);
    const glm::vec3 d(v.x / l, v.y / l, v.z / l);
    const float dd = (d.x * d.x + d.y * d.y) + d.z * d.z;
    if (dd > 1.0f) return d;
  }
  return glm::vec3(0, 0, 1);  // not reached with IEEE float (the search finds one within a few steps)
}

// Leaves over parallel, antiparallel and lone rays, directions with tied largest components, and a
// direction slightly longer than 1.
verify::BufferSet LeavesCall() {
  const glm::vec3 z(0, 0, 1), u = LongUnit();
  const float h = 0.70710677f;
  const glm::vec3 d = glm::vec3(1, 2, 3) / std::sqrt(14.0f);
  const std::vector<layout::Ray> rays = {RayAt({0, 0, 0}, z),  RayAt({1, 0, 0}, z),       // parallel
          RayAt({0, 0, 0}, z),  RayAt({0, 1, 0}, -z),      // antiparallel on an axis
          RayAt({2, 2, 2}, z),                             // alone
          RayAt({0, 0, 0}, u),  RayAt({0, 0, 1}, u),       // |u| above 1 in float
          RayAt({0, 0, 0}, d),  RayAt({1, 1, 1}, -d),      // antiparallel off the axes
          RayAt({0, 0, 0}, {h, 0, h}), RayAt({0, 0, 0}, {0, h, h}), RayAt({0, 0, 0}, {h, h, 0})};  // ties
  const std::vector<std::uint32_t> first = {0, 2, 4, 5, 7, 9, 12};
  std::vector<std::uint32_t> order;
  for (std::uint32_t i = 0; i < rays.size(); ++i) order.push_back(i);
  emu::call::BuildLeaves c;
  c.rays = rays;
  c.order = order;
  c.first = first;
  return verify::EncodeCall(c);
}

// Fixed-point channels next to every rounding step of resolve (v = sqrt(c) x 255 + 0.5 truncated):
// a window of accumulator values about each c where v crosses an integer, so that a scale or an
// offset one ulp off changes a byte.
verify::BufferSet ResolveCall() {
  std::vector<std::uint64_t> accum;
  const double scale = 4294967296.0;  // layout::kAccumScale
  for (int k = 1; k <= 255; ++k) {
    const double g = (k - 0.5) / 255.0;
    const auto centre = static_cast<std::int64_t>(g * g * scale);
    for (std::int64_t a = centre - 96; a < centre + 96; ++a) accum.push_back(static_cast<std::uint64_t>(std::max<std::int64_t>(a, 0)));
  }
  for (const std::uint64_t a : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{4294967295u}, std::uint64_t{4294967296u},
                                std::uint64_t{4294967297u}, std::uint64_t{1} << 40})
    accum.push_back(a);
  while (accum.size() % 3 != 0) accum.push_back(0);
  emu::call::Resolve c;
  c.accum = accum;
  return verify::EncodeCall(c);
}

}  // namespace

std::vector<KernelCase> KernelCases() {
  return {
      {"build-parents-boundaries", "build", "build.parents",
       "children whose cone union has sine 0, opposite axes, a full child, a negative sine, a sine of 2^-149",
       ParentsCall(layout::kChildMergeSequential)},
      {"build-parents-boundaries-pairwise", "build", "build.parents", "the same children merged pairwise",
       ParentsCall(layout::kChildMergePairwise)},
      {"build-leaves-boundaries", "build", "build.leaves",
       "parallel, antiparallel and lone rays, tied direction components, a direction whose float length exceeds 1",
       LeavesCall()},
      {"resolve-rounding", "resolve", "resolve", "accumulator values about every step of the 8-bit rounding",
       ResolveCall()},
  };
}

}  // namespace rayspace::mutate
