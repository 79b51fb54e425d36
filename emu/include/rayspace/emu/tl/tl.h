// Stackless traversal lists over a bounding-sphere hierarchy (Toczek, Houzet, Mancini 2010;
// docs/traversal-lists.md): the object tree's build (rayspace/object_tree.h, the paper's section 2.2)
// over the whole scene, flattened depth first into K lists, each with its nodes ordered along one
// direction, and walked without a stack by following escapes. The tree is built on the host; the lists
// are the pass tl.lists and the walk the pass tl.trace (emulated here, gpu/shaders/tl_*.comp).
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/tl/layout.h"
#include "rayspace/layout.h"
#include "rayspace/object_tree.h"

namespace rayspace::emu::tl {

// How a node's children are ordered along a list's direction, by the projection [lo, hi] of each
// child (sphere or triangle) on it: earliest first by ascending lo, latest last by ascending hi.
// Ties keep the tree's order (own triangles in input order, then child nodes in octant order).
enum class Order : std::uint32_t { kEarliestFirst = layout::kTlOrderEarliestFirst, kLatestLast = layout::kTlOrderLatestLast };

struct Options {
  // 1: one list along +x; 2: +x and -x; 6: +-x, +-y, +-z (the paper's sextants); 8: the diagonals
  // (+-1, +-1, +-1) (its octants).
  std::uint32_t lists = 6;
  Order order = Order::kEarliestFirst;
  // The object tree's build, with a triangle "big" only at 0.7 of its node's radius (the object tree's
  // own default is 0.25): measured on the bundled scenes (docs/traversal-lists.md), 0.7 visits the
  // fewest elements per ray; 0.25 keeps up to 3x more triangles high in the lists, and from 0.9 on
  // Sponza's large floor triangles inflate the octant spheres below them.
  ObjectTreeOptions tree{.big_fraction = kBigFraction};
  static constexpr float kBigFraction = 0.7f;
  // Back-face culling: one-sided triangles (a ray meets a triangle only from the side its normal
  // (v1 - v0) x (v2 - v0) points to), and each list drops the triangles every ray of its class meets
  // from behind (Culled). Off by default: the scene's triangles are two-sided for every other tracer.
  bool cull = false;
  // Per-polygon heads (layout::kTlHeads*): off, simple (the triangle's plane) or regular (and the
  // facet planes of the list's class). Off by default.
  std::uint32_t heads = 0;
  // Per-cell heads of eye rays (--frustum-cull on, with --primary tl): the pass tl.cells, and eye
  // rays walking their cell's window.
  bool cells = false;
};

// The host's half: the tree (BuildObjectTree over the scene as one object), each node's parent and
// subtree size, and the shared vertex array with every triangle's word. The view is what tl.lists
// reads; it points into this struct.
struct Tree {
  std::vector<glm::uvec4> links;
  std::vector<glm::vec4> spheres;
  std::vector<std::uint32_t> parents, sizes, roots, triangles, owners;
  std::vector<Word> tri_words;
  std::vector<Vertex> vertices;
  TlTreeView View() const;
};
Tree PrepareTree(std::span<const layout::Triangle> triangles, const ObjectTreeOptions& options = {});

// The lists' ordering directions: +x; +x, -x; +-x, +-y, +-z; the eight (+-1, +-1, +-1) / sqrt 3.
std::vector<glm::vec4> Directions(std::uint32_t k);

// K lists over one vertex array. List k holds the elements [first[k], first[k + 1]); escapes are
// relative, so a list is walked the same wherever it lies.
struct Lists {
  std::uint32_t count = 0;                // K
  std::vector<std::uint32_t> first;       // K + 1 offsets
  std::vector<std::uint32_t> escapes;     // per element: the bits of its Escape
  std::vector<Word> words;                // per element
  std::vector<Vertex> vertices;           // shared: distinct positions in first-use order
  std::vector<glm::vec3> directions;      // per list: its unit ordering direction
  bool one_sided = false;                 // built with back-face culling: walks meet fronts only
  std::uint64_t Bytes() const;            // escapes, words, vertices and offsets
};

bool ValidListCount(std::uint32_t k);

// Deterministic: the same triangles and options give the same bytes. The tree from PrepareTree, the
// lists from the emulated tl.lists.
Lists Build(std::span<const layout::Triangle> triangles, const Options& options = {});
// The lists of a prepared tree from tl.lists' output (what Build does after the pass): each list's
// elements moved together, list k after list k - 1.
Lists Assemble(const Tree& tree, std::uint32_t count, TlListArrays arrays, bool one_sided);
// tl.lists' slots of `slot` elements packed the same way: the K + 1 offsets, escapes and words.
// Throws InputError naming `what` when a length exceeds its slot or the arrays are short.
struct Packed {
  std::vector<std::uint32_t> first, escapes;
  std::vector<Word> words;
};
Packed Pack(const TlListArrays& arrays, std::size_t slot, std::string_view what);

// Back-face culling's test (rayspace/contract.h, kTlCullMargin), as tl.lists computes it in float:
// may list k of `count` drop the triangle, because every direction of its class sees the back
// (g . n >= 0 at every corner g of the class, with a margin that covers n's rounding)? The classes
// of 1 and 2 lists hold directions along the triangle's plane for every normal: nothing is dropped.
bool Culled(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, std::uint32_t count, std::uint32_t k);

// The list a ray of direction `dir` walks: the one whose class holds it (sign of x; dominant axis
// and its sign, ties to the lower axis; the signs of x, y, z). Zero components count as positive.
std::uint32_t ListFor(std::uint32_t count, glm::vec3 dir);

struct Stats {
  std::uint64_t spheres = 0;    // sphere elements tested
  std::uint64_t triangles = 0;  // triangle elements tested (the ignored primitive included)
  // List entries the walk passed, tested or skipped by an escape: from where it began to where it
  // stopped (the list's or window's end, or the element whose hit ended an any-hit walk).
  std::uint64_t entries = 0;
};

// The closest hit as emu::PackHit (kMissPacked for none), the same as testing every triangle with
// IntersectWatertight over (tmin, tmax) and ignoring ray.info.y: nearest t, ties to the lower id.
std::uint64_t Closest(const Lists& lists, const layout::Ray& ray, Stats* stats = nullptr);
// Whether any triangle but ray.info.y is hit in (tmin, tmax); stops at the first.
bool Any(const Lists& lists, const layout::Ray& ray, Stats* stats = nullptr);

// The arrays a walk reads (tl.trace's inputs); a Lists or a call's spans.
struct ListsView {
  std::span<const std::uint32_t> first, escapes;
  std::span<const Word> words;
  std::span<const Vertex> vertices;
  bool one_sided = false;  // a triangle counts only when met from its front (IntersectWatertight's det > 0)
  // Per-polygon windows (heads != kTlHeadsOff): tl.heads' windows and the scene triangles' words.
  std::uint32_t heads = 0;
  std::span<const Word> tri_words{};
  std::span<const std::uint32_t> windows{};
};
// Why the arrays are not lists a walk can follow safely, or "" (K in {1, 2, 6, 8}; each list's
// escapes 1, 0 (the last element only), at least 2 or -1 (a sphere, never last) and within the list;
// a triangle's vertex indices in range). `bad` receives the first bad element.
std::string ListsError(const ListsView& lists, std::size_t* bad = nullptr);
// A sphere test of SphereMayHit's signature: the walk's, or another one `rayspace accuracy` measures.
using SphereTest = bool (*)(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 sphere);

// One ray's walk: its packed closest hit (any = false) or, with any = true, kMissPacked when it is
// not occluded and some hit otherwise.
std::uint64_t Walk(const ListsView& lists, const layout::Ray& ray, bool any, Stats* stats = nullptr, SphereTest test = nullptr);

// May the ray's part [tmin, tlimit] meet the sphere? Conservative in float: never false when a point
// of that part lies in the sphere (docs/traversal-lists.md, "Sphere test").
bool SphereMayHit(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 sphere);

// A list element's key, as tl.lists computes it in float: the low (earliest first) or high end of the
// projection of a sphere or of a triangle's vertices on `axis`, as an unsigned integer that orders
// like the float (-0 before +0; a NaN last).
std::uint32_t SphereKey(glm::vec4 sphere, glm::vec3 axis, std::uint32_t order);
std::uint32_t TriangleKey(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 axis, std::uint32_t order);

}  // namespace rayspace::emu::tl

namespace rayspace::emu {
// The emulated passes (mirroring gpu/shaders/tl_lists.comp and tl_trace.comp).
TlListArrays PassTlLists(const call::TlLists& c);
TlWalks PassTlTrace(const call::TlTrace& c);
// tl.trace with another sphere test (null: SphereMayHit).
TlWalks TlTraceWith(const call::TlTrace& c, tl::SphereTest test);
}  // namespace rayspace::emu
