// The group reject of cone_cull.h. Why the margins suffice is docs/performance.md, "Group culling";
// in short: f(p) = |v x A| cos - (v.A) sin, v = p - apex, is Lipschitz with constant
// L = |A| sqrt(cos^2 + sin^2) <= 1 + 2^-20, every branch of the float test that accepts a sphere
// (p, r) implies f(p) <= (r + rn) (1 + 2^-17) + |eps| (1 + 2^-20) + 2^-16 |v|, and a group whose
// centre g clears (rho + rn + |eps|) (1 + 2^-12) + 2^-12 |g - apex| clears that for each member.
#include "rayspace/emu/cone_cull.h"
#include "rayspace/settings.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rayspace::emu::cone {
namespace {

constexpr double kUnitTolerance = 0x1p-20;

bool Bounded(double v) { return std::isfinite(v) && std::abs(v) < kCullLimit; }

}  // namespace

SphereGroups GroupsOf(std::span<const glm::vec4> spheres, std::uint32_t group_size) {
  const std::size_t n = (spheres.size() + group_size - 1) / group_size;
  SphereGroups g{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
                 std::vector<std::uint8_t>(n, 0)};
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t b = i * group_size, e = std::min(spheres.size(), b + group_size);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    bool usable = true;
    for (std::size_t k = b; k < e; ++k) {
      const glm::vec4 s = spheres[k];
      usable = usable && Bounded(s.x) && Bounded(s.y) && Bounded(s.z) && Bounded(s.w) && s.w >= 0.0f;
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], double(s[a])), hi[a] = std::max(hi[a], double(s[a]));
    }
    if (!usable) continue;
    const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]), cz = 0.5 * (lo[2] + hi[2]);
    double rho = 0.0;
    for (std::size_t k = b; k < e; ++k) {
      const glm::vec4 s = spheres[k];
      const double dx = s.x - cx, dy = s.y - cy, dz = s.z - cz;
      rho = std::max(rho, std::sqrt(dx * dx + dy * dy + dz * dz) + double(s.w));
    }
    // Double's rounding in rho is far below the bound's margin; this covers it anyway.
    g.x[i] = cx, g.y[i] = cy, g.z[i] = cz, g.r[i] = rho * (1.0 + 0x1p-40);
    g.usable[i] = 1;
  }
  return g;
}

CullNode CullNodeOf(const layout::ConeNode& n, float eps) {
  CullNode c{n.sphere.x, n.sphere.y, n.sphere.z, n.cone.x, n.cone.y, n.cone.z, n.cone.w, n.extra.x,
             double(n.sphere.w) + std::abs(double(eps)), false, CurrentSettings().cull_margin.value_or(kCullMargin)};
  const double values[] = {c.x, c.y, c.z, c.ax, c.ay, c.az, c.cosa, c.sina, double(n.sphere.w), c.reach};
  const bool finite = std::all_of(std::begin(values), std::end(values), Bounded);
  const double axis2 = c.ax * c.ax + c.ay * c.ay + c.az * c.az, angle2 = c.cosa * c.cosa + c.sina * c.sina;
  c.usable = finite && n.sphere.w >= 0.0f && c.cosa > -1.0 && std::abs(axis2 - 1.0) <= kUnitTolerance &&
             std::abs(angle2 - 1.0) <= kUnitTolerance;
  return c;
}

bool GroupMisses(const CullNode& n, const SphereGroups& groups, std::size_t g) {
  if (!n.usable || !groups.usable[g]) return false;
  const double vx = groups.x[g] - n.x, vy = groups.y[g] - n.y, vz = groups.z[g] - n.z;
  const double a = vx * n.ax + vy * n.ay + vz * n.az;
  const double cx = vy * n.az - vz * n.ay, cy = vz * n.ax - vx * n.az, cz = vx * n.ay - vy * n.ax;
  const double b = std::sqrt(cx * cx + cy * cy + cz * cz);
  const double f = b * n.cosa - a * n.sina;
  const double len = std::sqrt(vx * vx + vy * vy + vz * vz);
  return f > (groups.r[g] + n.reach) * (1.0 + n.margin) + n.margin * len;
}


bool DeviceCullable(glm::vec4 s) {
  const float lim = layout::kDeviceCullLimit;
  return std::abs(s.x) < lim && std::abs(s.y) < lim && std::abs(s.z) < lim && s.w >= 0.0f && s.w < lim;
}

float DeviceReach(glm::vec4 s, glm::vec3 c) {
  const float dx = s.x - c.x, dy = s.y - c.y, dz = s.z - c.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz) + s.w;
}

bool DeviceCullableNode(const layout::ConeNode& n) {
  const float unit = layout::kDeviceCullUnit;
  const float axis2 = n.cone.x * n.cone.x + n.cone.y * n.cone.y + n.cone.z * n.cone.z;
  const float angle2 = n.cone.w * n.cone.w + n.extra.x * n.extra.x;
  return DeviceCullable(n.sphere) && n.cone.w > -1.0f && std::abs(axis2 - 1.0f) <= unit && std::abs(angle2 - 1.0f) <= unit;
}

bool DeviceGroupMisses(const layout::ConeNode& n, glm::vec4 group, float eps, float margin) {
  if (!DeviceCullableNode(n) || !DeviceCullable(group) || !(std::abs(eps) < layout::kDeviceCullLimit)) return false;
  const float vx = group.x - n.sphere.x, vy = group.y - n.sphere.y, vz = group.z - n.sphere.z;
  const float ax = n.cone.x, ay = n.cone.y, az = n.cone.z;
  const float a = vx * ax + vy * ay + vz * az;
  const float cx = vy * az - vz * ay, cy = vz * ax - vx * az, cz = vx * ay - vy * ax;
  const float b = std::sqrt(cx * cx + cy * cy + cz * cz);
  const float f = b * n.cone.w - a * n.extra.x;
  const float len = std::sqrt(vx * vx + vy * vy + vz * vz);
  const float bound = (group.w + n.sphere.w + std::abs(eps)) * (1.0f + margin) + margin * len + layout::kDeviceCullFloor;
  return f > bound;
}

std::optional<glm::vec4> DeviceGroupOf(std::span<const glm::vec4> spheres) {
  const float lim = layout::kDeviceCullLimit;
  glm::vec3 lo(lim), hi(-lim);
  for (const glm::vec4& s : spheres) {
    if (!DeviceCullable(s)) return std::nullopt;
    lo = glm::min(lo, glm::vec3(s)), hi = glm::max(hi, glm::vec3(s));
  }
  const glm::vec3 c = (lo + hi) * 0.5f;
  float reach = 0.0f;
  for (const glm::vec4& s : spheres) reach = std::max(reach, DeviceReach(s, c));
  return glm::vec4(c, reach * layout::kDeviceCullRadiusUp);
}

}  // namespace rayspace::emu::cone
