// Per-polygon heads of the traversal lists (`--polygon-heads simple|regular`, rayspace/emu/tl/heads.h):
// every element a window leaves out lies, in exact arithmetic, beyond a plane its rays cannot cross;
// walks over the windows give brute force's hits for rays leaving and reaching triangles, and a
// window of the wrong side is caught; a hand-worked window; the same bits on every schedule; calls
// that break the contract are refused.
#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <random>
#include <string>

#include <doctest/doctest.h>

#include "rayspace/contract.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "test_util.h"
#include "tl_util.h"

namespace tl = rayspace::emu::tl;
namespace layout = rayspace::layout;
using rayspace::emu::kMissPacked;
using rayspace::emu::PackHit;
using rayspace::emu::TlWindows;
using rayspace::test::MakeSegment;
using rayspace::test::MakeTriangle;
using layout::Ray;
using layout::Triangle;

namespace {

// Small triangles in [-1, 1]^3 with a few large ones, plus a floor: rays leaving one triangle have
// others on both sides and along every axis.
std::vector<Triangle> Soup(std::uint32_t n, std::uint32_t seed) {
  std::vector<Triangle> t = rayspace::test::TlSoup(n, seed, 13, 0.5f, 0.08f);
  t.push_back(MakeTriangle({-2, -1.2f, -2}, {2, -1.2f, -2}, {0, -1.2f, 3}));
  return t;
}

struct Prepared {
  tl::Tree tree;
  tl::Lists lists;
  float margin = 0.0f;
};
Prepared Prepare(const std::vector<Triangle>& tris, std::uint32_t k) {
  Prepared p;
  tl::Options o;
  o.lists = k;
  p.tree = tl::PrepareTree(tris, o.tree);
  p.lists = tl::Build(tris, o);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const Triangle& t : tris)
    for (const glm::vec4& v : {t.v0, t.v1, t.v2}) lo = glm::min(lo, glm::vec3(v)), hi = glm::max(hi, glm::vec3(v));
  const std::vector<glm::vec3> lights{{0.3f, 3.0f, 0.2f}};
  p.margin = tl::HeadsMargin(lo, hi, lights);
  return p;
}

// Six lists over a hand-made scene, one leaf per triangle, a margin of 0.01.
Prepared HandPrepared(const std::vector<Triangle>& tris) {
  Prepared p;
  tl::Options o;
  o.lists = 6;
  o.tree.leaf_triangles = 1;
  p.tree = tl::PrepareTree(tris, o.tree);
  p.lists = tl::Build(tris, o);
  p.margin = 0.01f;
  return p;
}

TlWindows Windows(const Prepared& p, std::uint32_t mode) {
  return rayspace::emu::PassTlHeads({.first = p.lists.first,
                                     .escapes = p.lists.escapes,
                                     .words = p.lists.words,
                                     .vertices = p.lists.vertices,
                                     .tri_words = p.tree.tri_words,
                                     .mode = mode,
                                     .margin = p.margin});
}

tl::ListsView View(const Prepared& p, std::uint32_t mode, const TlWindows& w) {
  return {p.lists.first, p.lists.escapes, p.lists.words, p.lists.vertices, false, mode, p.tree.tri_words, w.windows};
}

glm::dvec3 D(const glm::vec4& v) { return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)}; }

