// The grids of `--algo grid`, built on the host in double (rayspace/emu/grid/grid.h, docs/grids.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <array>
#include <limits>
#include <map>
#include <utility>

#include "rayspace/emu/grid/grid.h"
#include "rayspace/emu/grid/face_math.h"
#include "grid_bin.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/light_sample.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu::grid {
namespace {

// A run of triangles' cell references, in the order they were binned.
struct Refs {
  std::vector<std::uint32_t> cells, triangles;
  std::vector<glm::vec4> boxes;  // 2D grids: each reference's (u, v) rectangle
};

// One grid's lists from every triangle's references, each list in ascending triangle order: the
// triangles are binned in parallel in fixed runs, then laid out by a counting sort of the runs in
// order (count, exclusive scan, scatter): the same arrays for every thread count, and the ones the
// kernels' count, scan, emit, stable sort and gather give (BuildWithPasses).
GridLists BinHost(const SceneBuffers& scene, const layout::GridBuildGrid& grid, std::span<const float> slices, std::size_t cells) {
  constexpr std::size_t kRun = 1024;
  const std::size_t triangles = scene.triangles.size();
  const bool boxes = grid.shape.x == layout::kGridKindPerspective;
  std::vector<Refs> runs((triangles + kRun - 1) / kRun);
  ParallelForDynamic(runs.size(), 1, [&](std::size_t k) {
    Refs& refs = runs[k];
    for (std::size_t t = k * kRun; t < std::min(triangles, (k + 1) * kRun); ++t)
      bin::BinTriangle(grid, slices, scene.triangles[t], [&](std::uint32_t cell, const glm::vec4& box) {
        refs.cells.push_back(cell);
        refs.triangles.push_back(static_cast<std::uint32_t>(t));
        if (boxes) refs.boxes.push_back(box);
      });
  });
  GridLists out;
  std::vector<std::size_t> at(cells, 0);
  for (const Refs& r : runs)
    for (const std::uint32_t c : r.cells) ++at[c];
  std::size_t next = 0;
  out.first.reserve(cells + 1);
  for (std::size_t c = 0; c < cells; ++c) {
    out.first.push_back(static_cast<std::uint32_t>(next));
    next += std::exchange(at[c], next);
  }
  RS_CHECK_MSG(next < (std::size_t{1} << 32), "grid: {} cell references", next);
  out.first.push_back(static_cast<std::uint32_t>(next));
  out.triangles.resize(next);
  if (boxes) out.boxes.resize(next);
  for (Refs& r : runs) {
    for (std::size_t i = 0; i < r.cells.size(); ++i) {
      const std::size_t pos = at[r.cells[i]]++;
      out.triangles[pos] = r.triangles[i];
      if (boxes) out.boxes[pos] = r.boxes[i];
    }
    r = Refs();
  }
  if (!boxes) return out;
  // Per cell, the least distance of the triangles it lists.
  std::vector<float> dist(triangles);
  ParallelFor(triangles, [&](std::size_t t) { dist[t] = bin::LeastDistance(grid, scene.triangles[t]); });
  out.min_dist.assign(cells, INFINITY);
  ParallelFor(cells, [&](std::size_t c) {
    float m = INFINITY;
    for (std::size_t i = out.first[c]; i < out.first[c + 1]; ++i) m = std::min(m, dist[out.triangles[i]]);
    out.min_dist[c] = m;
  });
  return out;
}

// Per face of a 3D grid about `o` with core half-side zn, the depth slices' boundaries in r = 1 / m:
// 1 / near, then geometric in depth out to the scene box's farthest corner, then 0 (infinitely far);
// appended to g.slices.
void AppendSlices(const SceneBuffers& scene, glm::dvec3 o, float zn, std::uint32_t depth, GridArrays& g) {
  for (std::uint32_t f = 0; f < layout::kGridFaces; ++f) {
    const bin::FaceAxes ax = bin::AxesOf(f);
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
}

std::uint32_t Flags(const Options& options, bool cull) {
  return (options.margins ? layout::kGridBuildMargins : 0u) | (cull ? layout::kGridBuildCull : 0u);
}

// The plan's grids are laid out one after another: each the next cells.
void AddGrid(GridPlan& p, const layout::GridBuildGrid& grid, std::uint64_t cells) {
  p.grids.push_back(grid);
  p.cells.push_back(cells);
  RS_CHECK_MSG(p.total_cells + cells < (std::uint64_t{1} << 32), "grid: {} cells", p.total_cells + cells);
  p.total_cells += cells;
}

// One point light's (or the eye's) grid: n x n cells on each of the six faces of a cube about it.
void PlanPerspective(GridPlan& p, glm::vec3 centre, std::uint32_t n, bool cull, const Options& options) {
  layout::GridBuildGrid grid{};
  grid.centre = glm::vec4(centre, 1.0f);
  grid.shape = glm::uvec4(layout::kGridKindPerspective, n, 0u, 0u);
  grid.flags = glm::uvec4(Flags(options, cull), 0u, 0u, 0u);
  AddGrid(p, grid, layout::kGridFaces * std::uint64_t{n} * n);
}

// An area light's 3D perspective grid about its centre (rayspace/contract.h, kGridNearShrink): per
// face n x n x D cells in (u, v, r = 1 / depth), depth slices spaced geometrically from the core's
// half-side zn (Options::area_near times the light's reach) to the farthest corner of the scene's
// box. Each triangle goes into the cells of the perspective box of its part in the face's frustum
// beyond the near plane, widened by kGridCellSlack in u, v and 2^-10 in r (bin::BinVolume). Within
// the core, rays walk the regular grid.
// `light`: an area light (its box culls under --closed-models), or null: the eye's grid at `centre`.
void PlanVolume(GridPlan& p, const SceneBuffers& scene, const layout::Light* light, glm::vec3 centre, const Options& options,
                std::uint32_t index) {
  GridArrays& g = p.arrays;
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
  g.light_grids[index] = glm::uvec4(static_cast<std::uint32_t>(p.total_cells), n, depth, static_cast<std::uint32_t>(g.slices.size()));
  g.origins[index] = glm::vec4(centre, zn);
  layout::GridBuildGrid grid{};
  grid.centre = glm::vec4(centre, zn);
  grid.light_lo = glm::vec4(llo, 0.0f);
  grid.light_hi = glm::vec4(lhi, 0.0f);
  grid.shape = glm::uvec4(layout::kGridKindVolume, n, depth, 0u);
  grid.flags = glm::uvec4(Flags(options, light && options.closed), static_cast<std::uint32_t>(g.slices.size()), 0u, 0u);
  AppendSlices(scene, glm::dvec3(centre), zn, depth, g);
  AddGrid(p, grid, layout::kGridFaces * std::uint64_t{n} * n * depth);
}

// The regular grid's cells along each axis of a box of `size`: `longest` along the longest side, the
// others in proportion (at least 1).
glm::uvec3 RegularDims(const glm::dvec3& size, std::uint32_t longest) {
  const double side = std::max({size.x, size.y, size.z});
  glm::uvec3 dims;
  for (int k = 0; k < 3; ++k) dims[k] = std::max(1u, static_cast<std::uint32_t>(std::ceil(longest * size[k] / side)));
  return dims;
}

// The regular grid over the scene's box, widened by 2^-10 of its size on each side; `cells` along
// the longest side (or, with options.regular_cells, the count whose grid is closest to that many
// cells), the others in proportion.
void PlanRegular(GridPlan& p, const SceneBuffers& scene, std::uint32_t longest, const Options& options) {
  GridArrays& g = p.arrays;
  glm::dvec3 lo(scene.lo), hi(scene.hi);
  const glm::dvec3 pad = glm::max(hi - lo, glm::dvec3(std::max({(hi - lo).x, (hi - lo).y, (hi - lo).z}))) * (1.0 / 1024.0) + 1e-30;
  lo -= pad;
  hi += pad;
  const glm::dvec3 size = hi - lo;
  if (options.regular_cells) longest = RegularLongestFor(size, options.regular_cells);
  const glm::uvec3 dims = RegularDims(size, longest);
  const glm::vec3 cell = glm::vec3(size / glm::dvec3(dims));
  const glm::vec3 flo(lo);
  const glm::vec3 inv = glm::vec3(1.0 / glm::dvec3(cell));
  const glm::vec3 fhi = flo + glm::vec3(dims) * cell;
  g.volume = {glm::vec4(flo, 0.0f), glm::vec4(cell, 0.0f), glm::vec4(inv, 0.0f), glm::vec4(fhi, 0.0f)};
  g.volume_dims = {glm::uvec4(dims, static_cast<std::uint32_t>(p.total_cells))};
  layout::GridBuildGrid grid{};
  grid.centre = glm::vec4(flo, 0.0f);
  grid.cell = glm::vec4(cell, 0.0f);
  grid.shape = glm::uvec4(layout::kGridKindRegular, dims.x, dims.y, dims.z);
  grid.flags = glm::uvec4(Flags(options, false), 0u, 0u, 0u);
  AddGrid(p, grid, std::uint64_t{dims.x} * dims.y * dims.z);
}

}  // namespace

FaceUv DirectionFace(glm::vec3 d) {
  const FaceUvOf<float> f = DirectionFaceOf<float>(d);
  return {f.face, f.u, f.v};
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
  const float x = FaceCoordinateOf(f.u, n), y = FaceCoordinateOf(f.v, n);
  const std::uint32_t i = std::min(static_cast<std::uint32_t>(Max(x, 0.0f)), n - 1u);
  const std::uint32_t j = std::min(static_cast<std::uint32_t>(Max(y, 0.0f)), n - 1u);
  return (f.face * n + j) * n + i;
}

double PointTriangleDistance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  return bin::PointTriangleDistanceOf<bin::Exact>(p, a, b, c);
}

