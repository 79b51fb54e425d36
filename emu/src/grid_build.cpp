// The grids of `--algo grid`, built on the host in double (rayspace/emu/grid/grid.h, docs/grids.md).
#include <algorithm>
#include <cmath>
#include <array>
#include <limits>
#include <map>
#include <utility>

#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/light_sample.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu::grid {
namespace {

// The face's axes: the major one, and the two that become u and v.
struct FaceAxes {
  int major, a, b;
  double sign;
};
FaceAxes AxesOf(std::uint32_t face) {
  const int major = static_cast<int>(face / 2);
  return {major, (major + 1) % 3, (major + 2) % 3, face % 2 == 0 ? 1.0 : -1.0};
}

// Sutherland-Hodgman: the part of `poly` where dot(plane, p) >= 0 (plane through the light).
std::vector<glm::dvec3> ClipHalfSpace(const std::vector<glm::dvec3>& poly, glm::dvec3 plane) {
  std::vector<glm::dvec3> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec3 p = poly[i], q = poly[(i + 1) % poly.size()];
    const double dp = glm::dot(plane, p), dq = glm::dot(plane, q);
    if (dp >= 0) out.push_back(p);
    if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
  return out;
}

// The cells [i0, i1] x [j0, j1] of face `face` that the triangle (relative to the light) may be seen
// through; false when it is not seen through the face at all.
bool FaceCellRange(const glm::dvec3 tri[3], std::uint32_t face, std::uint32_t n, bool margins, glm::uvec4& range, glm::vec4& box) {
  const FaceAxes ax = AxesOf(face);
  const double w = 1.0 + (margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0);
  std::vector<glm::dvec3> poly(tri, tri + 3);
  for (int side = 0; side < 4; ++side) {
    glm::dvec3 plane(0.0);
    plane[ax.major] = ax.sign * w;
    plane[side < 2 ? ax.a : ax.b] = side % 2 == 0 ? -1.0 : 1.0;  // w m - a >= 0, w m + a >= 0, ...
    poly = ClipHalfSpace(poly, plane);
    if (poly.empty()) return false;
  }
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const glm::dvec3& p : poly) {
    const double m = ax.sign * p[ax.major];
    if (!(m > 0.0)) {  // the triangle passes through the light: every cell of the face
      lo[0] = lo[1] = -INFINITY;
      hi[0] = hi[1] = INFINITY;
      break;
    }
    const double uv[2] = {p[ax.a] / m, p[ax.b] / m};
    for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], uv[k]), hi[k] = std::max(hi[k], uv[k]);
  }
  const double half = 0.5 * n, slack = margins ? static_cast<double>(layout::kGridCellSlack) : 0.0;
  std::uint32_t c[4];
  for (int k = 0; k < 2; ++k) {
    const double a = std::floor((lo[k] + 1.0) * half - slack), b = std::floor((hi[k] + 1.0) * half + slack);
    c[2 * k] = static_cast<std::uint32_t>(std::clamp(a, 0.0, n - 1.0));
    c[2 * k + 1] = static_cast<std::uint32_t>(std::clamp(b, 0.0, n - 1.0));
  }
  range = glm::uvec4(c[0], c[1], c[2], c[3]);  // u columns, v rows
  // The (u, v) rectangle of the projection, rounded outwards to float and widened by the face's slack
  // (a ray's rounded u, v); a triangle through the light: the whole face.
  const double uv_slack = margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0, ulp = margins ? 1e-12 : 0.0;
  const auto down = [&](double x) { return static_cast<float>(std::max(-2.0, x - uv_slack) - ulp); };
  const auto up = [&](double x) { return static_cast<float>(std::min(2.0, x + uv_slack) + ulp); };
  box = glm::vec4(down(lo[0]), down(lo[1]), up(hi[0]), up(hi[1]));
  return true;
}