// Independently of the pass's float tests: does triangle element (a, b, c) lie strictly beyond a plane
// of (triangle t, case, list k) in exact arithmetic (doubles hold these products of floats exactly
// enough: the decisions below have the pass's margin of 2^-10 of the scene to spare)?
bool BeyondExactly(const std::vector<glm::vec4>& verts, const tl::Word& t, std::uint32_t cs, std::uint32_t K, std::uint32_t k,
                   std::uint32_t mode, const tl::Word& e) {
  const glm::dvec3 v0 = D(verts[t.x]), v1 = D(verts[t.y]), v2 = D(verts[t.z]);
  const glm::dvec3 n = glm::cross(v1 - v0, v2 - v0);
  const double side = (cs & 1u) ? -1.0 : 1.0;
  const glm::dvec3 x[3] = {D(verts[e.x]), D(verts[e.y]), D(verts[e.z])};
  if (std::all_of(x, x + 3, [&](const glm::dvec3& q) { return side * glm::dot(n, q - v0) < 0.0; })) return true;
  if (mode != layout::kTlHeadsRegular) return false;
  glm::vec3 m[4];
  const std::uint32_t facets = tl::Facets(K, k, m);
  const bool ends = (cs & 2u) != 0;
  for (std::uint32_t j = 0; j < facets; ++j) {
    const glm::dvec3 mj(m[j]);
    const double a = glm::dot(mj, v0), b = glm::dot(mj, v1), c = glm::dot(mj, v2);
    const double bound = ends ? std::max({a, b, c}) : std::min({a, b, c});
    if (std::all_of(x, x + 3, [&](const glm::dvec3& q) { return ends ? glm::dot(mj, q) > bound : glm::dot(mj, q) < bound; }))
      return true;
  }
  return false;
}

// A ray that leaves triangle t (closest hit) or reaches it from a light (any hit), as the frame's
// reflection and shadow rays do.
Ray Leaving(const std::vector<Triangle>& tris, std::uint32_t t, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  const Triangle& tri = tris[t];
  const float a = w(rng), b = w(rng) * (1.0f - a);
  const glm::vec3 p = glm::vec3(tri.v0) + a * (glm::vec3(tri.v1) - glm::vec3(tri.v0)) + b * (glm::vec3(tri.v2) - glm::vec3(tri.v0));
  const glm::vec3 d(u(rng), u(rng), u(rng));
  return MakeSegment(p, d, 1e-4f, INFINITY, t);
}
Ray Reaching(const std::vector<Triangle>& tris, std::uint32_t t, std::mt19937& rng) {
  Ray r = Leaving(tris, t, rng);
  std::uniform_real_distribution<float> u(-3.0f, 3.0f);
  const glm::vec3 light(u(rng), u(rng), u(rng)), p(r.origin_tmin);
  return MakeSegment(light, p - light, 0.0f, 0.999f, t);
}

std::uint64_t Brute(const std::vector<Triangle>& tris, const Ray& ray) { return rayspace::test::BruteClosest(tris, ray); }

struct WalkCheck {
  std::size_t rays = 0, wrong = 0, windowed = 0;
  std::uint64_t elements = 0;
};
// Walks rays leaving and reaching every triangle with windows `w` (mode) and compares with brute force.
WalkCheck CheckWalks(const std::vector<Triangle>& tris, const Prepared& p, std::uint32_t mode, const TlWindows& w, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const tl::ListsView view = View(p, mode, w);
  WalkCheck c;
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      for (const bool any : {false, true}) {
        const Ray r = any ? Reaching(tris, t, rng) : Leaving(tris, t, rng);
        tl::Stats s;
        const std::uint64_t got = tl::Walk(view, r, any, &s), want = Brute(tris, r);
        c.wrong += any ? (got != kMissPacked) != (want != kMissPacked) : got != want;
        c.elements += s.spheres + s.triangles;
        c.windowed += mode != layout::kTlHeadsOff && tl::RayCase(view, p.tree.tri_words, r, any, tl::ListFor(p.lists.count, glm::vec3(r.direction_tmax))) != tl::kNoCase;
        ++c.rays;
      }
    }
  return c;
}

}  // namespace

