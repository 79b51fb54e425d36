// Per-polygon windows of the traversal lists (Toczek et al. section 3.1; docs/traversal-lists.md,
// "Per-polygon heads"). A ray that starts on a triangle (reflection, refraction) reaches only the
// side of the triangle's plane its direction points to, and, its direction lying in its list's
// class, only points past the triangle along every facet plane of the class (m . x >= the
// triangle's least m . v); a ray that ends on a triangle (a shadow ray, which starts at the light)
// only points on the side it comes from and before it. tl.heads writes per (triangle, case, list)
// the window [head, tail) of the list outside which every element lies beyond one of those planes
// by more than a margin, and tl.trace walks only the window.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include <vector>

#include <glm/vec3.hpp>

#include "rayspace/emu/tl/heads_math.h"
#include "rayspace/emu/tl/tl.h"

namespace rayspace::emu::tl {

// The planes of one (triangle, case, list) and of one screen cell: tl/heads_math.h.
using HeadPlanes = HeadPlanesOf<float>;
using CellPlanes = CellPlanesOf<float>;

// Is |n| too small against |e1| |e2| (max norms, |n| < |e1| |e2| / 32) for the float normal's
// direction to be trusted?
bool Sliver(glm::vec3 e1, glm::vec3 e2, glm::vec3 n);
HeadPlanes MakePlanes(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, std::uint32_t c, std::uint32_t count, std::uint32_t k,
                      std::uint32_t mode, float margin);
bool SphereRejected(const HeadPlanes& p, glm::vec4 sphere);
bool TriangleRejected(const HeadPlanes& p, glm::vec3 a, glm::vec3 b, glm::vec3 c);

// The case of a ray on its triangle (ray.info.y), as tl.trace computes it: 2 * ends + behind, or
// kNoCase when it has no triangle, the triangle is a sliver, or its direction lies within
// kTlSideRatio of the plane (no window: the whole list).
inline constexpr std::uint32_t kNoCase = ~0u;
// With regular heads also kNoCase when the ray's own point (its origin; for an ending ray o + tmax d)
// lies outside the triangle's bound along a facet of list k (a G-buffer point may lie just outside
// its triangle, in its plane, where the regular window does not hold what the ray can reach).
std::uint32_t RayCase(const ListsView& lists, std::span<const Word> tri_words, const layout::Ray& ray, bool ends, std::uint32_t k);
// The least (starting rays) or greatest (ending rays) projection of the triangle on m, by comparisons
// in vertex order.
float FacetBound(glm::vec3 m, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, bool ends);

// The margin of a scene: 2^-10 of the largest coordinate magnitude M of its bounds and lights. A
// ray's origin lies within a few ulps of M of its triangle, and the float plane of a non-sliver
// triangle turns by at most 2^-14.2 from the exact one, which moves it by 2^-12.4 M across the
// scene: the margin covers both four times over.
float HeadsMargin(glm::vec3 lo, glm::vec3 hi, std::span<const glm::vec3> lights);

// Per-cell heads of eye rays (Toczek et al. section 3.2; rayspace/contract.h, kTlCells*): the four
// side planes through the eye of the pyramid spanned by the directions through the cell's corner
// pixels' centres (PixelDirection, affine in the pixel, so every eye ray of the cell lies inside),
// normals n = (corner) x (next corner) turned towards the sum of the corners. A cell one pixel wide
// has a zero normal (a plane that rejects nothing) and two normals of its plane, which the sum of
// the corners (in that plane) may turn either way: each then keeps a half-space holding the rays.
std::uint32_t CellsX(const layout::FrameConstants& fc);
std::uint32_t CellCount(const layout::FrameConstants& fc);
// The cell of pixel (px, py).
std::uint32_t CellOf(const layout::FrameConstants& fc, std::uint32_t px, std::uint32_t py);
CellPlanes MakeCellPlanes(const layout::FrameConstants& fc, std::uint32_t cell, float margin);
bool CellSphereRejected(const CellPlanes& p, glm::vec4 sphere);
bool CellTriangleRejected(const CellPlanes& p, glm::vec3 a, glm::vec3 b, glm::vec3 c);
// The eye rays of a frame, one per pixel in pixel order: from the eye through the pixel's centre
// (PixelDirection), t in [0, inf), info (pixel, kNoPrim, kRayPrimary, cell), weight 1.
std::vector<layout::Ray> EyeRays(const layout::FrameConstants& fc);

}  // namespace rayspace::emu::tl

namespace rayspace::emu {
TlWindows PassTlHeads(const call::TlHeads& c);
TlWindows PassTlCells(const call::TlCells& c);
// Why windows do not fit the lists, or "": 2 words per (group, list), a group a (triangle, case) of
// tl.heads or a cell of tl.cells, each window [head, tail) inside its list. `bad` receives the first
// bad word.
std::string WindowsError(std::span<const std::uint32_t> first, std::span<const std::uint32_t> windows, std::size_t groups,
                         std::size_t* bad = nullptr);
}  // namespace rayspace::emu