// A run of triangles' cell references, in the order they were binned.
struct Refs {
  std::vector<std::uint32_t> cells, triangles;
  std::vector<glm::vec4> boxes;  // perspective grids: each reference's (u, v) rectangle
  void Add(std::uint32_t cell, std::uint32_t t) {
    cells.push_back(cell);
    triangles.push_back(t);
  }
};

// Appends to g the CSR lists of `cells` cells from every triangle's references (bin(t, refs) adds
// triangle t's, with their rectangles when `boxes`), each list in ascending triangle order. The
// triangles are binned in parallel in fixed runs; the lists are then laid out by a counting sort of
// the runs in order (count, exclusive scan, scatter): the same arrays for every thread count.
template <typename Bin>
std::uint64_t BinCsr(std::size_t triangles, std::size_t cells, bool boxes, const Bin& bin, GridArrays& g) {
  constexpr std::size_t kRun = 1024;
  std::vector<Refs> runs((triangles + kRun - 1) / kRun);
  ParallelForDynamic(runs.size(), 1, [&](std::size_t k) {
    for (std::size_t t = k * kRun; t < std::min(triangles, (k + 1) * kRun); ++t) bin(static_cast<std::uint32_t>(t), runs[k]);
  });
  std::vector<std::size_t> at(cells, 0);
  for (const Refs& r : runs)
    for (const std::uint32_t c : r.cells) ++at[c];
  std::size_t next = g.triangles.size();
  const std::size_t base = next;
  for (std::size_t c = 0; c < cells; ++c) {
    g.first.push_back(static_cast<std::uint32_t>(next));
    next += std::exchange(at[c], next);
  }
  RS_CHECK_MSG(next < (std::size_t{1} << 32), "grid: {} cell references", next);
  RS_CHECK(!boxes || g.boxes.size() == base);  // rectangles share the references' indices
  g.triangles.resize(next);
  if (boxes) g.boxes.resize(next);
  for (Refs& r : runs) {
    for (std::size_t i = 0; i < r.cells.size(); ++i) {
      const std::size_t pos = at[r.cells[i]]++;
      g.triangles[pos] = r.triangles[i];
      if (boxes) g.boxes[pos] = r.boxes[i];
    }
    r = Refs();
  }
  return next - base;
}

glm::dvec3 Vertex(const glm::vec4& v) { return {v.x, v.y, v.z}; }

// One point light's grid: n x n cells on each of the six faces of a cube about the light.
void BuildPerspective(const SceneBuffers& scene, glm::vec3 light, std::uint32_t n, bool closed, bool margins, GridArrays& g) {
  const std::size_t cells = layout::kGridFaces * std::size_t{n} * n, first_cell = g.first.size();
  const glm::dvec3 o(light);
  // Rounded down, then by the slack: no hit of a ray of a cell listing the triangle is closer
  // (docs/grids.md).
  std::vector<float> dist(scene.triangles.size());
  ParallelFor(dist.size(), [&](std::size_t t) {
    const layout::Triangle& tr = scene.triangles[t];
    const double d = PointTriangleDistance(o, Vertex(tr.v0), Vertex(tr.v1), Vertex(tr.v2));
    float df = static_cast<float>(d);
    if (margins && static_cast<double>(df) > d) df = std::nextafter(df, 0.0f);
    dist[t] = margins ? df * layout::kGridDistanceSlack : df;
  });
  g.perspective_refs += BinCsr(scene.triangles.size(), cells, true, [&](std::uint32_t t, Refs& refs) {
    const layout::Triangle& tr = scene.triangles[t];
    // Front-face culling: a closed mesh's shadow is cast by the faces turned away from the light.
    if (closed && !FacesAway(Xyz(tr.v0), Xyz(tr.v1), Xyz(tr.v2), light)) return;
    const glm::dvec3 rel[3] = {Vertex(tr.v0) - o, Vertex(tr.v1) - o, Vertex(tr.v2) - o};
    for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
      glm::uvec4 r;
      glm::vec4 box;
      if (!FaceCellRange(rel, f, n, margins, r, box)) continue;
      for (std::uint32_t j = r.z; j <= r.w; ++j)
        for (std::uint32_t i = r.x; i <= r.y; ++i) {
          refs.Add(static_cast<std::uint32_t>((std::size_t{f} * n + j) * n + i), t);
          refs.boxes.push_back(box);
        }
    }
  }, g);
  // Per cell, the least distance of the triangles it lists.
  const std::size_t base = g.min_dist.size();
  g.min_dist.resize(base + cells, INFINITY);
  ParallelFor(cells, [&](std::size_t c) {
    float m = INFINITY;
    const std::size_t end = c + 1 < cells ? g.first[first_cell + c + 1] : g.triangles.size();
    for (std::size_t i = g.first[first_cell + c]; i < end; ++i) m = std::min(m, dist[g.triangles[i]]);
    g.min_dist[base + c] = m;
  });
}