TEST_CASE("tl.heads: every element outside a window lies beyond one of its planes, exactly") {
  const std::vector<Triangle> tris = Soup(150, 21);
  for (const std::uint32_t K : {1u, 2u, 6u, 8u})
    for (const std::uint32_t mode : {layout::kTlHeadsSimple, layout::kTlHeadsRegular}) {
      const Prepared p = Prepare(tris, K);
      const TlWindows w = Windows(p, mode);
      REQUIRE(rayspace::emu::WindowsError(p.lists.first, w.windows, tris.size() * layout::kTlCases).empty());
      std::size_t outside = 0, unsafe = 0;
      for (std::uint32_t t = 0; t < tris.size(); ++t)
        for (std::uint32_t cs = 0; cs < layout::kTlCases; ++cs)
          for (std::uint32_t k = 0; k < K; ++k) {
            const std::size_t g = 2 * ((std::size_t{t} * layout::kTlCases + cs) * K + k);
            for (std::uint32_t i = p.lists.first[k]; i < p.lists.first[k + 1]; ++i) {
              if (i >= w.windows[g] && i < w.windows[g + 1]) continue;
              if (!tl::IsTriangle(static_cast<tl::Escape>(p.lists.escapes[i]))) continue;
              ++outside;
              unsafe += !BeyondExactly(p.lists.vertices, p.tree.tri_words[t], cs, K, k, mode, p.lists.words[i]);
            }
          }
      CAPTURE(K);
      CAPTURE(mode);
      CHECK(unsafe == 0);
      // The windows do leave elements out (else this test would hold vacuously).
      CHECK(outside > tris.size() * K);
    }
}

TEST_CASE("tl.heads: walks over the windows give brute force's hits, and a window of the wrong side is caught") {
  const std::vector<Triangle> tris = Soup(200, 5);
  for (const std::uint32_t K : {1u, 2u, 6u, 8u}) {
    const Prepared p = Prepare(tris, K);
    const WalkCheck off = CheckWalks(tris, p, layout::kTlHeadsOff, {}, 77);
    const TlWindows simple = Windows(p, layout::kTlHeadsSimple), regular = Windows(p, layout::kTlHeadsRegular);
    const WalkCheck s = CheckWalks(tris, p, layout::kTlHeadsSimple, simple, 77);
    const WalkCheck r = CheckWalks(tris, p, layout::kTlHeadsRegular, regular, 77);
    CAPTURE(K);
    CHECK(off.wrong == 0);
    CHECK(s.wrong == 0);
    CHECK(r.wrong == 0);
    // Most rays take a window, and the windows shorten the walks: regular at most simple, both below off.
    CHECK(r.windowed * 10 > r.rays * 9);
    CHECK(s.elements < off.elements);
    CHECK(r.elements <= s.elements);
    if (K > 1) CHECK(r.elements < s.elements);

    // Planted: each triangle's windows of its two sides swapped (the kernel's tl.trace fault 5):
    // rays then skip what lies in front of them.
    TlWindows swapped = regular;
    for (std::size_t t = 0; t < tris.size(); ++t)
      for (std::uint32_t ends = 0; ends < 2; ++ends)
        for (std::uint32_t k = 0; k < K; ++k) {
          const std::size_t a = 2 * ((t * layout::kTlCases + 2 * ends) * K + k), b = 2 * ((t * layout::kTlCases + 2 * ends + 1) * K + k);
          std::swap(swapped.windows[a], swapped.windows[b]);
          std::swap(swapped.windows[a + 1], swapped.windows[b + 1]);
        }
    CHECK(CheckWalks(tris, p, layout::kTlHeadsRegular, swapped, 77).wrong > 0);
  }
}

TEST_CASE("tl.heads: every facet plane of a class holds every direction of the class") {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 20000; ++i) {
    glm::vec3 d(u(rng), u(rng), u(rng));
    if (i % 7 == 0) d[i % 3] = 0.0f;  // zero components count as positive
    if (i % 11 == 0) d[(i + 1) % 3] = d[i % 3];  // ties between axes
    for (const std::uint32_t K : {1u, 2u, 6u, 8u}) {
      glm::vec3 m[4];
      const std::uint32_t n = tl::Facets(K, tl::ListFor(K, d), m);
      CHECK(n == (K == 1 ? 0u : K == 2 ? 1u : K == 6 ? 4u : 3u));
      for (std::uint32_t j = 0; j < n; ++j) REQUIRE(glm::dot(glm::dvec3(m[j]), glm::dvec3(d)) >= 0.0);
    }
  }
}

