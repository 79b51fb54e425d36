// A conservative reject of a group of triangle spheres by one cone node, proved to imply that the
// float cone test (cone::Test, and so every lane of cone_simd.h) rejects each sphere of the group.
// The fused top level skips such groups: the pairs it writes are the ones the per-slot test gives,
// and the statistics still count every slot of the algorithm (docs/performance.md, "Group culling"
// gives the bound and why it holds).
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/layout.h"

namespace rayspace::emu::cone {

// Spheres per group: groups are aligned, group g of size G holds spheres [g * G, (g + 1) * G). The
// top level tries a coarse group first and the fine groups within it where the coarse one is hit.
inline constexpr std::uint32_t kCullGroup = 32, kCullCoarse = 256;

// Per group, in double: a centre, a radius containing every sphere of the group, and whether the
// bound may be used (every sphere finite, radius >= 0, magnitudes below kCullLimit).
struct SphereGroups {
  std::vector<double> x, y, z, r;
  std::vector<std::uint8_t> usable;
};
inline constexpr double kCullLimit = 0x1p100;
SphereGroups GroupsOf(std::span<const glm::vec4> spheres, std::uint32_t group_size);

// A node as the group test reads it; usable is false where no group may be rejected (a full cone,
// a non-finite or huge value, an axis or (cos, sin) not of unit length within 2^-20, a negative radius).
struct CullNode {
  double x, y, z, ax, ay, az, cosa, sina, reach;  // reach = node radius + |eps|
  bool usable;
};
CullNode CullNodeOf(const layout::ConeNode& n, float eps);

// True only if cone::Test(n, s, eps) is false for every sphere s of group g.
bool GroupMisses(const CullNode& n, const SphereGroups& groups, std::size_t g);

// The bound's relative margin, 2^-12 (docs/performance.md); tests plant a negative one to see a
// culled group that the test would have hit. Returns the previous margin.
inline constexpr double kCullMargin = 0x1p-12;
double SetCullMarginForTesting(double margin);

}  // namespace rayspace::emu::cone