// Whether every point of the box [lo, hi] lies strictly in front of the triangle's plane: the
// triangle is front-facing from every point of a light inside the box (Hunt and Mark's soft-shadow
// culling, valid for closed meshes).
bool FrontFromBox(const layout::Triangle& tr, glm::dvec3 lo, glm::dvec3 hi) {
  const glm::dvec3 a = Vertex(tr.v0), n = glm::cross(Vertex(tr.v1) - a, Vertex(tr.v2) - a);
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
    if (!(glm::dot(n, p - a) > 0.0)) return false;
  }
  return true;
}

// The depth slice (0..D-1) of r = 1 / depth on a face whose boundaries are `b` (D + 1 of them,
// decreasing): how many inner boundaries lie at or beyond r (grid_trace.comp SliceOf).
std::uint32_t SliceOf(double r, const float* b, std::uint32_t depth) {
  std::uint32_t k = 0;
  for (std::uint32_t j = 1; j < depth; ++j) k += r <= static_cast<double>(b[j]) ? 1u : 0u;
  return k;
}

// Per face of a 3D grid about `o` with core half-side zn, the depth slices' boundaries in r = 1 / m:
// 1 / near, then geometric in depth out to the scene box's farthest corner, then 0 (infinitely far);
// appended to g.slices. Returns each face's first boundary.
std::array<const float*, layout::kGridFaces> AppendSlices(const SceneBuffers& scene, glm::dvec3 o, float zn, std::uint32_t depth,
                                                          GridArrays& g) {
  const std::size_t slice_base = g.slices.size();
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    const FaceAxes ax = AxesOf(f);
    double far = 0.0;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 p((k & 1) ? scene.hi.x : scene.lo.x, (k & 2) ? scene.hi.y : scene.lo.y, (k & 4) ? scene.hi.z : scene.lo.z);
      far = std::max(far, ax.sign * (p[ax.major] - o[ax.major]));
    }
    far = std::max(far, 2.0 * zn);
    g.slices.push_back(static_cast<float>(1.0 / (zn * layout::kGridNearShrink)));
    for (std::uint32_t j = 1; j < depth; ++j) g.slices.push_back(static_cast<float>(1.0 / (zn * std::pow(far / zn, double(j) / depth))));
    g.slices.push_back(0.0f);
  }
  std::array<const float*, layout::kGridFaces> bounds{};
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) bounds[f] = g.slices.data() + slice_base + std::size_t{f} * (depth + 1);
  return bounds;
}