TEST_CASE("tl.heads: a ray whose point lies outside its triangle walks the whole list under regular heads") {
  // T0 in z = 0 facing +z; X beyond T0's facet x + z >= 0 of the +x sextant (x + z = -0.2 on X) but
  // reachable from (-0.5, 0.5, 0), a point of T0's plane just outside T0 (a G-buffer point may be).
  const std::vector<Triangle> tris = {MakeTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}),
                                      MakeTriangle({-0.3f, 0.4f, 0.05f}, {-0.3f, 0.6f, 0.05f}, {-0.35f, 0.5f, 0.15f}),
                                      MakeTriangle({3, 0, 2}, {4, 0, 2}, {3, 1, 2})};
  const Prepared p = HandPrepared(tris);
  const TlWindows w = Windows(p, layout::kTlHeadsRegular);
  const Ray outside = MakeSegment({-0.5f, 0.5f, 0.0f}, {0.2f, 0.0f, 0.1f}, 1e-4f, INFINITY, 0);
  const Ray inside = MakeSegment({0.2f, 0.2f, 0.0f}, {0.2f, 0.0f, 0.1f}, 1e-4f, INFINITY, 0);
  const tl::ListsView view = View(p, layout::kTlHeadsRegular, w);
  CHECK(tl::RayCase(view, p.tree.tri_words, outside, false, 0) == tl::kNoCase);
  CHECK(tl::RayCase(view, p.tree.tri_words, inside, false, 0) == 0u);
  CHECK(tl::Walk(view, outside, false) == Brute(tris, outside));
  CHECK(rayspace::emu::HitPrim(Brute(tris, outside)) == 1u);
  // The window itself leaves X out: taken from the outside point it would lose the hit.
  const std::size_t g = 2 * ((0 * layout::kTlCases + 0) * 6 + 0);
  bool held = false;
  for (std::uint32_t i = w.windows[g]; i < w.windows[g + 1]; ++i)
    held |= tl::IsTriangle(static_cast<tl::Escape>(p.lists.escapes[i])) && p.lists.words[i].w == 1u;
  CHECK_FALSE(held);
}

