// Known answers for the exact cone-sphere oracles (refs/exact_cone.h), chosen where the geometry
// is exactly representable: boundary cases must come out as contained / meeting.
#include <doctest/doctest.h>

#include <cmath>

#include "rayspace/emu/cone.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/exact_cone.h"

using namespace rayspace;

namespace {

layout::ConeNode Node(glm::vec4 sphere, glm::vec3 axis, float c, float s) {
  layout::ConeNode n;
  n.sphere = sphere;
  n.cone = glm::vec4(axis, c);
  n.extra = glm::vec4(s, 1.0f, 0.0f, 0.0f);
  return n;
}

}  // namespace

TEST_CASE("exact cone: direction containment at and beyond the boundary") {
  const float h = std::sqrt(0.5f);  // cos = sin: exactly pi/4 as an angle of the vector (h, h)
  const layout::ConeNode n = Node({0, 0, 0, 0}, {0, 0, 1}, h, h);
  CHECK(refs::ExactConeContainsDirection(n, {1, 0, 1}));       // exactly on the boundary
  CHECK(refs::ExactConeContainsDirection(n, {0, 0, 5}));       // the axis, any length
  CHECK_FALSE(refs::ExactConeContainsDirection(n, {1, 0, 0.99999994f}));
  CHECK_FALSE(refs::ExactConeContainsDirection(n, {0, 0, -1}));
  // Collinear with the axis but opposite: angle pi, outside a zero-angle cone.
  CHECK_FALSE(refs::ExactConeContainsDirection(Node({0, 0, 0, 0}, {0, 0, 1}, 1.0f, 0.0f), {0, 0, -2}));
  CHECK(refs::ExactConeContainsDirection(Node({0, 0, 0, 0}, {0, 0, 1}, 1.0f, 0.0f), {0, 0, 2}));
  // Half-angle pi/2 (cos 0, sin 1) holds the closed half-space.
  const layout::ConeNode half = Node({0, 0, 0, 0}, {0, 0, 1}, 0.0f, 1.0f);
  CHECK(refs::ExactConeContainsDirection(half, {1, 0, 0}));
  CHECK_FALSE(refs::ExactConeContainsDirection(half, {1, 0, -1e-30f}));
  // Full nodes hold everything.
  CHECK(refs::ExactConeContainsDirection(Node({0, 0, 0, 0}, {1, 0, 0}, -1.0f, 0.0f), {-1, 0, 0}));
}

TEST_CASE("exact cone: cone containment adds the child's half-angle to the axis angle") {
  const layout::ConeNode half = Node({0, 0, 0, 0}, {0, 0, 1}, 0.0f, 1.0f);
  CHECK(refs::ExactConeContainsCone(half, Node({0, 0, 0, 0}, {1, 0, 0}, 1.0f, 0.0f)));   // pi/2 + 0
  CHECK_FALSE(refs::ExactConeContainsCone(half, Node({0, 0, 0, 0}, {1, 0, 0}, 1.0f, 1e-3f)));
  const float h = std::sqrt(0.5f);
  // Child of half-angle pi/4 around (1, 0, 1): reaches exactly the x axis and the z axis.
  CHECK(refs::ExactConeContainsCone(half, Node({0, 0, 0, 0}, {1, 0, 1}, h, h)));
  CHECK_FALSE(refs::ExactConeContainsCone(half, Node({0, 0, 0, 0}, {1, 0, 0.99f}, h, h)));
  // A wider child is never inside.
  CHECK_FALSE(refs::ExactConeContainsCone(Node({0, 0, 0, 0}, {0, 0, 1}, h, h), half));
  CHECK_FALSE(refs::ExactConeContainsCone(half, Node({0, 0, 0, 0}, {0, 0, 1}, -1.0f, 0.0f)));
}

TEST_CASE("exact cone: ball containment is |c_i - c_o| + r_i <= r_o") {
  CHECK(refs::ExactBallContainsBall({0, 0, 0, 2}, {1, 0, 0, 1}));  // internally tangent
  CHECK_FALSE(refs::ExactBallContainsBall({0, 0, 0, 2}, {1, 0, 0, 1.0000001f}));
  CHECK(refs::ExactBallContainsBall({0, 0, 0, 5}, {3, 4, 0, 0}));
  CHECK_FALSE(refs::ExactBallContainsBall({0, 0, 0, 5}, {3, 4, 1e-7f, 0}));
}