// An area light's 3D perspective grid about its centre (rayspace/contract.h, kGridNearShrink): per
// face n x n x D cells in (u, v, r = 1 / depth), depth slices spaced geometrically from the core's
// half-side zn (Options::area_near times the light's reach) to the farthest corner of the scene's
// box. Each triangle goes into the cells of the perspective box of its part in the face's frustum
// beyond the near plane, widened by kGridCellSlack in u, v and 2^-10 in r. Within the core, rays
// walk the regular grid.
// `light`: an area light (its box culls under --closed-models), or null: the eye's grid at `centre`.
void BuildVolume(const SceneBuffers& scene, const layout::Light* light, glm::vec3 centre, const Options& options, GridArrays& g,
                 std::uint32_t index) {
  const std::uint32_t n = options.area_cells, depth = options.area_depth;
  const float extent = std::max({scene.hi.x - scene.lo.x, scene.hi.y - scene.lo.y, scene.hi.z - scene.lo.z, 1e-30f});
  glm::vec3 llo = centre, lhi = centre;
  float zn = extent * 0.015625f;  // the eye's: 2^-6 of the scene
  if (light) {
    LightCorners(*light, llo, lhi);
    const glm::vec3 reach = glm::max(lhi - centre, centre - llo);
    // The core holds every sample point; never thinner than 2^-20 of the scene's size.
    zn = static_cast<float>(options.area_near) * std::max({reach.x, reach.y, reach.z, extent * 9.5367431640625e-07f});
  }
  g.light_grids[index] = glm::uvec4(static_cast<std::uint32_t>(g.first.size()), n, depth, static_cast<std::uint32_t>(g.slices.size()));
  g.origins[index] = glm::vec4(centre, zn);
  const glm::dvec3 o(centre);
  const double depth_slack = options.margins ? 1.0 / 1024.0 : 0.0;
  const double near = static_cast<double>(zn * layout::kGridNearShrink) * (1.0 - depth_slack);
  const std::array<const float*, layout::kGridFaces> bounds = AppendSlices(scene, o, zn, depth, g);
  const std::size_t face_cells = std::size_t{n} * n * depth, cells = layout::kGridFaces * face_cells;
  const double half = 0.5 * n, slack = options.margins ? static_cast<double>(layout::kGridCellSlack) : 0.0,
               w = 1.0 + (options.margins ? static_cast<double>(layout::kGridFaceSlack) : 0.0);
  g.volume_refs += BinCsr(scene.triangles.size(), cells, false, [&](std::uint32_t t, Refs& refs) {
    const layout::Triangle& tr = scene.triangles[t];
    if (light && options.closed && FrontFromBox(tr, glm::dvec3(llo), glm::dvec3(lhi))) return;
    const glm::dvec3 rel[3] = {Vertex(tr.v0) - o, Vertex(tr.v1) - o, Vertex(tr.v2) - o};
    for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
      const FaceAxes ax = AxesOf(f);
      std::vector<glm::dvec3> poly(rel, rel + 3);
      glm::dvec3 plane(0.0);
      plane[ax.major] = ax.sign;
      for (int side = 0; side < 5 && !poly.empty(); ++side) {
        if (side == 4) {  // beyond the near plane: sign * p[major] - near >= 0, as a plane through p - near * axis
          std::vector<glm::dvec3> shifted;
          for (glm::dvec3 p : poly) shifted.push_back(p - plane * near);
          poly = ClipHalfSpace(shifted, plane);
          for (glm::dvec3& p : poly) p += plane * near;
          continue;
        }
        glm::dvec3 s(0.0);
        s[ax.major] = ax.sign * w;
        s[side < 2 ? ax.a : ax.b] = side % 2 == 0 ? -1.0 : 1.0;
        poly = ClipHalfSpace(poly, s);
      }
      if (poly.empty()) continue;
      double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
      for (const glm::dvec3& p : poly) {
        const double m = std::max(ax.sign * p[ax.major], near);
        const double c3[3] = {p[ax.a] / m, p[ax.b] / m, 1.0 / m};
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c3[k]), hi[k] = std::max(hi[k], c3[k]);
      }
      std::uint32_t c[4];
      for (int k = 0; k < 2; ++k) {
        const double x0 = std::floor((lo[k] + 1.0) * half - slack), x1 = std::floor((hi[k] + 1.0) * half + slack);
        c[2 * k] = static_cast<std::uint32_t>(std::clamp(x0, 0.0, n - 1.0));
        c[2 * k + 1] = static_cast<std::uint32_t>(std::clamp(x1, 0.0, n - 1.0));
      }
      const std::uint32_t k0 = SliceOf(hi[2] * (1.0 + depth_slack), bounds[f], depth), k1 = SliceOf(lo[2] * (1.0 - depth_slack), bounds[f], depth);
      for (std::uint32_t k = k0; k <= k1; ++k)
        for (std::uint32_t j = c[2]; j <= c[3]; ++j)
          for (std::uint32_t i = c[0]; i <= c[1]; ++i) refs.Add(static_cast<std::uint32_t>(f * face_cells + (std::size_t{k} * n + j) * n + i), t);
    }
  }, g);
  g.volume_cells += cells;
}