TEST_CASE("tl.heads: a hand-worked window") {
  // T0 in z = 0 facing +z ((v1 - v0) x (v2 - v0) = +z); T1 below at z = -4, T2 above at z = 4, T3 at
  // z = 0.5 but far in -x. One leaf per triangle (leaf_triangles = 1).
  const std::vector<Triangle> tris = {MakeTriangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), MakeTriangle({0, 0, -4}, {1, 0, -4}, {0, 1, -4}),
                                      MakeTriangle({0, 0, 4}, {1, 0, 4}, {0, 1, 4}), MakeTriangle({-6, 0, 0.5f}, {-5, 0, 0.5f}, {-6, 1, 0.5f})};
  const Prepared p = HandPrepared(tris);
  auto held = [&](const TlWindows& w, std::uint32_t cs, std::uint32_t k) {
    std::vector<std::uint32_t> prims;
    const std::size_t g = 2 * ((0 * layout::kTlCases + cs) * 6 + k);
    for (std::uint32_t i = w.windows[g]; i < w.windows[g + 1]; ++i)
      if (tl::IsTriangle(static_cast<tl::Escape>(p.lists.escapes[i]))) prims.push_back(p.lists.words[i].w);
    std::sort(prims.begin(), prims.end());
    return prims;
  };
  const TlWindows simple = Windows(p, layout::kTlHeadsSimple), regular = Windows(p, layout::kTlHeadsRegular);
  // The tree: the root R over N3 {T3}, N01 {N1 {T1}, N0 {T0}} (T0's centroid lies on the root's
  // centre plane z = 0 and joins T1's octant) and N2 {T2}. Lists +x (0): R N3 T3 N01 N1 T1 N0 T0 N2
  // T2; -z (5): R N2 T2 N3 T3 N01 N0 T0 N1 T1.
  // Leaving T0 upwards (case 0, list +z): T1 lies behind the plane and heads the list: out.
  CHECK(held(simple, 0, 4) == std::vector<std::uint32_t>{0, 2, 3});
  // Leaving it downwards (case 1, list -z): T2 is above; N3's sphere dips below z = 0, so the head
  // enters it, but T3 itself is above: the window starts at T0.
  CHECK(held(simple, 1, 5) == std::vector<std::uint32_t>{0, 1});
  // Upwards in the +x sextant (list 0), simple: T1 is behind but lies between T3 and T2, which are
  // not, so it stays in (only a list's ends can be cut).
  CHECK(held(simple, 0, 0) == std::vector<std::uint32_t>{0, 1, 2, 3});
  // Regular: the facet x + z >= min(x + z) = 0 over T0 holds T3 out (x + z <= -4.5), x - z >= 0
  // holds T2 out (x - z <= -3: a ray of the class cannot rise 4 over at most 1 of x), and T1 is
  // behind: only T0 is left.
  CHECK(held(regular, 0, 0) == std::vector<std::uint32_t>{0});
  // Reaching T0 from above (case 2: ends, front side, list -z): what lies behind it is out.
  CHECK(held(simple, 2, 5) == std::vector<std::uint32_t>{0, 2, 3});
}

TEST_CASE("tl.heads: a triangle touching a plane's margin is kept, one ulp past it is rejected") {
  // T0 spans x in [0, 1] in y = 0 with normal (0, 1, 0): its reach and a vertex's side (its y) are
  // exact, and so are, in list 0 of 8 (facet normal (1, 0, 0)), its starting bound less the margin
  // (-2^-8) and a vertex's projection (its x). A margin of 2^-8 makes the boundaries exact floats.
  const glm::vec3 v0(0, 0, 0), v1(0, 0, 1), v2(1, 0, 0);
  const float margin = 0x1p-8f, below = std::nextafter(-margin, -1.0f);
  const tl::HeadPlanes plane = tl::MakePlanes(v0, v1, v2, 0, 8, 0, layout::kTlHeadsSimple, margin);
  const tl::HeadPlanes facets = tl::MakePlanes(v0, v1, v2, 0, 8, 0, layout::kTlHeadsRegular, margin);
  for (int at = 0; at < 3; ++at) {
    CAPTURE(at);
    // Behind the plane: two vertices past the reach, one exactly on it, then one ulp past it.
    glm::vec3 v[3] = {{0, -0.5f, 0}, {1, -0.5f, 0}, {0, -0.5f, 1}};
    v[at].y = -margin;
    CHECK_FALSE(tl::TriangleRejected(plane, v[0], v[1], v[2]));
    v[at].y = below;
    CHECK(tl::TriangleRejected(plane, v[0], v[1], v[2]));
    // In front of the plane, beside the facet x >= 0: the same with x.
    glm::vec3 u[3] = {{-1, 0.5f, 0}, {-1, 0.75f, 1}, {-0.5f, 0.6f, 0.5f}};
    u[at].x = -margin;
    CHECK_FALSE(tl::TriangleRejected(facets, u[0], u[1], u[2]));
    u[at].x = below;
    CHECK(tl::TriangleRejected(facets, u[0], u[1], u[2]));
  }
}