TEST_CASE("exact cone: node-sphere meeting (surface, inside, apex, behind)") {
  const layout::ConeNode ray = Node({0, 0, 0, 0}, {0, 0, 1}, 1.0f, 0.0f);  // one ray along +z
  CHECK(refs::ExactNodeMeetsSphere(ray, {1, 0, 5, 1}));                  // tangent to the ray
  CHECK_FALSE(refs::ExactNodeMeetsSphere(ray, {1, 0, 5, 0.99999994f}));
  CHECK(refs::ExactNodeMeetsSphere(ray, {0, 0, -5, 5}));                 // behind, touching the apex
  CHECK_FALSE(refs::ExactNodeMeetsSphere(ray, {0, 0, -5, 4.9999995f}));
  const layout::ConeNode half = Node({0, 0, 0, 0}, {0, 0, 1}, 0.0f, 1.0f);  // the half-space z >= 0
  CHECK(refs::ExactNodeMeetsSphere(half, {3, 0, -4, 4}));                 // distance to the plane is 4
  CHECK_FALSE(refs::ExactNodeMeetsSphere(half, {3, 0, -4, 3.9999998f}));
  CHECK(refs::ExactNodeMeetsSphere(half, {3, 0, 4, 0}));                  // inside
  // The node's own radius counts like the sphere's.
  CHECK(refs::ExactNodeMeetsSphere(Node({0, 0, 0, 1}, {0, 0, 1}, 1.0f, 0.0f), {2, 0, 5, 1}));
  CHECK_FALSE(refs::ExactNodeMeetsSphere(Node({0, 0, 0, 1}, {0, 0, 1}, 1.0f, 0.0f), {2, 0, 5, 0.99999994f}));
}

TEST_CASE("exact cone: the float test never misses what the exact decision meets on a grid") {
  // A deterministic sweep of spheres around a 30-degree cone; a planted miss would show up here.
  const layout::ConeNode n = Node({0.5f, -0.25f, 1, 0.125f}, emu::Normalize(glm::vec3(0.3f, 0.2f, 1)),
                               static_cast<float>(std::cos(M_PI / 6)), static_cast<float>(std::sin(M_PI / 6)));
  int met = 0, missed = 0;
  for (int i = -12; i <= 12; ++i)
    for (int j = -12; j <= 12; ++j)
      for (int k = -12; k <= 12; ++k) {
        const glm::vec4 s(i * 0.37f, j * 0.41f, k * 0.43f, 0.05f * static_cast<float>((i + j + k + 40) % 7));
        if (!refs::ExactNodeMeetsSphere(n, s)) continue;
        ++met;
        missed += !emu::cone::Test(n, s, 0.0f);
      }
  CHECK(met > 500);
  CHECK(missed == 0);
}

TEST_CASE("exact ray-triangle: robust interior hits, and what does not count as one") {
  const glm::vec3 v0(0, 0, 0), v1(1, 0, 0), v2(0, 1, 0);
  const float rel = 0x1p-16f;
  CHECK(refs::ExactRobustInteriorHit({0.25f, 0.25f, 1}, {0, 0, -1}, v0, v1, v2, rel));
  CHECK(refs::ExactRobustInteriorHit({0.25f, 0.25f, -1}, {0, 0, 3}, v0, v1, v2, rel));     // from below
  CHECK_FALSE(refs::ExactRobustInteriorHit({0.25f, 0.25f, 1}, {0, 0, 1}, v0, v1, v2, rel)); // behind the origin
  CHECK_FALSE(refs::ExactRobustInteriorHit({0.5f, 0, 1}, {0, 0, -1}, v0, v1, v2, rel));    // on an edge
  CHECK_FALSE(refs::ExactRobustInteriorHit({0.5f, 1e-6f, 1}, {0, 0, -1}, v0, v1, v2, rel)); // within 2^-16 of it
  CHECK(refs::ExactRobustInteriorHit({0.5f, 1e-3f, 1}, {0, 0, -1}, v0, v1, v2, rel));       // beyond
  CHECK_FALSE(refs::ExactRobustInteriorHit({-1, 0.25f, 1e-6f}, {1, 0, -1e-7f}, v0, v1, v2, rel));  // grazing
  CHECK_FALSE(refs::ExactRobustInteriorHit({0.7f, 0.7f, 1}, {0, 0, -1}, v0, v1, v2, rel));  // outside
  CHECK_FALSE(refs::ExactRobustInteriorHit({0.25f, 0.25f, 1}, {0, 0, -1}, v0, v1, {2, 0, 0}, rel));  // degenerate
  CHECK_FALSE(refs::ExactRobustInteriorHit({-1, 0.25f, 0}, {1, 0, 0}, v0, v1, v2, rel));    // in the plane
  // The same configuration scaled by 2^60 and 2^-60 keeps its answers.
  for (float k : {0x1p60f, 0x1p-60f}) {
    CHECK(refs::ExactRobustInteriorHit(glm::vec3(0.25f, 0.25f, 1) * k, {0, 0, -1}, v0 * k, v1 * k, v2 * k, rel));
    CHECK_FALSE(refs::ExactRobustInteriorHit(glm::vec3(0.5f, 1e-6f, 1) * k, {0, 0, -1}, v0 * k, v1 * k, v2 * k, rel));
  }
}