// The regular grid over the scene's box, widened by 2^-10 of its size on each side; `cells` along
// the longest side, the others in proportion (at least 1).
void BuildRegular(const SceneBuffers& scene, std::uint32_t longest, bool margins, GridArrays& g) {
  glm::dvec3 lo(scene.lo), hi(scene.hi);
  const glm::dvec3 pad = glm::max(hi - lo, glm::dvec3(std::max({(hi - lo).x, (hi - lo).y, (hi - lo).z}))) * (1.0 / 1024.0) + 1e-30;
  lo -= pad;
  hi += pad;
  const glm::dvec3 size = hi - lo;
  const double side = std::max({size.x, size.y, size.z});
  glm::uvec3 dims;
  for (int k = 0; k < 3; ++k) dims[k] = std::max(1u, static_cast<std::uint32_t>(std::ceil(longest * size[k] / side)));
  const glm::vec3 cell = glm::vec3(size / glm::dvec3(dims));
  const glm::vec3 flo(lo);
  const glm::vec3 inv = glm::vec3(1.0 / glm::dvec3(cell));
  const glm::vec3 fhi = flo + glm::vec3(dims) * cell;
  g.volume = {glm::vec4(flo, 0.0f), glm::vec4(cell, 0.0f), glm::vec4(inv, 0.0f), glm::vec4(fhi, 0.0f)};
  g.volume_dims = {glm::uvec4(dims, static_cast<std::uint32_t>(g.first.size()))};
  const std::size_t cells = std::size_t{dims.x} * dims.y * dims.z;
  const double slack = margins ? static_cast<double>(layout::kGridCellSlack) : 0.0;
  g.regular_refs += BinCsr(scene.triangles.size(), cells, false, [&](std::uint32_t t, Refs& refs) {
    const layout::Triangle& tr = scene.triangles[t];
    const glm::dvec3 a = Vertex(tr.v0), b = Vertex(tr.v1), c = Vertex(tr.v2);
    const glm::dvec3 tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
    glm::uvec3 c0, c1;
    for (int k = 0; k < 3; ++k) {
      const double x0 = std::floor((tlo[k] - double(flo[k])) / double(cell[k]) - slack);
      const double x1 = std::floor((thi[k] - double(flo[k])) / double(cell[k]) + slack);
      c0[k] = static_cast<std::uint32_t>(std::clamp(x0, 0.0, dims[k] - 1.0));
      c1[k] = static_cast<std::uint32_t>(std::clamp(x1, 0.0, dims[k] - 1.0));
    }
    for (std::uint32_t z = c0.z; z <= c1.z; ++z)
      for (std::uint32_t y = c0.y; y <= c1.y; ++y)
        for (std::uint32_t x = c0.x; x <= c1.x; ++x) refs.Add(static_cast<std::uint32_t>((std::size_t{z} * dims.y + y) * dims.x + x), t);
  }, g);
  g.regular_cells = cells;
}

}  // namespace