TEST_CASE("tl.heads: the same bits on every schedule (threads, chunk sizes)") {
  rayspace::test::TestSettings settings;
  const std::vector<Triangle> tris = Soup(300, 9);
  const Prepared p = Prepare(tris, 6);
  const TlWindows ref = Windows(p, layout::kTlHeadsRegular);
  for (const auto& [threads, chunk] : {std::pair{2, std::size_t{1}}, {3, std::size_t{7}}, {2, std::size_t{1000}}}) {
    settings->threads = threads;
    settings->chunk = chunk;
    const TlWindows w = Windows(p, layout::kTlHeadsRegular);
    settings->threads = 0;
    settings->chunk = 0;
    CAPTURE(threads);
    CHECK(w.windows == ref.windows);
  }
}

using rayspace::test::InputErrorOf;

TEST_CASE("tl.heads: calls whose inputs break the contract are refused, naming the call") {
  const std::vector<Triangle> tris = Soup(60, 3);
  const Prepared p = Prepare(tris, 6);
  auto heads_error = [&](std::uint32_t mode, float margin, std::vector<tl::Word> tri_words) {
    return InputErrorOf([&] {
      rayspace::emu::CheckInputs(rayspace::emu::call::TlHeads{.first = p.lists.first, .escapes = p.lists.escapes, .words = p.lists.words,
                                                              .vertices = p.lists.vertices, .tri_words = tri_words, .mode = mode,
                                                              .margin = margin});
    });
  };
  CHECK(heads_error(layout::kTlHeadsRegular, p.margin, p.tree.tri_words).empty());
  CHECK(heads_error(3, p.margin, p.tree.tri_words).find("tl.heads: mode 3") != std::string::npos);
  CHECK(heads_error(layout::kTlHeadsSimple, NAN, p.tree.tri_words).find("tl.heads: margin") != std::string::npos);
  CHECK(heads_error(layout::kTlHeadsSimple, -1.0f, p.tree.tri_words).find("tl.heads: margin") != std::string::npos);
  std::vector<tl::Word> bad = p.tree.tri_words;
  bad[4].z = static_cast<std::uint32_t>(p.lists.vertices.size());
  CHECK(heads_error(layout::kTlHeadsSimple, p.margin, bad).find("'tri_words' element 4") != std::string::npos);

  TlWindows w = Windows(p, layout::kTlHeadsRegular);
  const std::vector<Ray> rays{MakeSegment({0, 0, 2}, {0, 0, -1}, 0.0f, INFINITY, 3)};
  auto trace_error = [&](std::uint32_t heads, const std::vector<std::uint32_t>& windows) {
    return InputErrorOf([&] {
      rayspace::emu::CheckInputs(rayspace::emu::call::TlTrace{.first = p.lists.first, .escapes = p.lists.escapes, .words = p.lists.words,
                                                              .vertices = p.lists.vertices, .rays = rays, .heads = heads,
                                                              .tri_words = p.tree.tri_words, .windows = windows});
    });
  };
  CHECK(trace_error(layout::kTlHeadsRegular, w.windows).empty());
  std::vector<std::uint32_t> bw = w.windows;
  bw.pop_back();
  CHECK(trace_error(layout::kTlHeadsRegular, bw).find("input 'windows'") != std::string::npos);
  bw = w.windows;
  bw[1] = p.lists.first[1] + 1;  // window 0 (list 0) reaching into list 1
  CHECK(trace_error(layout::kTlHeadsRegular, bw).find("not inside its list") != std::string::npos);
  // Cells: whole cells of K windows each.
  const std::vector<std::uint32_t> cells = {p.lists.first[0], p.lists.first[1], p.lists.first[1], p.lists.first[2], p.lists.first[2],
                                            p.lists.first[3], p.lists.first[3], p.lists.first[4], p.lists.first[4], p.lists.first[5],
                                            p.lists.first[5], p.lists.first[6]};
  CHECK(trace_error(layout::kTlHeadsCells, cells).empty());
  CHECK(trace_error(layout::kTlHeadsCells, std::vector<std::uint32_t>(cells.begin(), cells.end() - 2)).find("whole cells") !=
        std::string::npos);
  CHECK(trace_error(4, cells).find("tl.trace: heads 4") != std::string::npos);
}

