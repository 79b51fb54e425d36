// The group rejects of the fused top level (emu/cone_cull.h), the emulator's in double and the
// kernel's in float (cone::DeviceGroupMisses, twin of gpu/shaders/cone_cull.glsl): whenever one says
// a group misses, the float cone test rejects every sphere of the group. Groups are slid towards each cone until they sit
// at the edge of being culled, where the test is tightest; a planted negative margin must be caught
// there, and groups the bound may not judge (non-finite, full cones, axes off unit length) never are.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/cone_cull.h"
#include "rayspace/emu/cone_simd.h"

using namespace rayspace;
using namespace rayspace::emu;

namespace {

using D3 = glm::dvec3;

// A node with a unit axis and (cos, sin) rounded once from double, as the hierarchy's nodes are to
// within their margins; half-angles from a needle to past a half-space.
layout::ConeNode RandomNode(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  D3 axis(u(rng), u(rng), u(rng));
  while (glm::length(axis) < 0.1) axis = D3(u(rng), u(rng), u(rng));
  axis = glm::normalize(axis);
  const double angle = std::array{1e-4, 0.01, 0.2, 0.7, 1.4, 2.0}[rng() % 6] * (0.5 + 0.5 * std::abs(u(rng)));
  layout::ConeNode n{};
  n.sphere = glm::vec4(float(u(rng) * scale), float(u(rng) * scale), float(u(rng) * scale), float(std::abs(u(rng)) * scale * 0.05));
  if (rng() % 4 == 0) n.sphere.w = 0.0f;
  n.cone = glm::vec4(float(axis.x), float(axis.y), float(axis.z), float(std::cos(angle)));
  n.extra = glm::vec4(float(std::sin(angle)), 1.0f, 0.0f, 0.0f);
  return n;
}

D3 Apex(const layout::ConeNode& n) { return D3(n.sphere.x, n.sphere.y, n.sphere.z); }
D3 Axis(const layout::ConeNode& n) { return D3(n.cone.x, n.cone.y, n.cone.z); }

// The unit direction in which the distance to the cone's surface falls fastest at p (outside it).
D3 TowardCone(const layout::ConeNode& n, D3 p) {
  const D3 v = p - Apex(n), A = Axis(n);
  D3 perp = v - A * glm::dot(v, A);
  if (glm::length(perp) == 0.0) perp = glm::abs(A.x) < 0.9 ? glm::cross(A, D3(1, 0, 0)) : glm::cross(A, D3(0, 1, 0));
  return glm::normalize(D3(A) * double(n.extra.x) - glm::normalize(perp) * double(n.cone.w));
}

struct Group {
  std::vector<glm::vec4> spheres;
};

// Which reject: the emulator's (double, aligned groups) or the kernel's (float, a subgroup's group);
// `margin` is the device bound's (the host's is Settings::cull_margin).
enum class Bound { kHost, kDevice };
struct Reject {
  Bound bound = Bound::kHost;
  float margin = layout::kDeviceCullMargin;
  bool Misses(const layout::ConeNode& n, float eps, const std::vector<glm::vec4>& m) const {
    if (bound == Bound::kHost) return cone::GroupMisses(cone::CullNodeOf(n, eps), cone::GroupsOf(m, cone::kCullGroup), 0);
    const std::optional<glm::vec4> g = cone::DeviceGroupOf(m);
    return g && cone::DeviceGroupMisses(n, *g, eps, margin);
  }
};

// Members about the point `centre`: two extreme spheres along `dir` (they define the group's bound)
// and, unless tight, random smaller ones inside it.
Group MakeGroup(std::mt19937& rng, D3 centre, D3 dir, double extent, double radius, bool tight) {
  Group g;
  auto add = [&](D3 p, double r) { g.spheres.push_back(glm::vec4(float(p.x), float(p.y), float(p.z), float(r))); };
  add(centre + dir * extent, radius);
  add(centre - dir * extent, radius);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int extra = tight ? 0 : static_cast<int>(rng() % 30);
  for (int i = 0; i < extra; ++i) add(centre + D3(u(rng), u(rng), u(rng)) * (0.5 * extent), radius * 0.5 * std::abs(u(rng)));
  return g;
}

// Slides the group along a ray from the apex out of the cone and returns the members at the nearest
// position where the bound culls them (bisection), or nothing if it never does.
std::vector<glm::vec4> AtCullingEdge(std::mt19937& rng, const layout::ConeNode& n, float eps, double scale, bool tight,
                                     const Reject& reject) {
  const D3 A = Axis(n);
  D3 out = glm::normalize(glm::cross(A, D3(0.3, -0.5, 0.8)));  // perpendicular to the axis, then tilted backwards
  out = glm::normalize(out - A * (std::uniform_real_distribution<double>(0.0, 1.0)(rng)));
  const double extent = scale * std::array{1e-6, 1e-3, 0.05, 0.3}[rng() % 4], radius = extent * std::array{0.0, 0.01, 0.5}[rng() % 3];
  auto members = [&](double t) {
    const D3 c = Apex(n) + out * t;
    return MakeGroup(rng, c, TowardCone(n, c), extent, radius, tight).spheres;
  };
  auto culled = [&](const std::vector<glm::vec4>& m) { return reject.Misses(n, eps, m); };
  double lo = 0.0, hi = scale * 64.0;
  const unsigned seed = rng();
  auto at = [&](double t) {
    rng.seed(seed);  // the same random members at every t
    return members(t);
  };
  if (!culled(at(hi))) return {};
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    (culled(at(mid)) ? hi : lo) = mid;
  }
  return at(hi);
}

