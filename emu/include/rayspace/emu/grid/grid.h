// Hunt and Mark's perspective grids (docs/grids.md): per point light a grid of cells about the light,
// so that each of its shadow rays visits one cell; a regular grid over the scene for every other ray.
// The grids are built on the host (grid::Build, deterministic, in double); each batch is one
// grid.trace call on the frame's backend, so `diff` compares it as any other pass.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "rayspace/contract.h"
#include "rayspace/emu/cone_simd.h"
#include "rayspace/emu/fields.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::emu {

// What grid.trace reads (rayspace/contract.h, kGridTrace*).
struct GridArrays {
  std::vector<std::uint32_t> first;      // every cell's CSR offset into `triangles`, then the total
  std::vector<std::uint32_t> triangles;  // per cell, ascending scene triangle ids
  std::vector<float> min_dist;           // per perspective cell: least distance from its light
  std::vector<glm::vec4> boxes;          // per reference of a perspective cell: its (u, v) rectangle, umin, vmin, umax, vmax
  std::vector<glm::uvec4> light_grids;   // per light, then the eye's (--primary grid): first cell (kGridNoLight: none), n
  std::vector<glm::vec4> origins;        // per light, then the eye: its position, 1
  std::uint32_t eye = layout::kGridNoLight;  // the eye's entry in light_grids/origins, or none
  std::uint32_t secondary = layout::kGridNoLight;  // the 3D grid about the eye for reflection and refraction rays, or none
  std::vector<glm::vec4> volume;         // the regular grid: lo, cell, inv_cell, hi
  std::vector<glm::uvec4> volume_dims;   // one entry: cells along x, y, z, the first cell
  std::vector<float> slices;             // per area light's 3D grid, per face: D + 1 depth boundaries in r = 1 / depth
  std::uint64_t perspective_cells = 0, regular_cells = 0, perspective_refs = 0, regular_refs = 0;
  std::uint64_t volume_cells = 0, volume_refs = 0;  // the area lights' 3D perspective grids
};

// One grid's lists (grid.cells, the host's BinHost): per cell its CSR offset into `triangles`, then
// the total; per cell its triangles in ascending order; in a 2D grid each reference's (u, v)
// rectangle and per cell the least distance of its triangles from the grid's centre.
struct GridLists {
  std::vector<std::uint32_t> first, triangles;
  std::vector<glm::vec4> boxes;
  std::vector<float> min_dist;
  RS_FIELDS(first, triangles, boxes, min_dist)
};

// grid.count: per triangle its references in one grid, and per (triangle, face) its span of cells
// (rayspace/contract.h kGridBuild*: columns, rows and slices packed two to a word, w = 1 when the
// face holds any) and, in a 2D grid, its (u, v) rectangle; a 2D grid's least distance per triangle
// from the grid's centre, rounded down. Unused arrays are empty.
struct GridCounts {
  std::vector<std::uint32_t> counts;
  std::vector<float> dist;
  std::vector<glm::uvec4> spans;
  std::vector<glm::vec4> span_boxes;
  RS_FIELDS(counts, dist, spans, span_boxes)
};

// grid.emit: per triangle its first reference; per reference, in triangle order, its cell within the
// grid, its triangle and (2D grids; else empty) its (u, v) rectangle.
struct GridRefs {
  std::vector<std::uint32_t> offsets, cells, triangles;
  std::vector<glm::vec4> boxes;
  RS_FIELDS(offsets, cells, triangles, boxes)
};

// Per ray: the closest hit (closest-hit batches) or whether it is occluded (shadow batches; the other
// array is empty), the cells it visited and the triangles it tested.
struct GridWalks {
  std::vector<std::uint64_t> hits;
  std::vector<std::uint32_t> occluded, steps, tests;
  RS_FIELDS(hits, occluded, steps, tests)
  // Per ray, the steps of `steps` taken in an area light's core cube (the regular grid's cells):
  // counted by the emulator's walk for the statistics (Hunt and Mark's table 5 is reported with and
  // without them); grid_trace.comp does not write it, so a backend's walks leave it empty and it is
  // not one of the compared fields.
  std::vector<std::uint32_t> core_steps;
};