FaceUv DirectionFace(glm::vec3 d) {
  const glm::vec3 a(Abs(d.x), Abs(d.y), Abs(d.z));
  const std::uint32_t major = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
  const float m = a[major];
  FaceUv f;
  f.face = 2u * major + (d[major] < 0.0f ? 1u : 0u);
  f.u = d[(major + 1) % 3] / m;
  f.v = d[(major + 2) % 3] / m;
  return f;
}

std::uint32_t PerspectiveGridOf(const layout::Ray& r, bool shadow, std::span<const glm::uvec4> light_grids,
                                std::span<const glm::vec4> origins, std::uint32_t eye) {
  std::uint32_t index = layout::kGridNoLight;
  if (shadow && r.info.z == layout::kRayShadow) index = r.info.w;
  if (!shadow && r.info.z == layout::kRayPrimary) index = eye;
  if (index >= light_grids.size() || light_grids[index].x == layout::kGridNoLight || light_grids[index].z != 0u) return layout::kGridNoLight;
  const glm::vec4 o = origins[index];
  return o.x == r.origin_tmin.x && o.y == r.origin_tmin.y && o.z == r.origin_tmin.z ? index : layout::kGridNoLight;
}

std::uint32_t VolumeGridOf(const layout::Ray& r, bool shadow, std::span<const glm::uvec4> light_grids, std::uint32_t secondary) {
  std::uint32_t index = layout::kGridNoLight;
  if (shadow && r.info.z == layout::kRayShadow) index = r.info.w;
  if (!shadow && r.info.z != layout::kRayPrimary) index = secondary;
  if (index >= light_grids.size()) return layout::kGridNoLight;
  const glm::uvec4 g = light_grids[index];
  return g.x != layout::kGridNoLight && g.z != 0u ? index : layout::kGridNoLight;
}

std::uint32_t FaceCell(FaceUv f, std::uint32_t n) {
  const float half = static_cast<float>(n) * 0.5f;
  const float x = (f.u + 1.0f) * half, y = (f.v + 1.0f) * half;
  const std::uint32_t i = std::min(static_cast<std::uint32_t>(Max(x, 0.0f)), n - 1u);
  const std::uint32_t j = std::min(static_cast<std::uint32_t>(Max(y, 0.0f)), n - 1u);
  return (f.face * n + j) * n + i;
}

double PointTriangleDistance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = va + vb + vc;
  if (!(denom != 0.0)) return std::min({glm::length(p - a), glm::length(p - b), glm::length(p - c)});  // degenerate
  const double v = vb / denom, w = vc / denom;
  return glm::length(p - (a + ab * v + ac * w));
}

bool FacesAway(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 o) {
  const glm::vec3 n = PlaneNormalOf(v0, v1, v2);
  return Dot(n, o - v0) < 0.0f;
}

