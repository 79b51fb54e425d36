// Exact ray-triangle decisions (CGAL, exact rational arithmetic) that settle disagreements between
// the frame's tracer and the oracle. Every float input is taken as the exact rational it encodes.
#pragma once
#include <cstdint>
#include <vector>

#include "rayspace/scene_buffers.h"

namespace rayspace::refs {

// Where the ray meets a closed triangle: not at all, inside, or exactly on an edge or vertex (where
// tracers may legitimately differ: Embree counts some edges out, the emulator counts all edges in).
enum class Contact { kMiss, kBoundary, kInterior };

// Does the ray meet the triangle at some t with tmin < t < tmax (exactly)? `one_sided`: only from the
// front, against the normal (v1 - v0) x (v2 - v0) (SceneBuffers::one_sided); a ray in the plane meets
// no front.
Contact ExactContact(const layout::Ray& ray, const layout::Triangle& tri, bool one_sided = false);
inline bool ExactHits(const layout::Ray& ray, const layout::Triangle& tri) { return ExactContact(ray, tri) != Contact::kMiss; }

// ExactOccluded and ExactClosest follow scene.one_sided.
// Exact answer for a shadow ray over all triangles other than info.y: kInterior if some triangle is
// met inside, else kBoundary if one is met only on an edge or vertex, else kMiss.
Contact ExactOccluded(const layout::Ray& ray, const SceneBuffers& scene);

// Exact closest hit: every primitive (other than info.y) hit at the exactly smallest t, in id order;
// empty for a miss. More than one means an exact tie (shared edge or vertex).
std::vector<std::uint32_t> ExactClosest(const layout::Ray& ray, const SceneBuffers& scene);

// Does the ray o + t d (t > 0, no upper bound) cross the triangle's interior robustly: does the hit
// survive moving the vertices (relative to o) by up to rel x M, M the largest coordinate magnitude
// of o and the vertices? A float test translates the vertices by o and rounds at the scale M, so
// this is what it can promise (fuzz/ray_triangle uses rel = 2^-16); grazing rays and hits near an
// edge are not robust. Interval arithmetic first, exact rationals when it cannot decide.
bool ExactRobustInteriorHit(glm::vec3 o, glm::vec3 d, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, float rel);

// Exact hit decision on the closed triangle with tmin < t < tmax from signs of triple products (no
// constructions); a ray in the triangle's plane counts as a miss, as in float tests. `filtered`:
// interval arithmetic first; else exact rationals throughout.
bool ExactHitDecision(const layout::Ray& ray, const layout::Triangle& tri, bool filtered = true, bool one_sided = false);
// What a float test may answer for a ray and a triangle: the exact decision with tmin < t < tmax,
// and whether it is robust: it survives moving every vertex relative to the origin by rel x L per
// coordinate, L the largest coordinate magnitude of those relative vertices, which covers what the
// watertight test's rounding does (docs/numerics.md, "The hit convention"). A robust answer is what every
// correct float tracer gives; a fragile one (grazing rays, hits near an edge or an interval end) may
// come out either way.
struct Judgement {
  bool hit = false;
  bool robust = false;
};
// `one_sided`: a hit only from the front (ExactContact); the side is robust when moving the vertices
// cannot turn the triangle's normal across the ray's direction.
Judgement ExactJudge(const layout::Ray& ray, const layout::Triangle& tri, float rel, bool one_sided = false);
// Does some point o + t d with t0 <= t <= t1 (t1 = +inf: no upper end) lie in the closed ball
// (sphere.xyz, sphere.w), exactly? The exact form of the traversal lists' sphere test
// (docs/traversal-lists.md). Inputs must be finite but t1; t0 > t1 is an empty part (false).
bool ExactSegmentMeetsSphere(glm::vec3 o, glm::vec3 d, float t0, float t1, glm::vec4 sphere);
// Could rounding order the two triangles' distances either way: |t_a - t_b| |d| <= rel (L + |t| |d|)?
bool ExactDistancesClose(const layout::Ray& ray, const layout::Triangle& a, const layout::Triangle& b, float rel);

// For two triangles the ray hits (ExactHitDecision): the sign of t_a - t_b, exactly.
int ExactCompareHitDistance(const layout::Ray& ray, const layout::Triangle& a, const layout::Triangle& b);
// Does the ray's line lie in the triangle's plane (origin in the plane, direction parallel to it)?
bool ExactInPlane(const layout::Ray& ray, const layout::Triangle& tri);

}  // namespace rayspace::refs
