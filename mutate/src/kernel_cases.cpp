#include "rayspace/mutate/kernel_cases.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "rayspace/contract.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/verify/call_codec.h"

namespace rayspace::mutate {
namespace {

using glm::vec4;
using layout::ConeNode;

// A node of one ray or of parallel rays: its axis, cosine 1 and the given sine, one ray below.
ConeNode Node(vec4 sphere, glm::vec3 axis, float cosine, float sine, float rays = 1.0f) {
  return {sphere, vec4(axis, cosine), vec4(sine, rays, 0.0f, 0.0f)};
}

// Parents whose children meet every boundary of the cone union: identical degenerate cones (the
// union's sine is exactly 0), opposite axes (the axes' sum is zero), a full-sphere child, two cones
// that together exceed a hemisphere on both sides (the sine goes negative), a sine of 2^-149.
verify::BufferSet ParentsCall(std::uint32_t child_merge) {
  const float tiny = std::numeric_limits<float>::denorm_min();
  const glm::vec3 z(0, 0, 1);
  const std::vector<ConeNode> below = {
      Node({0, 0, 0, 0}, z, 1, 0), Node({1, 0, 0, 0}, z, 1, 0),                                 // sine 0 exactly
      Node({0, 0, 0, 0}, z, 1, 0), Node({0, 1, 0, 0}, -z, 1, 0),                                // x1 + x2 = 0
      Node({0, 0, 0, 2}, {1, 0, 0}, -1, 0, 4), Node({3, 0, 0, 1}, z, 0.5f, 0.8660254f),        // a full child
      Node({0, 0, 0, 1}, z, -0.5f, 0.8660254f), Node({0, 0, 1, 1}, {0, 0.6f, -0.8f}, 0.9f, 0.43588989f),  // sine < 0
      Node({0, 0, 0, 0}, z, 1, tiny), Node({2, 0, 0, 0}, z, 1, tiny), Node({4, 0, 0, 0}, z, 1, 0),       // sine 2^-149
      Node({0, 0, 0, 1}, {1, 0, 0}, 0, 1), Node({0, 0, 0, 1}, {-1, 0, 0}, 0, 1),              // two hemispheres
  };
  const std::vector<std::uint32_t> first = {0, 2, 4, 6, 8, 11, 13};
  emu::call::BuildParents c;
  c.below = below;
  c.first = first;
  c.child_merge = child_merge;
  return verify::EncodeCall(c);
}

layout::Ray RayAt(glm::vec3 o, glm::vec3 d) {
  layout::Ray r{};
  r.origin_tmin = vec4(o, 0.0f);
  r.direction_tmax = vec4(d, std::numeric_limits<float>::max());
  r.info = glm::uvec4(0, layout::kNoPrim, layout::kRayReflection, 0);
  r.weight = vec4(1, 1, 1, 0);
  return r;
}

// A unit direction (normalised in float as the kernels do) whose float dot with itself is above 1:
// the cosines computed from it leave [-1, 1] by one ulp, which the clamps must catch.
glm::vec3 LongUnit() {
  for (int i = 1; i < 100000; ++i) {
    const glm::vec3 v(1.0f, static_cast<float>(i) * 1.0e-3f, 0.5f);
    const float l = std::sqrt((v.x * v.x + v.y * v.y) + v.z * v.z);
    const glm::vec3 d(v.x / l, v.y / l, v.z / l);
    const float dd = (d.x * d.x + d.y * d.y) + d.z * d.z;
    if (dd > 1.0f) return d;
  }
  return glm::vec3(0, 0, 1);  // not reached with IEEE float (the search finds one within a few steps)
}

// v / |v| as the kernels normalise (dot left to right, sqrt, three divisions).
glm::vec3 NormalizeAsKernels(glm::vec3 v) {
  const float l = std::sqrt((v.x * v.x + v.y * v.y) + v.z * v.z);
  return {v.x / l, v.y / l, v.z / l};
}

// Two ray directions that the kernels normalise to unit vectors whose float dot product is above 1
// while they are 1e-5 apart, more than a leaf's loosened cone of one ray (kAngleSlack): the second
// does not grow the leaf's cone (its cosine test passes), and enclosing it clamps a cosine above 1.
std::pair<glm::vec3, glm::vec3> LongPair() {
  for (int i = 1; i < 2000; ++i)
    for (int j = 1; j < 400; ++j) {
      const glm::vec3 v(1.0f, static_cast<float>(i) * 1.0e-3f, 0.5f);
      const glm::vec3 w(1.0f, static_cast<float>(i) * 1.0e-3f + static_cast<float>(j) * 1.0e-6f, 0.5f);
      const glm::vec3 a = NormalizeAsKernels(v), b = NormalizeAsKernels(w);
      const glm::vec3 x(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
      const float sr = std::sqrt((x.x * x.x + x.y * x.y) + x.z * x.z);
      if ((a.x * b.x + a.y * b.y) + a.z * b.z > 1.0f && sr > 2.0f * layout::kAngleSlack) return {v, w};
    }
  return {glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)};  // not reached with IEEE float (i = 1, j = 12 is such a pair)
}

// Leaves over parallel, antiparallel and lone rays, directions with tied largest components, a
// direction slightly longer than 1, and two different directions whose dot is above 1 (and, one
// turned round, below -1).
verify::BufferSet LeavesCall() {
  const glm::vec3 z(0, 0, 1), u = LongUnit();
  const std::pair<glm::vec3, glm::vec3> p = LongPair();
  const float h = 0.70710677f;
  const glm::vec3 d = glm::vec3(1, 2, 3) / std::sqrt(14.0f);
  const std::vector<layout::Ray> rays = {RayAt({0, 0, 0}, z),  RayAt({1, 0, 0}, z),       // parallel
          RayAt({0, 0, 0}, z),  RayAt({0, 1, 0}, -z),      // antiparallel on an axis
          RayAt({2, 2, 2}, z),                             // alone
          RayAt({0, 0, 0}, u),  RayAt({0, 0, 1}, u),       // |u| above 1 in float
          RayAt({0, 0, 0}, d),  RayAt({1, 1, 1}, -d),      // antiparallel off the axes
          RayAt({0, 0, 0}, {h, 0, h}), RayAt({0, 0, 0}, {0, h, h}), RayAt({0, 0, 0}, {h, h, 0}),  // ties
          RayAt({0, 0, 0}, p.first), RayAt({0, 0, 0}, p.second),                                   // dot above 1
          RayAt({0, 0, 0}, p.first), RayAt({0, 0, 0}, -p.second)};                                 // dot below -1
  const std::vector<std::uint32_t> first = {0, 2, 4, 5, 7, 9, 12, 14, 16};
  std::vector<std::uint32_t> order;
  for (std::uint32_t i = 0; i < rays.size(); ++i) order.push_back(i);
  emu::call::BuildLeaves c;
  c.rays = rays;
  c.order = order;
  c.first = first;
  return verify::EncodeCall(c);
}

// Fixed-point channels next to every rounding step of resolve (v = sqrt(c) x 255 + 0.5 truncated):
// a window of accumulator values about each c where v crosses an integer, so that a scale or an
// offset one ulp off changes a byte.
verify::BufferSet ResolveCall() {
  std::vector<std::uint64_t> accum;
  const double scale = 4294967296.0;  // layout::kAccumScale
  for (int k = 1; k <= 255; ++k) {
    const double g = (k - 0.5) / 255.0;
    const auto centre = static_cast<std::int64_t>(g * g * scale);
    for (std::int64_t a = centre - 96; a < centre + 96; ++a) accum.push_back(static_cast<std::uint64_t>(std::max<std::int64_t>(a, 0)));
  }
  for (const std::uint64_t a : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{4294967295u}, std::uint64_t{4294967296u},
                                std::uint64_t{4294967297u}, std::uint64_t{1} << 40})
    accum.push_back(a);
  while (accum.size() % 3 != 0) accum.push_back(0);
  emu::call::Resolve c;
  c.accum = accum;
  return verify::EncodeCall(c);
}

// Four unit triangles side by side in z = 0, whose vertex normals are zero, tiny (1.5 x 2^-75: their
// squared length rounds to 2^-149), huge (a squared length past 3e38) and unit; one glass material
// of index 1 and one of 1.5; a point light above them and one 3e38 away along y.
SceneBuffers CaseScene() {
  SceneBuffers s;
  const float tiny = std::ldexp(1.5f, -75);
  const glm::vec3 normals[4] = {{0, 0, 0}, {0, 0, tiny}, {1e20f, 1e20f, 1e20f}, {0, 0, 1}};
  for (int t = 0; t < 4; ++t) {
    const float x = 2.0f * static_cast<float>(t);
    s.triangles.push_back({vec4(x, 0, 0, 1), vec4(x + 1, 0, 0, 1), vec4(x, 1, 0, 1)});
    const vec4 n(normals[t], 0.0f);
    s.normals.push_back({n, n, n});
    s.info.push_back({glm::uvec4(t == 3 ? 1u : 0u, 0u, 0u, 0u)});
  }
  s.materials = {{vec4(0.5f, 0.5f, 0.5f, 0.0f), vec4(0.2f, 0.2f, 0.2f, 8.0f), vec4(1.0f, 1.0f, 0.0f, 0.0f)},
                 {vec4(0.5f, 0.5f, 0.5f, 0.0f), vec4(0.2f, 0.2f, 0.2f, 8.0f), vec4(0.8f, 1.5f, 0.0f, 0.0f)}};
  for (const glm::vec3 at : {glm::vec3(0, 0, 5), glm::vec3(0, 3e38f, 0)}) {
    layout::Light l{};
    l.position = vec4(at, 0.0f);
    l.color_intensity = vec4(1, 1, 1, 1);
    l.attenuation = vec4(1, 0, 0, 1);
    l.sampling = glm::uvec4(layout::kLightPoint, 1u, static_cast<std::uint32_t>(s.lights.size()), 1u);
    s.lights.push_back(l);
  }
  s.objects = {glm::uvec4(0, 4, 0, 0)};
  s.lo = glm::vec3(0, 0, 0);
  s.hi = glm::vec3(7, 1, 0);
  return s;
}

layout::FrameConstants CaseFrame(const SceneBuffers& s) {
  layout::FrameConstants f{};
  f.view_proj = glm::mat4(1.0f);
  f.eye = vec4(0, 0, 10, 1);
  f.pixel_origin = vec4(0, 0, -1, 0);
  f.pixel_dx = vec4(0.01f, 0, 0, 0);
  f.pixel_dy = vec4(0, 0.01f, 0, 0);
  f.scene_lo = vec4(s.lo, 0);
  f.scene_hi = vec4(s.hi, 0);
  f.params = vec4(1e-3f, 0.01f, 1.0f - std::ldexp(1.0f, -12), 0.0f);
  f.dims = glm::uvec4(4, 1, s.triangles.size(), s.lights.size());
  return f;
}

// One ray down onto each triangle (its interpolated normal zero, tiny, huge, unit) and one miss.
verify::BufferSet SurfacesHitsCall() {
  const SceneBuffers scene = CaseScene();
  std::vector<layout::Ray> rays;
  std::vector<std::uint64_t> hits;
  for (std::uint32_t t = 0; t < 4; ++t) {
    rays.push_back(RayAt({2.0f * static_cast<float>(t) + 0.25f, 0.25f, 1.0f}, {0, 0, -1}));
    rays.back().info.x = t;
    hits.push_back(emu::PackHit(1.0f, t));
  }
  rays.push_back(RayAt({0, 0, 1}, {0, 0, 1}));
  hits.push_back(emu::kMissPacked);
  emu::call::SurfacesFromHits c;
  c.rays = rays;
  c.hits = hits;
  c.scene = &scene;
  return verify::EncodeCall(c);
}

layout::Surface SurfaceAt(glm::vec3 p, glm::vec3 n, glm::vec3 incoming, std::uint32_t prim, std::uint32_t pixel) {
  layout::Surface s{};
  s.position = vec4(p, 1.0f);
  s.normal = vec4(n, 0.0f);
  s.incoming = vec4(incoming, 0.0f);
  s.weight = vec4(1, 1, 1, 0);
  s.info = glm::uvec4(prim, pixel, 0u, 0u);
  return s;
}

// Refraction: a ray grazing the surface of an index-1 glass (Snell's k is exactly 0), one straight
// through, one leaving an index-1.5 glass, an empty slot. Shadow: the same surfaces and two more
// 3e38 from the origin, whose vectors to the far light overflow to infinity in one component.
verify::BufferSet RaygenCall(std::uint32_t kind) {
  const SceneBuffers scene = CaseScene();
  const glm::vec3 up(0, 0, 1);
  std::vector<layout::Surface> surfaces = {SurfaceAt({0.25f, 0.25f, 0}, up, {1, 0, 0}, 0, 0),
                                           SurfaceAt({0.25f, 0.5f, 0}, up, {0, 0, -1}, 0, 1),
                                           SurfaceAt({6.25f, 0.25f, 0}, up, {0.6f, 0, 0.8f}, 3, 2), layout::Surface{}};
  surfaces[2].info.z = 1;
  if (kind == layout::kRayShadow) {
    surfaces.push_back(SurfaceAt({0, -3e38f, 0}, up, {0, 0, -1}, 0, 3));
    surfaces.push_back(SurfaceAt({3e38f, 0, 0}, up, {0, 0, -1}, 0, 3));
  }
  emu::call::Raygen c;
  c.kind = kind;
  c.frame = CaseFrame(scene);
  c.surfaces = surfaces;
  c.scene = &scene;
  return verify::EncodeCall(c);
}

// Three unit triangles, one in each coordinate plane through the origin (x = 0, y = 0, z = 0), as
// the scene of the intersect case.
SceneBuffers AxisPlanesScene() {
  SceneBuffers s;
  s.triangles = {{vec4(0, 0, 0, 1), vec4(0, 1, 0, 1), vec4(0, 0, 1, 1)},
                 {vec4(0, 0, 0, 1), vec4(1, 0, 0, 1), vec4(0, 0, 1, 1)},
                 {vec4(0, 0, 0, 1), vec4(1, 0, 0, 1), vec4(0, 1, 0, 1)}};
  for (int axis = 0; axis < 3; ++axis) {
    vec4 n(0.0f);
    n[axis] = 1.0f;
    s.normals.push_back({n, n, n});
    s.info.push_back({glm::uvec4(0u)});
  }
  s.materials = CaseScene().materials;
  s.objects = {glm::uvec4(0, 3, 0, 0)};
  s.hi = glm::vec3(1, 1, 1);
  return s;
}

// Rays exactly along each axis, both ways, through each plane's triangle (a hit) and through its
// plane beside the triangle (a miss): the two components across the ray are exactly zero, so Woop's
// test must take the ray's own axis as its z (dividing by a zero component gives infinities and NaNs
// that pass the edge tests); all rays of one node against all three triangles.
verify::BufferSet IntersectAxisCall() {
  const SceneBuffers scene = AxisPlanesScene();
  std::vector<layout::Ray> rays;
  for (int axis = 0; axis < 3; ++axis)
    for (const float side : {1.0f, -1.0f})
      for (const float off : {0.25f, 3.0f}) {
        glm::vec3 o(off), d(0.0f);
        o[axis] = side;
        d[axis] = -side;
        rays.push_back(RayAt(o, d));
      }
  std::vector<std::uint32_t> order;
  for (std::uint32_t i = 0; i < rays.size(); ++i) order.push_back(i);
  const std::vector<std::uint32_t> pairs = {0, 1, 2}, first1 = {0, static_cast<std::uint32_t>(rays.size())};
  std::vector<std::uint64_t> hits(rays.size(), emu::kMissPacked);
  emu::call::Intersect c;
  c.pairs = pairs;
  c.first1 = first1;
  c.order = order;
  c.rays = rays;
  c.scene = &scene;
  c.hits = &hits;
  return verify::EncodeCall(c);
}

// A 3 x 3 x 3 lattice of small triangles, one at each integer point of [0, 2]^3.
std::vector<layout::Triangle> LatticeTriangles() {
  std::vector<layout::Triangle> triangles;
  for (int i = 0; i < 27; ++i) {
    const glm::vec3 p(static_cast<float>(i % 3), static_cast<float>(i / 3 % 3), static_cast<float>(i / 9));
    triangles.push_back({vec4(p, 1), vec4(p + glm::vec3(0.3f, 0.1f, 0), 1), vec4(p + glm::vec3(0, 0.3f, 0.2f), 1)});
  }
  return triangles;
}

// Traversal lists (6, one per signed axis) over the lattice of small triangles, walked by
// shadow rays whose largest direction components tie (|z| = |x|, |z| = |y|, all three): the class of
// a tie goes to the lower axis. An any-hit walk stops at its first hit, and each list orders the
// lattice differently, so another list shows in the count of spheres tested before it.
verify::BufferSet TlTraceTiesCall() {
  const std::vector<layout::Triangle> triangles = LatticeTriangles();
  emu::tl::Options options;
  options.lists = 6;
  const emu::tl::Lists lists = emu::tl::Build(triangles, options);
  std::vector<layout::Ray> rays;
  const float h = 0.70710677f, t = 0.57735026f;
  for (const glm::vec3 d : {glm::vec3(h, 0, h), glm::vec3(-h, 0, -h), glm::vec3(0, h, h), glm::vec3(0, -h, h),
                            glm::vec3(t, t, t), glm::vec3(-t, t, -t)})
    for (const glm::vec3 o : {glm::vec3(-1, 0.05f, -1), glm::vec3(-1, 1.05f, -1), glm::vec3(3, 2.05f, 3),
                              glm::vec3(1.05f, -1, -1), glm::vec3(-1, -1, -1)})
      rays.push_back(RayAt(o, d));
  for (layout::Ray& r : rays) r.info.y = layout::kNoPrim;
  emu::call::TlTrace c;
  c.first = lists.first;
  c.escapes = lists.escapes;
  c.words = lists.words;
  c.vertices = lists.vertices;
  c.rays = rays;
  c.shadow = 1;
  return verify::EncodeCall(c);
}

// A tl.heads call (regular heads) over the triangles' earliest-first lists, `count` of them.
verify::BufferSet TlHeadsCall(const std::vector<layout::Triangle>& triangles, std::uint32_t count, float margin) {
  const emu::tl::Options options;
  const emu::tl::Tree tree = emu::tl::PrepareTree(triangles, options.tree);
  const std::vector<vec4> directions = emu::tl::Directions(count);
  emu::tl::Lists lists = emu::tl::Assemble(
      tree, count, emu::PassTlLists({.tree = tree.View(), .directions = directions, .order = layout::kTlOrderEarliestFirst}), false);
  emu::call::TlHeads c;
  c.first = lists.first;
  c.escapes = lists.escapes;
  c.words = lists.words;
  c.vertices = lists.vertices;
  c.tri_words = tree.tri_words;
  c.mode = layout::kTlHeadsRegular;
  c.margin = margin;
  return verify::EncodeCall(c);
}

// Per-polygon heads over the lattice and three slivers (triangles whose normal is short against their
// edges: their float plane cannot bound a window, so they walk whole lists) lying across it.
verify::BufferSet TlHeadsSliversCall() {
  std::vector<layout::Triangle> triangles = LatticeTriangles();
  for (const float y : {0.5f, 1.5f})
    triangles.push_back({vec4(-0.5f, y, -0.5f, 1), vec4(2.5f, y, 2.5f, 1), vec4(1.0f, y + 1e-3f, 1.0f, 1)});
  triangles.push_back({vec4(0, 0, 2.5f, 1), vec4(2.5f, 2.5f, 2.5f, 1), vec4(1.25f, 1.25f, 2.5f + 1e-3f, 1)});
  const std::vector<glm::vec3> lights = {glm::vec3(1, 5, 1)};
  return TlHeadsCall(triangles, 6, emu::tl::HeadsMargin(glm::vec3(-0.5f), glm::vec3(2.5f, 3.0f, 2.6f), lights));
}

// Per-polygon heads (regular, 8 lists) where triangles touch a facet's margin exactly. The margin
// is 2^-8 and the first triangle spans x in [0, 1], so for a list whose class has the facet normal
// (1, 0, 0) its starting rays' bound is 0 - 2^-8, and a vertex's side of it is its x, both exact.
// In front of that triangle lie three others, each with one vertex exactly on the bound (x = -2^-8)
// and two past it (x <= -0.5), one triangle per vertex position: touching the margin keeps a
// triangle, and each of the three is the first triangle kept by one window, so a rejection moved
// onto the boundary at any vertex moves a head or a tail.
verify::BufferSet TlHeadsTouchingCall() {
  std::vector<layout::Triangle> triangles = {{vec4(0, 0, 0, 1), vec4(0, 0, 1, 1), vec4(1, 0, 0, 1)}};
  for (int at = 0; at < 3; ++at) {
    const float y = 0.5f * static_cast<float>(at + 1);
    glm::vec3 v[3] = {{-1.0f, y, 0.0f}, {-1.0f, y + 0.25f, 1.0f}, {-0.5f, y + 0.125f, 0.5f}};
    v[at].x = -0x1p-8f;
    triangles.push_back({vec4(v[0], 1), vec4(v[1], 1), vec4(v[2], 1)});
  }
  // The scene and its light lie within [-4, 4]^3: the margin is 4 x 2^-10.
  const std::vector<glm::vec3> lights = {glm::vec3(0, 4, 0)};
  return TlHeadsCall(triangles, 8, emu::tl::HeadsMargin(glm::vec3(-4), glm::vec3(4), lights));
}

// Walks through a regular grid of 2 x 2 x 2 cells over [0, 2]^3, every cell listing three walls, of
// rays with zero direction components: along each axis and in the coordinate planes, from inside the
// box, from outside it along the moving axis, outside a slab they do not move across, and exactly on
// a slab's faces (no quotient of a zero component is taken: emu grid::BoxClip).
verify::BufferSet GridAxisRaysCall() {
  emu::call::GridTrace c;
  std::vector<layout::Triangle> triangles = {{vec4(1.5f, -1, -1, 1), vec4(1.5f, 3, -1, 1), vec4(1.5f, 1, 3, 1)},
                                             {vec4(-1, 0.25f, -1, 1), vec4(3, 0.25f, -1, 1), vec4(1, 0.25f, 3, 1)},
                                             {vec4(-1, -1, 1.25f, 1), vec4(3, -1, 1.25f, 1), vec4(1, 3, 1.25f, 1)}};
  std::vector<std::uint32_t> first, cell_triangles;
  for (std::uint32_t cell = 0; cell <= 8; ++cell) first.push_back(3 * cell);
  for (std::uint32_t cell = 0; cell < 8; ++cell)
    for (std::uint32_t t = 0; t < 3; ++t) cell_triangles.push_back(t);
  const float h = 0.70710677f;
  std::vector<layout::Ray> rays;
  for (const glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1),
                            glm::vec3(0, 0, -1), glm::vec3(h, h, 0), glm::vec3(0, -h, h), glm::vec3(-h, 0, -h)})
    for (const glm::vec3 o : {glm::vec3(0.5f, 0.5f, 0.5f), glm::vec3(-1.0f, 0.75f, 0.5f), glm::vec3(0.5f, 3.0f, 0.5f),
                              glm::vec3(2.0f, 2.0f, 0.0f), glm::vec3(0.0f, 1.0f, 2.0f), glm::vec3(1.0f, 1.0f, 1.0f)})
      rays.push_back(RayAt(o, d));
  c.first = first;
  c.cell_triangles = cell_triangles;
  const std::vector<vec4> volume = {vec4(0.0f), vec4(1.0f), vec4(1.0f), vec4(2.0f)};  // lo, cell, 1 / cell, hi
  const std::vector<glm::uvec4> dims = {glm::uvec4(2, 2, 2, 0)};
  c.volume = volume;
  c.volume_dims = dims;
  c.triangles = triangles;
  c.rays = rays;
  return verify::EncodeCall(c);
}

}  // namespace