std::vector<bool> ClosedObjects(const SceneBuffers& scene, std::vector<std::size_t>* open_edges) {
  const std::size_t n = scene.triangles.size();
  // Vertex ids by exact coordinates; each undirected edge's triangles.
  std::map<std::array<std::uint32_t, 3>, std::uint32_t> ids;
  const auto id = [&](const glm::vec4& v) {
    const std::array<std::uint32_t, 3> key{FloatBits(v.x), FloatBits(v.y), FloatBits(v.z)};
    return ids.emplace(key, static_cast<std::uint32_t>(ids.size())).first->second;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edges;
  for (std::uint32_t t = 0; t < n; ++t) {
    const layout::Triangle& tr = scene.triangles[t];
    const std::uint32_t v[3] = {id(tr.v0), id(tr.v1), id(tr.v2)};
    for (int e = 0; e < 3; ++e) edges[std::minmax(v[e], v[(e + 1) % 3])].push_back(t);
  }
  // Surfaces: union-find over triangles sharing an edge.
  std::vector<std::uint32_t> parent(n);
  for (std::uint32_t t = 0; t < n; ++t) parent[t] = t;
  const auto find = [&](std::uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (const auto& [edge, tris] : edges)
    for (std::size_t i = 1; i < tris.size(); ++i) parent[find(tris[i])] = find(tris[0]);
  std::map<std::uint32_t, std::size_t> open_of_surface;
  for (const auto& [edge, tris] : edges)
    if (tris.size() != 2) ++open_of_surface[find(tris[0])];
  std::vector<bool> closed;
  if (open_edges) open_edges->clear();
  for (const glm::uvec4& obj : scene.objects) {
    std::map<std::uint32_t, std::size_t> surfaces;  // the open surfaces this object has triangles in
    for (std::uint32_t t = obj.x; t < obj.x + obj.y; ++t)
      if (const auto it = open_of_surface.find(find(t)); it != open_of_surface.end()) surfaces[it->first] = it->second;
    std::size_t open = 0;
    for (const auto& [s, count] : surfaces) open += count;
    closed.push_back(obj.y > 0 && open == 0);
    if (open_edges) open_edges->push_back(open);
  }
  return closed;
}

std::uint32_t EyeCells(std::uint32_t height, double tan_half_fov) {
  const double face_pixels = tan_half_fov > 0 ? height / tan_half_fov : 100.0;
  return static_cast<std::uint32_t>(std::clamp(std::round(face_pixels / 100.0), 1.0, 1024.0));
}

GridArrays Build(const SceneBuffers& scene, const Options& options, const glm::vec3* eye, std::uint32_t eye_cells, const glm::vec3* secondary_eye) {
  RS_CHECK_MSG(options.cells >= 1 && options.regular >= 1, "grid: {} cells per face, {} along the box", options.cells, options.regular);
  RS_CHECK_MSG(options.area_cells >= 1 && options.area_depth >= 1 && options.area_depth <= layout::kGridMaxSlices, "grid: {}x{}x{} area cells",
               options.area_cells, options.area_cells, options.area_depth);
  GridArrays g;
  for (const layout::Light& l : scene.lights) {
    g.origins.emplace_back(l.position.x, l.position.y, l.position.z, 1.0f);
    if (l.sampling.x != layout::kLightPoint) {
      g.light_grids.emplace_back(layout::kGridNoLight, 0u, 0u, 0u);
      continue;
    }
    g.light_grids.emplace_back(static_cast<std::uint32_t>(g.first.size()), options.cells, 0u, 0u);
    BuildPerspective(scene, Xyz(l.position), options.cells, options.closed, options.margins, g);
  }
  if (eye) {
    g.eye = static_cast<std::uint32_t>(g.light_grids.size());
    g.origins.emplace_back(*eye, 1.0f);
    g.light_grids.emplace_back(static_cast<std::uint32_t>(g.first.size()), eye_cells, 0u, 0u);
    BuildPerspective(scene, *eye, eye_cells, false, options.margins, g);
  }
  g.perspective_cells = g.first.size();
  BuildRegular(scene, options.regular, options.margins, g);
  // The 3D grids come last: only the 2D grids' references carry (u, v) rectangles.
  if (options.area_perspective)
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
      if (scene.lights[l].sampling.x != layout::kLightPoint)
        BuildVolume(scene, &scene.lights[l], Xyz(scene.lights[l].position), options, g, static_cast<std::uint32_t>(l));
  if (options.secondary_perspective && secondary_eye) {
    g.secondary = static_cast<std::uint32_t>(g.light_grids.size());
    g.light_grids.emplace_back(layout::kGridNoLight, 0u, 0u, 0u);
    g.origins.emplace_back(*secondary_eye, 1.0f);
    BuildVolume(scene, nullptr, *secondary_eye, options, g, g.secondary);
  }
  g.first.push_back(static_cast<std::uint32_t>(g.triangles.size()));
  RS_CHECK_MSG(g.triangles.size() < (std::size_t{1} << 32), "grid: {} cell references", g.triangles.size());
  return g;
}

}  // namespace rayspace::emu::grid