// The number of groups culled and of members the float test accepted among them, over many cases.
struct Tally {
  int culled = 0, accepted = 0;
};

Tally Run(std::uint32_t seed, int cases, bool tight, const Reject& reject = {}) {
  std::mt19937 rng(seed);
  Tally t;
  for (int i = 0; i < cases; ++i) {
    const double scale = std::array{1e-3, 1.0, 1e3, 1e7}[rng() % 4];
    const layout::ConeNode n = RandomNode(rng, scale);
    const float eps = rng() % 3 ? 0.0f : float(scale * 1e-4);
    const std::vector<glm::vec4> m = AtCullingEdge(rng, n, eps, scale, tight, reject);
    if (m.empty()) continue;
    ++t.culled;
    for (const glm::vec4& s : m) t.accepted += cone::Test(n, s, eps) ? 1 : 0;
  }
  return t;
}

}  // namespace

TEST_CASE("cone cull: a culled group's every sphere is rejected by the float test, at the edge of culling") {
  for (const bool tight : {true, false}) {
    const Tally t = Run(tight ? 7u : 11u, 4000, tight);
    CAPTURE(tight);
    CHECK(t.culled > 3000);  // the cases reached the edge
    CHECK(t.accepted == 0);
  }
}

// Margin 0 drops only the bound's allowance for the test's own slack and rounding (about 2^-16.5 of
// the distance); the edge cases are tight enough to see even that. (Measured: 2^-16 and above
// accept nothing here, 2^-18 and below do.)
TEST_CASE("cone cull: a planted margin of 0 or below culls groups the test hits") {
  for (const double planted : {-0x1p-8, 0.0}) {
    const ScopedSettings margin([planted](Settings& s) { s.cull_margin = planted; });
    const Tally t = Run(7u, 500, true);
    CAPTURE(planted);
    CHECK(t.culled > 400);
    CHECK(t.accepted > 0);
  }
}

TEST_CASE("cone cull, device: a culled group's every sphere is rejected by the float test, at the edge of culling") {
  for (const bool tight : {true, false}) {
    const Tally t = Run(tight ? 13u : 17u, 4000, tight, {Bound::kDevice});
    CAPTURE(tight);
    CHECK(t.culled > 3000);
    CHECK(t.accepted == 0);
  }
}

// The device bound's margins cover its own float rounding besides the test's slack: at 0 or below
// it must be caught the same way.
TEST_CASE("cone cull, device: a planted margin of 0 or below culls groups the test hits") {
  for (const float planted : {-0x1p-8f, 0.0f}) {
    const Tally t = Run(13u, 500, true, {Bound::kDevice, planted});
    CAPTURE(planted);
    CHECK(t.culled > 400);
    CHECK(t.accepted > 0);
  }
}