std::vector<KernelCase> KernelCases() {
  return {
      {"build-parents-boundaries", "build", "build.parents",
       "children whose cone union has sine 0, opposite axes, a full child, a negative sine, a sine of 2^-149",
       ParentsCall(layout::kChildMergeSequential)},
      {"build-parents-boundaries-pairwise", "build", "build.parents", "the same children merged pairwise",
       ParentsCall(layout::kChildMergePairwise)},
      {"build-leaves-boundaries", "build", "build.leaves",
       "parallel, antiparallel and lone rays, tied direction components, a direction whose float length exceeds 1, "
       "two different directions whose float dot exceeds 1 (and one turned round)",
       LeavesCall()},
      {"resolve-rounding", "resolve", "resolve", "accumulator values about every step of the 8-bit rounding",
       ResolveCall()},
      {"surfaces-hits-normals", "surfaces.hits", "surfaces.hits",
       "hits on triangles whose vertex normals are zero, of squared length 2^-149, past 3e38, and unit; a miss",
       SurfacesHitsCall()},
      {"raygen-refraction-grazing", "raygen.refraction", "raygen",
       "a ray grazing an index-1 glass (Snell's k exactly 0), one straight through, one leaving index 1.5, an empty slot",
       RaygenCall(layout::kRayRefraction)},
      {"raygen-shadow-far", "raygen.shadow", "raygen",
       "shadow rays from a light 3e38 away to surfaces 3e38 away: light vectors with one infinite component",
       RaygenCall(layout::kRayShadow)},
      {"intersect-axis-rays", "intersect", "intersect",
       "rays exactly along each axis through triangles in the planes across them, inside and beside each triangle",
       IntersectAxisCall()},
      {"tl-trace-ties", "tl.trace", "tl.trace",
       "shadow rays whose largest direction components tie (|z| = |x|, |z| = |y|, all three) walking 6 lists over a lattice",
       TlTraceTiesCall()},
      {"grid-trace-axis-rays", "grid.trace", "grid.trace",
       "regular-grid walks of rays with zero direction components, inside the box, outside a slab they do not cross, on its faces",
       GridAxisRaysCall()},
      {"tl-heads-slivers", "tl.heads", "tl.heads",
       "per-polygon heads of sliver triangles (normal short against the edges: whole lists) across a lattice",
       TlHeadsSliversCall()},
      {"tl-heads-touching", "tl.heads", "tl.heads",
       "per-polygon heads (regular, 8 lists) of triangles with one vertex exactly on a facet's bound less the margin, the others past it",
       TlHeadsTouchingCall()},
  };
}

}  // namespace rayspace::mutate
