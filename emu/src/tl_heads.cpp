// Per-polygon windows of the traversal lists (Toczek et al. section 3.1; rayspace/contract.h,
// kTlHeads*): the planes and rejection tests of tl.heads, mirroring gpu/shaders/tl_heads.comp
// operation for operation (the pass itself, PassTlHeads, is in tl.cpp beside the other two), and the
// case a ray's walk takes (tl::RayCase, as tl_trace.comp computes it).
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "rayspace/contract.h"
#include "rayspace/kernel_functions.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/walk_math.h"
#include "rayspace/parallel.h"

namespace rayspace::emu::tl {

float FacetBound(glm::vec3 m, glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, bool ends) { return FacetBoundOf(m, v0, v1, v2, ends); }

bool Sliver(glm::vec3 e1, glm::vec3 e2, glm::vec3 n) { return SliverOf(e1, e2, n); }

std::uint32_t Facets(std::uint32_t count, std::uint32_t k, glm::vec3 m[4]) {
  if (count == 2) {
    m[0] = glm::vec3(k == 1 ? -1.0f : 1.0f, 0.0f, 0.0f);
    return 1;
  }
  if (count == 8) {
    m[0] = glm::vec3((k & 1u) ? -1.0f : 1.0f, 0.0f, 0.0f);
    m[1] = glm::vec3(0.0f, (k & 2u) ? -1.0f : 1.0f, 0.0f);
    m[2] = glm::vec3(0.0f, 0.0f, (k & 4u) ? -1.0f : 1.0f);
    return 3;
  }
  if (count != 6) return 0;
  const std::uint32_t a = k / 2u, b = a == 2u ? 0u : a + 1u, c = b == 2u ? 0u : b + 1u;
  const float s = (k & 1u) ? -1.0f : 1.0f;
  for (std::uint32_t j = 0; j < 4; ++j) {
    glm::vec3 v(0.0f);
    v[a] = s;
    v[j < 2 ? b : c] = (j & 1u) ? -1.0f : 1.0f;
    m[j] = v;
  }
  return 4;
}

HeadPlanes MakePlanes(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, std::uint32_t c, std::uint32_t count, std::uint32_t k,
                      std::uint32_t mode, float margin) {
  return MakePlanesOf(v0, v1, v2, c, count, k, mode, margin);
}

bool SphereRejected(const HeadPlanes& p, glm::vec4 s) { return SphereRejectedOf(p, s); }

bool TriangleRejected(const HeadPlanes& p, glm::vec3 a, glm::vec3 b, glm::vec3 d) { return TriangleRejectedOf(p, a, b, d); }

float HeadsMargin(glm::vec3 lo, glm::vec3 hi, std::span<const glm::vec3> lights) {
  float m = std::max(MaxAbs(lo, lo), MaxAbs(hi, hi));
  for (const glm::vec3& l : lights) m = std::max(m, MaxAbs(l, l));
  return m * 0x1p-10f;
}

std::uint32_t CellsX(const layout::FrameConstants& fc) { return (fc.dims.x + layout::kTlCellPixels - 1) / layout::kTlCellPixels; }

std::uint32_t CellCount(const layout::FrameConstants& fc) {
  return CellsX(fc) * ((fc.dims.y + layout::kTlCellPixels - 1) / layout::kTlCellPixels);
}

std::uint32_t CellOf(const layout::FrameConstants& fc, std::uint32_t px, std::uint32_t py) {
  return py / layout::kTlCellPixels * CellsX(fc) + px / layout::kTlCellPixels;
}

CellPlanes MakeCellPlanes(const layout::FrameConstants& fc, std::uint32_t cell, float margin) {
  const std::uint32_t cx = cell % CellsX(fc), cy = cell / CellsX(fc);
  const std::uint32_t x0 = cx * layout::kTlCellPixels, y0 = cy * layout::kTlCellPixels;
  const std::uint32_t x1 = std::min(x0 + layout::kTlCellPixels, fc.dims.x) - 1, y1 = std::min(y0 + layout::kTlCellPixels, fc.dims.y) - 1;
  return MakeCellPlanesOf(fc, x0, y0, x1, y1, margin);
}

bool CellSphereRejected(const CellPlanes& p, glm::vec4 s) { return CellSphereRejectedOf(p, s); }

bool CellTriangleRejected(const CellPlanes& p, glm::vec3 a, glm::vec3 b, glm::vec3 c) { return CellTriangleRejectedOf(p, a, b, c); }

std::vector<layout::Ray> EyeRays(const layout::FrameConstants& fc) {
  std::vector<layout::Ray> rays(std::size_t{fc.dims.x} * fc.dims.y);
  for (std::uint32_t py = 0; py < fc.dims.y; ++py)
    for (std::uint32_t px = 0; px < fc.dims.x; ++px) {
      layout::Ray& r = rays[std::size_t{py} * fc.dims.x + px];
      r.origin_tmin = glm::vec4(Xyz(fc.eye), 0.0f);
      r.direction_tmax = glm::vec4(layout::PixelDirection(fc, px, py), std::numeric_limits<float>::infinity());
      r.info = glm::uvec4(py * fc.dims.x + px, layout::kNoPrim, layout::kRayPrimary, CellOf(fc, px, py));
      r.weight = glm::vec4(1.0f, 1.0f, 1.0f, 0.0f);
    }
  return rays;
}

std::uint32_t RayCase(const ListsView& lists, std::span<const Word> tri_words, const layout::Ray& ray, bool ends, std::uint32_t k) {
  const std::uint32_t prim = ray.info.y;
  if (prim >= tri_words.size()) return kNoCase;
  const Word w = tri_words[prim];
  glm::vec3 m[4];
  const std::uint32_t facets =
      lists.heads == layout::kTlHeadsRegular ? Facets(static_cast<std::uint32_t>(lists.first.size() - 1), k, m) : 0u;
  return RayCaseOf(Xyz(lists.vertices[w.x]), Xyz(lists.vertices[w.y]), Xyz(lists.vertices[w.z]), Xyz(ray.origin_tmin),
                   Xyz(ray.direction_tmax), ray.direction_tmax.w, ends, m, facets, kNoCase);
}

}  // namespace rayspace::emu::tl
