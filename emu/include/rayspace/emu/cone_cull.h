// A conservative reject of a group of triangle spheres by one cone node, proved to imply that the
// float cone test (cone::Test, and so every lane of cone_simd.h) rejects each sphere of the group.
// The fused top level skips such groups: the pairs it writes are the ones the per-slot test gives,
// and the statistics still count every slot of the algorithm (docs/performance.md, "Group culling"
// gives the bound and why it holds).
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "rayspace/contract.h"
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
  double margin;  // the bound's relative margin in force when the node was made (kCullMargin)
};
CullNode CullNodeOf(const layout::ConeNode& n, float eps);

// True only if cone::Test(n, s, eps) is false for every sphere s of group g.
bool GroupMisses(const CullNode& n, const SphereGroups& groups, std::size_t g);

// The bound's relative margin, 2^-12 (docs/performance.md); tests plant a negative one
// (Settings::cull_margin) to see a culled group that the test would have hit.
inline constexpr double kCullMargin = 0x1p-12;

// ---- The same reject as a device computes it (gpu/shaders/cone_cull.glsl, its twin) ---------------
// The fused top-level kernel bounds each subgroup's triangles of a round in float, by subgroup
// min/max, and tests the bound against the subgroup's rows: lane r against row r's node. Margins
// 2^-11 (contract.h) cover float evaluation on any conformant device (docs/performance.md, "Group
// culling on the device"). Only for --cone-test conservative, as GroupMisses.

// A sphere the bound may include: finite, |x|, |y|, |z| and r below kDeviceCullLimit, r >= 0.
bool DeviceCullable(glm::vec4 s);
// |s - c| + r in float, one member's reach from the centre c.
float DeviceReach(glm::vec4 s, glm::vec3 c);
// A node the bound may judge: finite and below kDeviceCullLimit, radius >= 0, cos > -1, |A|^2 and
// cos^2 + sin^2 within kDeviceCullUnit of 1 as computed in float.
bool DeviceCullableNode(const layout::ConeNode& n);
// True only if cone::Test(n, s, eps) is false for every sphere s with |s - group.xyz| + s.w <= group.w
// (group.w already widened by kDeviceCullRadiusUp). `margin`: tests plant smaller ones.
bool DeviceGroupMisses(const layout::ConeNode& n, glm::vec4 group, float eps, float margin = layout::kDeviceCullMargin);
// The kernel's group of `spheres` (all members cullable, else nullopt), reduced as the subgroup does:
// the box by min/max, its centre, the largest reach widened by kDeviceCullRadiusUp.
std::optional<glm::vec4> DeviceGroupOf(std::span<const glm::vec4> spheres);

}  // namespace rayspace::emu::cone