namespace grid {

struct Options {
  std::uint32_t cells = 200;   // a perspective grid's cells per face side (--grid-cells)
  std::uint32_t regular = 54;  // the regular grid's cells along the scene box's longest side (--grid-regular)
  // --closed-models (Hunt and Mark's front-face culling, valid for closed meshes only): a light's grid
  // holds only the triangles facing away from it, and a shadow ray ending on one is occluded untraced.
  bool closed = false;
  // An area light's 3D perspective grid (Hunt and Mark's 200 x 200 x 4): cells per face side and
  // depth slices; `area_perspective` false sends area-light shadow rays through the regular grid
  // instead (their Table 5 compares the two).
  std::uint32_t area_cells = 200, area_depth = 4;
  // The core cube about an area light (walked through the regular grid: rays from points off the
  // centre sweep many perspective columns close to it) has this many times the light's reach as its
  // half-side; the faces' cells begin beyond it.
  std::uint32_t area_near = 8;
  // --grid-secondary perspective: reflection and refraction rays walk a 3D perspective grid about the
  // eye (area_cells x area_cells x area_depth a face, beginning 2^-6 of the scene's size from the
  // eye) instead of the regular grid.
  bool secondary_perspective = false;
  bool area_perspective = true;
  // The binning's rounding margins (kGridFaceSlack, kGridCellSlack, kGridDistanceSlack and 2^-10 in
  // depth, docs/grids.md). false: none, each triangle binned by its exact extent and its least
  // distance rounded to nearest: what `rayspace accuracy` compares them with (rays then miss hits).
  bool margins = true;
  // The render path (--path auto/fused on the emulator): grid.trace with each cell's triangles in
  // lanes (PassGridTraceLanes), the pass's walks bit for bit; `diff` and a backend run the pass.
  bool lanes = false;
  // --grid-regular-cells: when not 0, `regular` is instead the count along the longest side (1 to
  // 1024, the lower on a tie) whose grid holds the number of cells closest to this.
  std::uint64_t regular_cells = 0;
};

// The face (0..5: +x, -x, +y, -y, +z, -z) and the (u, v) in [-1, 1] of a direction seen from a light;
// u, v are the direction's two other components over the major one (kernels: grid_trace.comp).
struct FaceUv {
  std::uint32_t face = 0;
  float u = 0.0f, v = 0.0f;
};
FaceUv DirectionFace(glm::vec3 d);
// The cell (row-major within the face) of (u, v) on a face of n x n cells.
std::uint32_t FaceCell(FaceUv f, std::uint32_t n);

// Which perspective grid a ray goes through: a point light's shadow ray (in a shadow batch) its
// light's, an eye ray (in a closest-hit batch) the eye's, when that entry has a grid and the ray
// starts exactly at its origin; kGridNoLight otherwise (the regular grid). grid.trace decides so
// (gpu/shaders/grid_trace.comp PerspectiveCell), and the statistics count with it.
std::uint32_t PerspectiveGridOf(const layout::Ray& r, bool shadow, std::span<const glm::uvec4> light_grids,
                                std::span<const glm::vec4> origins, std::uint32_t eye);

// Which 3D perspective grid a ray goes through: an area light's shadow ray (in a shadow batch) its
// light's, when the light has one; a closest-hit ray other than an eye ray the one about the eye
// (`secondary`), when there is one; kGridNoLight otherwise (grid_trace.comp VolumeOf).
std::uint32_t VolumeGridOf(const layout::Ray& r, bool shadow, std::span<const glm::uvec4> light_grids, std::uint32_t secondary);

// The least distance from p to the triangle (a, b, c), in double (Ericson's closest point).
double PointTriangleDistance(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c);

// Whether the triangle (v0, v1, v2) faces away from the point o: o lies behind its plane,
// dot((v1 - v0) x (v2 - v0), o - v0) < 0, with the normal scaled by powers of two as the watertight
// test's (PlaneNormalOf). The kernels compute it in the same order (grid_trace.comp).
bool FacesAway(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 o);

// Closedness of the scene's surfaces. Triangles sharing an edge (vertices matched by their exact
// coordinates) form one surface, whatever objects they belong to (a room's walls are one closed box);
// a surface is closed when each of its edges is shared by exactly two triangles. Per object
// (SceneBuffers::objects): whether every surface it has triangles in is closed; `open_edges` (if
// given) receives per object the open edges of those surfaces.
std::vector<bool> ClosedObjects(const SceneBuffers& scene, std::vector<std::size_t>* open_edges = nullptr);

// An eye grid's cells per face side: Hunt and Mark's cells of about 100 x 100 pixels, for an image of
// `height` pixels whose vertical half-angle has tangent `tan_half_fov` (a face spans tangents -1..1).
std::uint32_t EyeCells(std::uint32_t height, double tan_half_fov);

// --grid-regular-cells: the regular grid's count along the longest side of a box of `size` (its
// extent, padded as the grid pads it), 1 to kRegularLongestMax, whose grid holds the number of cells
// closest to `cells` (the lower count on a tie).
inline constexpr std::uint32_t kRegularLongestMax = 1024;
std::uint32_t RegularLongestFor(const glm::dvec3& size, std::uint64_t cells);

// The grids a frame builds, in cell order, each described as the build kernels read it
// (layout::GridBuildGrid), with everything of GridArrays that does not depend on binning: lights'
// and the eye's entries, the regular grid's box, the 3D grids' depth slices.
struct GridPlan {
  GridArrays arrays;
  std::vector<layout::GridBuildGrid> grids;
  std::vector<std::uint64_t> cells;  // per grid
  std::uint64_t total_cells = 0;
  std::size_t eye_grid = SIZE_MAX;  // the eye's grid among `grids` (--primary grid), or none
};
GridPlan Plan(const SceneBuffers& scene, const Options& options, const glm::vec3* eye = nullptr, std::uint32_t eye_cells = 0,
              const glm::vec3* secondary_eye = nullptr);
// Appends a planned grid's lists (its cells in plan order) to g; FinishLists closes `first` with the
// total once every grid is in.
void AppendLists(GridArrays& g, const layout::GridBuildGrid& grid, std::uint64_t cells, const GridLists& lists);
void FinishLists(GridArrays& g);
// The build kernels' descriptor as call inputs: centre, cell, light_lo, light_hi; shape, flags.
struct GridDescriptor {
  std::array<glm::vec4, 4> params;
  std::array<glm::uvec4, 2> shape;
};
GridDescriptor Describe(const layout::GridBuildGrid& g);
layout::GridBuildGrid FromDescriptor(std::span<const glm::vec4> params, std::span<const glm::uvec4> shape);

// Builds every point light's perspective grid, the eye's when `eye` is given (every triangle, no
// culling: eye rays want the closest hit), the regular grid, every area light's 3D grid and, with
// Options::secondary_perspective and `secondary_eye` given, the 3D grid about that eye.
GridArrays Build(const SceneBuffers& scene, const Options& options, const glm::vec3* eye = nullptr, std::uint32_t eye_cells = 0,
                 const glm::vec3* secondary_eye = nullptr);
// The grids of a plan binned on the host; `eye_ms`, when given, gets the time spent on the eye's grid
// (Hunt and Mark give the eye's build share apart from the lights').
GridArrays Build(const SceneBuffers& scene, GridPlan plan, double* eye_ms = nullptr);

}  // namespace grid