bool FacesAway(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 o) { return FacesAwayOf(v0, v1, v2, o); }

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

std::uint32_t RegularLongestFor(const glm::dvec3& size, std::uint64_t cells) {
  std::uint32_t best = 1;
  std::uint64_t best_gap = ~std::uint64_t{0};
  for (std::uint32_t n = 1; n <= kRegularLongestMax; ++n) {
    const glm::uvec3 d = RegularDims(size, n);
    const std::uint64_t have = std::uint64_t{d.x} * d.y * d.z, gap = have > cells ? have - cells : cells - have;
    if (gap < best_gap) best = n, best_gap = gap;
  }
  return best;
}

std::uint32_t EyeCells(std::uint32_t height, double tan_half_fov) {
  const double face_pixels = tan_half_fov > 0 ? height / tan_half_fov : 100.0;
  return static_cast<std::uint32_t>(std::clamp(std::round(face_pixels / 100.0), 1.0, 1024.0));
}

GridPlan Plan(const SceneBuffers& scene, const Options& options, const glm::vec3* eye, std::uint32_t eye_cells, const glm::vec3* secondary_eye) {
  RS_CHECK_MSG(options.cells >= 1 && options.regular >= 1, "grid: {} cells per face, {} along the box", options.cells, options.regular);
  RS_CHECK_MSG(options.area_cells >= 1 && options.area_depth >= 1 && options.area_depth <= layout::kGridMaxSlices, "grid: {}x{}x{} area cells",
               options.area_cells, options.area_cells, options.area_depth);
  GridPlan p;
  GridArrays& g = p.arrays;
  for (const layout::Light& l : scene.lights) {
    g.origins.emplace_back(l.position.x, l.position.y, l.position.z, 1.0f);
    if (l.sampling.x != layout::kLightPoint) {
      g.light_grids.emplace_back(layout::kGridNoLight, 0u, 0u, 0u);
      continue;
    }
    g.light_grids.emplace_back(static_cast<std::uint32_t>(p.total_cells), options.cells, 0u, 0u);
    PlanPerspective(p, Xyz(l.position), options.cells, options.closed, options);
  }
  if (eye) {
    g.eye = static_cast<std::uint32_t>(g.light_grids.size());
    g.origins.emplace_back(*eye, 1.0f);
    g.light_grids.emplace_back(static_cast<std::uint32_t>(p.total_cells), eye_cells, 0u, 0u);
    p.eye_grid = p.grids.size();
    PlanPerspective(p, *eye, eye_cells, false, options);  // every triangle: eye rays want the closest hit
  }
  g.perspective_cells = p.total_cells;
  PlanRegular(p, scene, options.regular, options);
  // The 3D grids come last: only the 2D grids' references carry (u, v) rectangles.
  if (options.area_perspective)
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
      if (scene.lights[l].sampling.x != layout::kLightPoint)
        PlanVolume(p, scene, &scene.lights[l], Xyz(scene.lights[l].position), options, static_cast<std::uint32_t>(l));
  if (options.secondary_perspective && secondary_eye) {
    g.secondary = static_cast<std::uint32_t>(g.light_grids.size());
    g.light_grids.emplace_back(layout::kGridNoLight, 0u, 0u, 0u);
    g.origins.emplace_back(*secondary_eye, 1.0f);
    PlanVolume(p, scene, nullptr, *secondary_eye, options, g.secondary);
  }
  return p;
}