TEST_CASE("cone cull, device: what the bound may not judge is never culled") {
  const glm::vec4 far(1e3f, 0.0f, 0.0f, 1.0f);
  layout::ConeNode n{};
  n.sphere = glm::vec4(0, 0, 0, 0);
  n.cone = glm::vec4(0, 0, 1, std::cos(0.01f));
  n.extra = glm::vec4(std::sin(0.01f), 1, 0, 0);
  const std::vector<glm::vec4> good(32, far);
  const glm::vec4 group = cone::DeviceGroupOf(good).value();
  REQUIRE(cone::DeviceGroupMisses(n, group, 0.0f));
  for (const float bad : {NAN, INFINITY, -1.0f, 0x1p61f}) {
    std::vector<glm::vec4> m = good;
    m[5].w = bad;
    CAPTURE(bad);
    CHECK_FALSE(cone::DeviceGroupOf(m).has_value());
    m = good;
    m[7].y = bad == -1.0f ? -0x1p61f : bad;
    CHECK_FALSE(cone::DeviceGroupOf(m).has_value());
  }
  auto misses_with = [&](auto edit) {
    layout::ConeNode m = n;
    edit(m);
    return cone::DeviceGroupMisses(m, group, 0.0f);
  };
  CHECK_FALSE(misses_with([](layout::ConeNode& m) { m.cone.w = -1.0f; }));    // full
  CHECK_FALSE(misses_with([](layout::ConeNode& m) { m.cone.z = 1.001f; }));   // axis off unit
  CHECK_FALSE(misses_with([](layout::ConeNode& m) { m.extra.x = 0.1f; }));    // cos^2 + sin^2 off 1
  CHECK_FALSE(misses_with([](layout::ConeNode& m) { m.sphere.x = NAN; }));
  CHECK_FALSE(misses_with([](layout::ConeNode& m) { m.sphere.w = -1.0f; }));
  CHECK_FALSE(misses_with([](layout::ConeNode& m) { m.sphere.z = 0x1p61f; }));
  CHECK_FALSE(cone::DeviceGroupMisses(n, group, INFINITY));
}

TEST_CASE("cone cull: what the bound may not judge is never culled") {
  const glm::vec4 far(1e3f, 0.0f, 0.0f, 1.0f);  // far off the axis of a narrow cone along +z
  layout::ConeNode n{};
  n.sphere = glm::vec4(0, 0, 0, 0);
  n.cone = glm::vec4(0, 0, 1, std::cos(0.01f));
  n.extra = glm::vec4(std::sin(0.01f), 1, 0, 0);
  const std::vector<glm::vec4> good(32, far);
  REQUIRE(cone::GroupMisses(cone::CullNodeOf(n, 0.0f), cone::GroupsOf(good, cone::kCullGroup), 0));
  for (const float bad : {NAN, INFINITY, -1.0f, 0x1p110f}) {
    std::vector<glm::vec4> m = good;
    m[5].w = bad;
    CAPTURE(bad);
    CHECK_FALSE(cone::GroupMisses(cone::CullNodeOf(n, 0.0f), cone::GroupsOf(m, cone::kCullGroup), 0));
  }
  auto node_with = [&](auto edit) {
    layout::ConeNode m = n;
    edit(m);
    return cone::CullNodeOf(m, 0.0f);
  };
  const cone::SphereGroups groups = cone::GroupsOf(good, cone::kCullGroup);
  CHECK_FALSE(cone::GroupMisses(node_with([](layout::ConeNode& m) { m.cone.w = -1.0f; }), groups, 0));       // full
  CHECK_FALSE(cone::GroupMisses(node_with([](layout::ConeNode& m) { m.cone.z = 1.001f; }), groups, 0));      // axis off unit
  CHECK_FALSE(cone::GroupMisses(node_with([](layout::ConeNode& m) { m.extra.x = 0.1f; }), groups, 0));       // cos^2 + sin^2 off 1
  CHECK_FALSE(cone::GroupMisses(node_with([](layout::ConeNode& m) { m.sphere.x = NAN; }), groups, 0));
  CHECK_FALSE(cone::GroupMisses(node_with([](layout::ConeNode& m) { m.sphere.w = -1.0f; }), groups, 0));
  CHECK_FALSE(cone::GroupMisses(cone::CullNodeOf(n, INFINITY), groups, 0));
}