// ---- tl.cells: per-cell heads of eye rays (--frustum-cull on) ----------------------------------

namespace {

// A 40 x 24 image (cells of 16: 3 x 2, the last column and row partial) from an eye at z = -3 looking
// along +z, a horizontal field of view of about 60 degrees.
layout::FrameConstants Camera(std::uint32_t w = 40, std::uint32_t h = 24) {
  layout::FrameConstants fc{};
  const float tx = 0.57735f, ty = tx * static_cast<float>(h) / static_cast<float>(w);
  fc.eye = glm::vec4(0.1f, -0.05f, -3.0f, 1.0f);
  fc.pixel_dx = glm::vec4(2.0f * tx / static_cast<float>(w), 0.0f, 0.0f, 0.0f);
  fc.pixel_dy = glm::vec4(0.0f, -2.0f * ty / static_cast<float>(h), 0.0f, 0.0f);
  fc.pixel_origin = glm::vec4(-tx + 0.5f * fc.pixel_dx.x, ty + 0.5f * fc.pixel_dy.y, 1.0f, 0.0f);
  fc.dims = glm::uvec4(w, h, 0u, 0u);
  return fc;
}

TlWindows Cells(const Prepared& p, const layout::FrameConstants& fc) {
  return rayspace::emu::PassTlCells(
      {.first = p.lists.first, .escapes = p.lists.escapes, .words = p.lists.words, .vertices = p.lists.vertices, .frame = fc, .margin = p.margin});
}

}  // namespace

TEST_CASE("tl.cells: eye rays over their cells' windows give brute force's hits, and nothing outside is hit") {
  const std::vector<Triangle> tris = Soup(250, 31);
  const layout::FrameConstants fc = Camera();
  const std::vector<Ray> rays = tl::EyeRays(fc);
  REQUIRE(rays.size() == 40u * 24u);
  CHECK(tl::CellCount(fc) == 6u);
  CHECK(rays[39].info.w == 2u);        // pixel (39, 0): the third cell of the first row
  CHECK(rays[16 * 40 + 17].info.w == 4u);  // pixel (17, 16): the second cell of the second row
  for (const std::uint32_t K : {1u, 6u, 8u}) {
    const Prepared p = Prepare(tris, K);
    const TlWindows w = Cells(p, fc);
    REQUIRE(rayspace::emu::WindowsError(p.lists.first, w.windows, tl::CellCount(fc)).empty());
    const tl::ListsView cells{p.lists.first, p.lists.escapes, p.lists.words, p.lists.vertices, false, layout::kTlHeadsCells, {}, w.windows};
    const tl::ListsView whole{p.lists.first, p.lists.escapes, p.lists.words, p.lists.vertices};
    std::size_t wrong = 0, hits = 0, outside_hit = 0, outside = 0;
    std::uint64_t with = 0, without = 0;
    for (const Ray& r : rays) {
      tl::Stats a, b;
      const std::uint64_t got = tl::Walk(cells, r, false, &a), want = Brute(tris, r);
      tl::Walk(whole, r, false, &b);
      wrong += got != want;
      hits += want != kMissPacked;
      with += a.spheres + a.triangles;
      without += b.spheres + b.triangles;
      // Every triangle of the ray's list outside its cell's window: the ray does not meet it.
      const std::uint32_t k = tl::ListFor(K, glm::vec3(r.direction_tmax));
      const std::size_t g = 2 * (std::size_t{r.info.w} * K + k);
      const rayspace::emu::WatertightRay wr = rayspace::emu::SetupWatertight(glm::vec3(r.origin_tmin), glm::vec3(r.direction_tmax));
      for (std::uint32_t i = p.lists.first[k]; i < p.lists.first[k + 1]; ++i) {
        if ((i >= w.windows[g] && i < w.windows[g + 1]) || !tl::IsTriangle(static_cast<tl::Escape>(p.lists.escapes[i]))) continue;
        const tl::Word& e = p.lists.words[i];
        float t;
        ++outside;
        outside_hit += rayspace::emu::IntersectWatertight(wr, glm::vec3(p.lists.vertices[e.x]), glm::vec3(p.lists.vertices[e.y]),
                                                          glm::vec3(p.lists.vertices[e.z]), 0.0f, INFINITY, t);
      }
    }
    CAPTURE(K);
    CHECK(wrong == 0);
    CHECK(outside_hit == 0);
    CHECK(hits > rays.size() / 4);     // most pixels see a triangle: agreeing on misses proves little
    CHECK(outside > rays.size() * 10);  // the windows leave triangles out
    CHECK(with < without);
  }
}

