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
namespace {

// An upper bound of sqrt(2), the length of a sextant facet's normal e_a +- e_b.
constexpr float kSqrt2Up = 1.41421366f;

}  // namespace

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
  HeadPlanes p;
  const glm::vec3 e1 = v1 - v0, e2 = v2 - v0;
  p.n = Cross(e1, e2);
  p.valid = !Sliver(e1, e2, p.n);
  p.v0 = v0;
  p.behind = (c & 1u) != 0;
  p.ends = (c & 2u) != 0;
  p.reach = margin * Length(p.n);
  p.margin = margin;
  p.facets = mode == layout::kTlHeadsRegular ? Facets(count, k, p.m) : 0u;
  for (std::uint32_t j = 0; j < p.facets; ++j) {
    p.bound[j] = FacetBound(p.m[j], v0, v1, v2, p.ends);
    p.len[j] = count == 6 ? kSqrt2Up : 1.0f;
  }
  return p;
}

// Beyond the triangle's plane: the side the rays reach is h >= 0 (h the signed, scaled distance),
// up to the margin; beyond a facet: below the bound (starting rays) or above it (ending rays).
bool SphereRejected(const HeadPlanes& p, glm::vec4 s) {
  const glm::vec3 c = Xyz(s);
  const float h0 = Dot(p.n, c - p.v0), h = p.behind ? -h0 : h0;
  if (h + s.w * Length(p.n) < -p.reach) return true;
  for (std::uint32_t j = 0; j < p.facets; ++j) {
    const float x = Dot(p.m[j], c), r = s.w * p.len[j], g = p.margin * p.len[j];
    if (p.ends ? x - r > p.bound[j] + g : x + r < p.bound[j] - g) return true;
  }
  return false;
}

bool TriangleRejected(const HeadPlanes& p, glm::vec3 a, glm::vec3 b, glm::vec3 d) {
  const glm::vec3 v[3] = {a, b, d};
  bool all = true;
  for (const glm::vec3& x : v) {
    const float h0 = Dot(p.n, x - p.v0), h = p.behind ? -h0 : h0;
    all = all && h < -p.reach;
  }
  if (all) return true;
  for (std::uint32_t j = 0; j < p.facets; ++j) {
    bool beyond = true;
    for (const glm::vec3& x : v) {
      const float y = Dot(p.m[j], x), g = p.margin * p.len[j];
      beyond = beyond && (p.ends ? y > p.bound[j] + g : y < p.bound[j] - g);
    }
    if (beyond) return true;
  }
  return false;
}

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
  const glm::vec3 c[4] = {layout::PixelDirection(fc, x0, y0), layout::PixelDirection(fc, x1, y0), layout::PixelDirection(fc, x1, y1),
                          layout::PixelDirection(fc, x0, y1)};
  const glm::vec3 mid = ((c[0] + c[1]) + c[2]) + c[3];
  CellPlanes p;
  p.eye = Xyz(fc.eye);
  p.margin = margin;
  for (std::uint32_t j = 0; j < 4; ++j) {
    glm::vec3 n = Cross(c[j], c[(j + 1) & 3u]);
    if (Dot(n, mid) < 0.0f) n = -n;
    p.n[j] = n;
    p.len[j] = Length(n);
  }
  return p;
}

bool CellSphereRejected(const CellPlanes& p, glm::vec4 s) {
  const glm::vec3 v = Xyz(s) - p.eye;
  for (std::uint32_t j = 0; j < 4; ++j)
    if (Dot(p.n[j], v) + s.w * p.len[j] < -(p.margin * p.len[j])) return true;
  return false;
}

bool CellTriangleRejected(const CellPlanes& p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  for (std::uint32_t j = 0; j < 4; ++j) {
    const float g = -(p.margin * p.len[j]);
    if (Dot(p.n[j], a - p.eye) < g && Dot(p.n[j], b - p.eye) < g && Dot(p.n[j], c - p.eye) < g) return true;
  }
  return false;
}

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