namespace call {
struct GridTrace;
struct GridCount;
struct GridEmit;
struct GridCells;
}
// The emulated grid.trace (mirrors gpu/shaders/grid_trace.comp).
GridWalks PassGridTrace(const call::GridTrace& c);

// The emulated build passes (mirror gpu/shaders/grid_build.comp; rayspace/contract.h kGridBuild*).
GridCounts PassGridCount(const call::GridCount& c);
GridRefs PassGridEmit(const call::GridEmit& c);
GridLists PassGridCells(const call::GridCells& c);

// The render path's grid.trace: the same walks, answers and counts as PassGridTrace, with each
// cell's triangles (those a ray tests: its own surface and, in a perspective cell, references whose
// rectangle misses the ray's (u, v) left out) gathered into lanes and tested 8 (AVX2) or 16
// (AVX-512F) at a time, each lane the scalar watertight test bit for bit. A shadow ray's tests are
// counted up to its first hit in list order, as the scalar scan stops there.
struct GridLanes {
  std::vector<float> triangles;  // per scene triangle: v0, v1, v2 and its plane normal (PlaneNormalOf), 12 floats
  cone::Isa isa = cone::Isa::kScalar;  // kScalar: PassGridTrace itself
};
// Set up once per scene (the triangles do not change over a frame); an ISA the CPU lacks means the
// best it has.
GridLanes PrepareGridLanes(std::span<const layout::Triangle> triangles, cone::Isa isa = cone::BestIsa());
GridWalks PassGridTraceLanes(const call::GridTrace& c, const GridLanes& lanes);
// Settings::grid_lanes_fault (tests only): the lanes drop the last triangle of every full lane
// group (a difference the equality test must see).

}  // namespace rayspace::emu