TEST_CASE("tl.cells: a cell's planes face its own rays; flipped, they lose hits") {
  const std::vector<Triangle> tris = Soup(250, 31);
  const layout::FrameConstants fc = Camera();
  const Prepared p = Prepare(tris, 6);
  // Every eye ray lies inside its cell's four planes (n . d >= 0 up to rounding)...
  for (const Ray& r : tl::EyeRays(fc)) {
    const tl::CellPlanes c = tl::MakeCellPlanes(fc, r.info.w, p.margin);
    for (std::uint32_t j = 0; j < 4; ++j)
      REQUIRE(glm::dot(glm::dvec3(c.n[j]), glm::dvec3(glm::vec3(r.direction_tmax))) >= -1e-6 * glm::length(glm::dvec3(c.n[j])));
  }
  // ... and the windows of another cell (each ray walking the next cell's: the kernel's tl.trace
  // fault 6) lose hits.
  const TlWindows w = Cells(p, fc);
  std::vector<std::uint32_t> shifted(w.windows.begin() + 2 * 6, w.windows.end());
  shifted.insert(shifted.end(), w.windows.begin(), w.windows.begin() + 2 * 6);
  const tl::ListsView view{p.lists.first, p.lists.escapes, p.lists.words, p.lists.vertices, false, layout::kTlHeadsCells, {}, shifted};
  std::size_t wrong = 0;
  for (const Ray& r : tl::EyeRays(fc)) wrong += tl::Walk(view, r, false) != Brute(tris, r);
  CHECK(wrong > 0);
}

TEST_CASE("tl.cells: the same bits on every schedule, and calls that break the contract are refused") {
  rayspace::test::TestSettings settings;
  const std::vector<Triangle> tris = Soup(200, 8);
  const layout::FrameConstants fc = Camera(70, 33);
  const Prepared p = Prepare(tris, 8);
  const TlWindows ref = Cells(p, fc);
  for (const auto& [threads, chunk] : {std::pair{2, std::size_t{1}}, {3, std::size_t{5}}}) {
    settings->threads = threads;
    settings->chunk = chunk;
    const TlWindows w = Cells(p, fc);
    settings->threads = 0;
    settings->chunk = 0;
    CHECK(w.windows == ref.windows);
  }
  auto error = [&](layout::FrameConstants f, float margin) {
    return InputErrorOf([&] {
      rayspace::emu::CheckInputs(rayspace::emu::call::TlCells{.first = p.lists.first, .escapes = p.lists.escapes, .words = p.lists.words,
                                                              .vertices = p.lists.vertices, .frame = f, .margin = margin});
    });
  };
  CHECK(error(fc, p.margin).empty());
  CHECK(error(fc, NAN).find("tl.cells: margin") != std::string::npos);
  layout::FrameConstants bad = fc;
  bad.dims.x = 0;
  CHECK(error(bad, p.margin).find("tl.cells: frame size 0x33") != std::string::npos);
  bad = fc;
  bad.pixel_dx.y = INFINITY;
  CHECK(error(bad, p.margin).find("not finite") != std::string::npos);
}
