// Exact decisions about cone-sphere nodes (CGAL's exact rationals; every float is taken as the
// rational it encodes). They define what a node means and judge the float code against it.
//
// A node (layout.h ConeNode) stands for a ray bundle: origins in the ball (sphere.xyz, sphere.w),
// directions d with angle(axis, d) <= alpha, where axis = cone.xyz (any length) and alpha is the angle
// of the 2D vector (cos, sin) = (cone.w, extra.x) in [0, pi] (lengths need not be 1). A node is full
// (every direction) when cone.w <= -1, when (cos, sin) is (0, 0), or when its axis is zero, as the
// float test treats those. Square roots are avoided by comparing squares with sign case analysis
// (docs/numerics.md), so every verdict is exact.
#pragma once
#include <string>

#include "rayspace/layout.h"

namespace rayspace::refs {

// Is the direction d (any nonzero length) inside the node's cone?
bool ExactConeContainsDirection(const layout::ConeNode& n, glm::vec3 d);
// Is every direction of the child's cone inside the node's cone?
bool ExactConeContainsCone(const layout::ConeNode& n, const layout::ConeNode& child);
// Is the ball (inner) inside the ball (outer)? |c_inner - c_outer| + r_inner <= r_outer.
bool ExactBallContainsBall(glm::vec4 outer, glm::vec4 inner);
// Node containment (ball and cone); `why` names the part that fails.
bool ExactNodeContains(const layout::ConeNode& n, const layout::ConeNode& child, std::string* why = nullptr);
bool ExactNodeContainsRay(const layout::ConeNode& n, glm::vec3 origin, glm::vec3 direction, std::string* why = nullptr);

// Does the node's ray bundle meet the ball (centre xyz, radius w)? True iff the distance from the
// ball's centre to the cone with apex at the node's centre is at most node radius + ball radius.
bool ExactNodeMeetsSphere(const layout::ConeNode& n, glm::vec4 sphere);

// The same decision with a chosen arithmetic, for measuring what exactness costs (rayspace accuracy):
// interval filter then exact rationals (the default above), exact rationals only, or CGAL's lazy
// exact number type (Epeck::FT). All three give the exact answer.
enum class ExactArithmetic { kFiltered, kRational, kLazy };
bool ExactNodeMeetsSphere(const layout::ConeNode& n, glm::vec4 sphere, ExactArithmetic arithmetic);
// The cone-sphere decision of eqs. 3.8-3.16 evaluated in double without margins (not exact).
bool DoubleNodeMeetsSphere(const layout::ConeNode& n, glm::vec4 sphere);

}  // namespace rayspace::refs