void AppendLists(GridArrays& g, const layout::GridBuildGrid& grid, std::uint64_t cells, const GridLists& lists) {
  RS_CHECK(lists.first.size() == cells + 1 && lists.first.back() == lists.triangles.size());
  const std::size_t base = g.triangles.size(), refs = lists.triangles.size();
  RS_CHECK_MSG(base + refs < (std::size_t{1} << 32), "grid: {} cell references", base + refs);
  for (std::size_t c = 0; c < cells; ++c) g.first.push_back(static_cast<std::uint32_t>(base + lists.first[c]));
  g.triangles.insert(g.triangles.end(), lists.triangles.begin(), lists.triangles.end());
  if (grid.shape.x == layout::kGridKindPerspective) {
    RS_CHECK(g.boxes.size() == base && lists.boxes.size() == refs && lists.min_dist.size() == cells);  // rectangles share the references' indices
    g.boxes.insert(g.boxes.end(), lists.boxes.begin(), lists.boxes.end());
    g.min_dist.insert(g.min_dist.end(), lists.min_dist.begin(), lists.min_dist.end());
    g.perspective_refs += refs;
  } else if (grid.shape.x == layout::kGridKindRegular) {
    g.regular_refs += refs;
    g.regular_cells = cells;
  } else {
    g.volume_refs += refs;
    g.volume_cells += cells;
  }
}

void FinishLists(GridArrays& g) {
  g.first.push_back(static_cast<std::uint32_t>(g.triangles.size()));
}

GridArrays Build(const SceneBuffers& scene, const Options& options, const glm::vec3* eye, std::uint32_t eye_cells, const glm::vec3* secondary_eye) {
  return Build(scene, Plan(scene, options, eye, eye_cells, secondary_eye));
}

GridArrays Build(const SceneBuffers& scene, GridPlan p, double* eye_ms) {
  for (std::size_t k = 0; k < p.grids.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    AppendLists(p.arrays, p.grids[k], p.cells[k], BinHost(scene, p.grids[k], p.arrays.slices, p.cells[k]));
    if (eye_ms && k == p.eye_grid) *eye_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  FinishLists(p.arrays);
  return std::move(p.arrays);
}

}  // namespace rayspace::emu::grid
