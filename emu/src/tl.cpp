// Traversal lists (rayspace/emu/tl/tl.h): the build in double from the object tree, the walk in
// float with the kernels' operations (intersect.h), so that a GLSL kernel can repeat it.
#include "rayspace/emu/tl/tl.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <unordered_map>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "rayspace/contract.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/walk_math.h"
#include "rayspace/emu/tl/window.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu::tl {
namespace {

// Distinct positions by their bits, in first-use order: deterministic, and -0 and 0 stay apart so
// a triangle reads back exactly the floats it was given.
std::vector<Word> ShareVertices(std::span<const layout::Triangle> tris, std::vector<Vertex>& vertices) {
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> seen;
  auto index = [&](const glm::vec4& v) {
    const std::uint32_t x = std::bit_cast<std::uint32_t>(v.x), y = std::bit_cast<std::uint32_t>(v.y), z = std::bit_cast<std::uint32_t>(v.z);
    auto& bucket = seen[(std::uint64_t{x} << 32 | y) ^ (std::uint64_t{z} * 0x9E3779B97F4A7C15ull)];
    for (const std::uint32_t k : bucket)
      if (std::bit_cast<std::uint32_t>(vertices[k].x) == x && std::bit_cast<std::uint32_t>(vertices[k].y) == y &&
          std::bit_cast<std::uint32_t>(vertices[k].z) == z)
        return k;
    bucket.push_back(static_cast<std::uint32_t>(vertices.size()));
    vertices.push_back({v.x, v.y, v.z, 1.0f});
    return bucket.back();
  };
  std::vector<Word> words(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i)
    words[i] = {index(tris[i].v0), index(tris[i].v1), index(tris[i].v2), static_cast<std::uint32_t>(i)};
  return words;
}

// A float as an unsigned integer of the same order (-0 before +0), a NaN after everything.
std::uint32_t Ordered(float f) {
  if (std::isnan(f)) return ~0u;
  const std::uint32_t b = std::bit_cast<std::uint32_t>(f);
  return (b & 0x80000000u) ? ~b : b | 0x80000000u;
}

}  // namespace

TlTreeView Tree::View() const {
  return {links, spheres, parents, sizes, roots, triangles, owners, tri_words, vertices};
}

// Nodes are breadth first (a child after its parent), so sizes accumulate from the last node up.
Tree PrepareTree(std::span<const layout::Triangle> triangles, const ObjectTreeOptions& options) {
  Tree t;
  t.tri_words = ShareVertices(triangles, t.vertices);
  if (triangles.empty()) return t;
  const glm::uvec4 all(0u, static_cast<std::uint32_t>(triangles.size()), 0u, 0u);
  const ObjectTree tree = BuildObjectTree(triangles, std::span<const glm::uvec4>(&all, 1), options);
  const std::size_t n = tree.nodes.size();
  t.links.resize(n);
  t.spheres.resize(n);
  t.parents.assign(n, layout::kTlNoParent);
  t.sizes.assign(n, 0);
  t.owners.assign(tree.triangles.size(), 0);
  for (std::size_t i = 0; i < n; ++i) {
    const ObjectTreeNode& nd = tree.nodes[i];
    t.links[i] = {nd.first_child, nd.children, nd.first_tri, nd.tris};
    t.spheres[i] = nd.sphere;
    for (std::uint32_t c = 0; c < nd.children; ++c) t.parents[nd.first_child + c] = static_cast<std::uint32_t>(i);
    for (std::uint32_t j = 0; j < nd.tris; ++j) t.owners[nd.first_tri + j] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t i = n; i-- > 0;) {
    const ObjectTreeNode& nd = tree.nodes[i];
    RS_CHECK(nd.children == 0 || nd.first_child > i);
    std::uint32_t size = 1 + nd.tris;
    for (std::uint32_t c = 0; c < nd.children; ++c) size += t.sizes[nd.first_child + c];
    t.sizes[i] = size;
  }
  t.roots = tree.roots;
  t.triangles = tree.triangles;
  return t;
}

std::vector<glm::vec4> Directions(std::uint32_t k) {
  if (k == 1) return {{1, 0, 0, 0}};
  if (k == 2) return {{1, 0, 0, 0}, {-1, 0, 0, 0}};
  if (k == 6) return {{1, 0, 0, 0}, {-1, 0, 0, 0}, {0, 1, 0, 0}, {0, -1, 0, 0}, {0, 0, 1, 0}, {0, 0, -1, 0}};
  std::vector<glm::vec4> d;
  const float c = static_cast<float>(1.0 / std::sqrt(3.0));
  for (std::uint32_t b = 0; b < 8; ++b) d.push_back({(b & 1) ? -c : c, (b & 2) ? -c : c, (b & 4) ? -c : c, 0.0f});
  return d;
}

std::uint32_t SphereKey(glm::vec4 sphere, glm::vec3 axis, std::uint32_t order) {
  const float p = Dot(Xyz(sphere), axis);
  return Ordered(order == layout::kTlOrderEarliestFirst ? p - sphere.w : p + sphere.w);
}

// min and max by comparisons in a fixed order (GLSL's min/max leave NaN operands open).
std::uint32_t TriangleKey(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, glm::vec3 axis, std::uint32_t order) {
  const float p1 = Dot(v1, axis), p2 = Dot(v2, axis);
  float k = Dot(v0, axis);
  if (order == layout::kTlOrderEarliestFirst) {
    if (p1 < k) k = p1;
    if (p2 < k) k = p2;
  } else {
    if (p1 > k) k = p1;
    if (p2 > k) k = p2;
  }
  return Ordered(k);
}

bool ValidListCount(std::uint32_t k) { return k == 1 || k == 2 || k == 6 || k == 8; }

std::uint64_t Lists::Bytes() const {
  return escapes.size() * sizeof(Escape) + words.size() * sizeof(Word) + vertices.size() * sizeof(Vertex) +
         first.size() * sizeof(std::uint32_t);
}

Packed Pack(const TlListArrays& a, std::size_t slot, std::string_view what) {
  const std::size_t k = a.lengths.size();
  if (a.escapes.size() < k * slot || a.words.size() < k * slot)
    ThrowInput("{}: {} escapes and {} words for {} lists of up to {} elements", what, a.escapes.size(), a.words.size(), k, slot);
  Packed p;
  p.first.push_back(0);
  for (std::size_t j = 0; j < k; ++j) {
    const std::uint32_t n = a.lengths[j];
    if (n > slot) ThrowInput("{}: list {} holds {} elements, beyond its {}", what, j, n, slot);
    p.escapes.insert(p.escapes.end(), a.escapes.begin() + j * slot, a.escapes.begin() + j * slot + n);
    p.words.insert(p.words.end(), a.words.begin() + j * slot, a.words.begin() + j * slot + n);
    p.first.push_back(static_cast<std::uint32_t>(p.escapes.size()));
  }
  return p;
}

Lists Assemble(const Tree& tree, std::uint32_t count, TlListArrays arrays, bool one_sided) {
  Lists out;
  out.count = count;
  for (const glm::vec4& d : Directions(count)) out.directions.push_back(Xyz(d));
  Packed p = Pack(arrays, tree.links.size() + tree.triangles.size(), "tl.lists");
  RS_CHECK(p.first.size() == count + 1);
  out.first = std::move(p.first);
  out.escapes = std::move(p.escapes);
  out.words = std::move(p.words);
  out.vertices = tree.vertices;
  out.one_sided = one_sided;
  return out;
}

// The corners of a class: for 6 lists s e_a + (+-e_b) + (+-e_c), so g . n >= 0 at all four is
// s n_a >= |n_b| + |n_c|; for 8 lists the axes s_x e_x, s_y e_y, s_z e_z. The margin scales with
// |e1| |e2| and |g|_1: float n is within about 2^-20 |e1| |e2| per component (the edges' and the
// products' rounding), so a culled triangle is one whose exact normal passes the exact test.
bool Culled(glm::vec3 v0, glm::vec3 v1, glm::vec3 v2, std::uint32_t count, std::uint32_t k) {
  return CulledOf(v0, v1, v2, count, k);
}

Lists Build(std::span<const layout::Triangle> triangles, const Options& options) {
  RS_CHECK_MSG(ValidListCount(options.lists), "traversal lists: {} lists (1, 2, 6 or 8)", options.lists);
  const Tree tree = PrepareTree(triangles, options.tree);
  const std::vector<glm::vec4> dirs = Directions(options.lists);
  return Assemble(tree, options.lists,
                  PassTlLists({.tree = tree.View(),
                               .directions = dirs,
                               .order = static_cast<std::uint32_t>(options.order),
                               .cull = options.cull ? 1u : 0u}),
                  options.cull);
}

std::uint32_t ListFor(std::uint32_t count, glm::vec3 dir) {
  if (count == 2) return dir.x < 0.0f ? 1u : 0u;
  if (count == 6) {
    const glm::vec3 a(std::fabs(dir.x), std::fabs(dir.y), std::fabs(dir.z));
    int k = 0;
    if (a.y > a[k]) k = 1;
    if (a.z > a[k]) k = 2;
    return static_cast<std::uint32_t>(2 * k) + (dir[k] < 0.0f ? 1u : 0u);
  }
  if (count == 8) return (dir.x < 0.0f ? 1u : 0u) | (dir.y < 0.0f ? 2u : 0u) | (dir.z < 0.0f ? 4u : 0u);
  return 0;
}

bool SphereMayHit(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 sphere) {
  return SphereMayHitOf<float>(org, dir, tmin, tlimit, sphere);
}

namespace {

// The walk as tl_trace.comp runs it: in blocks of kTlLoopBlock steps (lavapipe's loop bound), each
// step moving forward, so a list of at most kTlMaxElements elements always ends.
struct Walker {
  const ListsView& lists;
  glm::vec3 org, dir;
  float tmin, tmax;
  std::uint32_t ignore;
  WatertightRay wr;
  std::uint64_t best = kMissPacked;
  Stats stats;
  SphereTest test;

  bool Triangle(const Word& w) {
    ++stats.triangles;
    if (w.w == ignore) return false;
    float t, det;
    if (!IntersectWatertight(wr, Xyz(lists.vertices[w.x]), Xyz(lists.vertices[w.y]), Xyz(lists.vertices[w.z]), tmin, tmax, t, &det))
      return false;
    if (lists.one_sided && !(det > 0.0f)) return false;  // met from behind
    best = std::min(best, PackHit(t, w.w));
    return true;
  }
  // The paper's loop: a hit sphere leads to its first child (next element), a missed one to its
  // escape; following 0 or -1 ends the walk. A sphere is pruned beyond the best hit so far, not
  // strictly before it, so that a tie at the same t with a lower id is still found.
  void Walk(const layout::Ray& ray, bool any) {
    const std::uint32_t K = static_cast<std::uint32_t>(lists.first.size() - 1), k = ListFor(K, dir);
    std::uint32_t i = lists.first[k], end = lists.first[k + 1];
    // A ray on a triangle walks that triangle's window (tl.heads) for its case; an eye ray its
    // cell's (tl.cells; a cell beyond the windows: the whole list).
    if (lists.heads == layout::kTlHeadsCells) {
      const std::size_t w = 2 * (std::size_t{ray.info.w} * K + k);
      if (ray.info.w < lists.windows.size() / (2 * K)) i = lists.windows[w], end = lists.windows[w + 1];
    } else {
      const std::uint32_t cs = lists.heads != 0 ? RayCase(lists, lists.tri_words, ray, any, k) : kNoCase;
      if (cs != kNoCase) {
        const std::size_t w = 2 * ((std::size_t{ray.info.y} * layout::kTlCases + cs) * K + k);
        i = lists.windows[w];
        end = lists.windows[w + 1];
      }
    }
    bool done = i >= end;
    const std::uint32_t begin = i;
    std::uint32_t reached = i;  // one past the last entry passed
    for (std::uint32_t b = 0; !done && b <= end / layout::kTlLoopBlock; ++b) {
      for (std::uint32_t j = 0; !done && j < layout::kTlLoopBlock; ++j) {
        Escape next = static_cast<Escape>(lists.escapes[i]);
        const Word& w = lists.words[i];
        bool stop_here = false;  // an any-hit walk's hit: the entries after it are not passed
        if (IsTriangle(next)) {
          if (Triangle(w) && any) next = kEscapeLast, stop_here = true;
        } else {
          ++stats.spheres;
          const float limit = best == kMissPacked ? tmax : HitT(best);
          const glm::vec4 s(std::bit_cast<float>(w.x), std::bit_cast<float>(w.y), std::bit_cast<float>(w.z), std::bit_cast<float>(w.w));
          if (test(org, dir, tmin, limit, s)) next = 1;
        }
        reached = next > 0 ? std::min(i + static_cast<std::uint32_t>(next), end) : stop_here ? i + 1 : end;
        i += static_cast<std::uint32_t>(next);
        done = next <= 0 || i >= end;
      }
    }
    stats.entries = reached - begin;
  }
};

void AddStats(Stats* to, const Stats& s) {
  if (to == nullptr) return;
  to->spheres += s.spheres;
  to->triangles += s.triangles;
  to->entries += s.entries;
}

ListsView ViewOf(const Lists& l) { return {l.first, l.escapes, l.words, l.vertices, l.one_sided}; }

}  // namespace

std::string ListsError(const ListsView& l, std::size_t* bad) {
  const std::size_t k = l.first.size() - (l.first.empty() ? 0 : 1);
  if (!ValidListCount(static_cast<std::uint32_t>(k))) return fmt::format("{} lists (1, 2, 6 or 8)", k);
  if (l.first.front() != 0 || l.first.back() != l.escapes.size() || l.words.size() != l.escapes.size())
    return fmt::format("the list offsets must run from 0 to the {} escapes and {} words", l.escapes.size(), l.words.size());
  for (std::size_t j = 0; j < k; ++j) {
    const std::uint32_t b = l.first[j], e = l.first[j + 1];
    if (e < b || e - b > layout::kTlMaxElements) return fmt::format("list {} runs from {} to {}", j, b, e);
    for (std::uint32_t i = b; i < e; ++i) {
      if (bad) *bad = i;
      const Escape x = static_cast<Escape>(l.escapes[i]);
      const bool last = i + 1 == e;
      if (IsTriangle(x)) {
        if ((x == kEscapeLast) != last) return fmt::format("element {} of list {}: escape {} {} the last element", i - b, j, x, last ? "at" : "before");
        const Word w = l.words[i];
        if (w.x >= l.vertices.size() || w.y >= l.vertices.size() || w.z >= l.vertices.size())
          return fmt::format("element {} of list {}: a vertex index beyond the {} vertices", i - b, j, l.vertices.size());
      } else if (last || (x != kEscapeNone && (x < 2 || std::uint64_t{i} + static_cast<std::uint64_t>(x) >= e))) {
        return fmt::format("element {} of list {}: a sphere with escape {}{}", i - b, j, x, last ? " as the last element" : " outside its list");
      }
    }
  }
  return {};
}

std::uint64_t Walk(const ListsView& lists, const layout::Ray& ray, bool any, Stats* stats, SphereTest test) {
  const glm::vec3 org = Xyz(ray.origin_tmin), dir = Xyz(ray.direction_tmax);
  Walker w{lists, org, dir, ray.origin_tmin.w, ray.direction_tmax.w, ray.info.y, SetupWatertight(org, dir), kMissPacked, {},
           test ? test : SphereMayHit};
  w.Walk(ray, any);
  AddStats(stats, w.stats);
  return w.best;
}

std::uint64_t Closest(const Lists& lists, const layout::Ray& ray, Stats* stats) { return Walk(ViewOf(lists), ray, false, stats); }

bool Any(const Lists& lists, const layout::Ray& ray, Stats* stats) { return Walk(ViewOf(lists), ray, true, stats) != kMissPacked; }

}  // namespace rayspace::emu::tl

namespace rayspace::emu {
namespace {

// tl_lists.comp's invocations, one per (list k, element e), phase by phase. `kept` holds per (list,
// node) the kept triangles and kept nodes of its subtree; a node's size in list k is their sum when
// a triangle is kept below it, else 0 (it is dropped).
struct ListsPass {
  const call::TlLists& c;
  std::uint32_t nodes, K;
  std::vector<glm::uvec2>& kept;
  std::vector<std::uint32_t>& rel;

  std::uint32_t E() const { return static_cast<std::uint32_t>(c.tree.Elements()); }
  bool TriangleKept(std::uint32_t k, std::uint32_t ref) const {
    if (c.cull == 0) return true;
    const glm::uvec4 w = c.tree.tl_tri_words[c.tree.tl_triangles[ref]];
    const auto& v = c.tree.tl_vertices;
    return !tl::Culled(Xyz(v[w.x]), Xyz(v[w.y]), Xyz(v[w.z]), K, k);
  }
  std::uint32_t NodeSize(std::uint32_t k, std::uint32_t n) const {
    const glm::uvec2 x = kept[std::size_t{k} * nodes + n];
    return x.x == 0 ? 0u : x.x + x.y;
  }
  // Phase Triangles and phase Nodes: integer additions, the same sums in any order.
  void AddUp(std::uint32_t k, std::uint32_t from, int component) {
    std::uint32_t x = from;
    for (std::uint32_t d = 0; d <= layout::kTlMaxDepth && x != layout::kTlNoParent; ++d, x = c.tree.tl_parents[x])
      std::atomic_ref<std::uint32_t>(kept[std::size_t{k} * nodes + x][component]).fetch_add(1, std::memory_order_relaxed);
  }
  void Triangles(std::uint32_t k, std::uint32_t e) {
    if (e >= nodes && TriangleKept(k, e - nodes)) AddUp(k, c.tree.tl_owners[e - nodes], 0);
  }
  void Nodes(std::uint32_t k, std::uint32_t e) {
    if (e < nodes && kept[std::size_t{k} * nodes + e].x > 0) AddUp(k, e, 1);
  }

  std::uint32_t Key(glm::vec3 axis, std::uint32_t parent, std::uint32_t sibling) const {
    const glm::uvec4 l = c.tree.tl_links[parent];
    if (sibling >= l.w) return tl::SphereKey(c.tree.tl_spheres[l.x + sibling - l.w], axis, c.order);
    const glm::uvec4 w = c.tree.tl_tri_words[c.tree.tl_triangles[l.z + sibling]];
    const auto& v = c.tree.tl_vertices;
    return tl::TriangleKey(Xyz(v[w.x]), Xyz(v[w.y]), Xyz(v[w.z]), axis, c.order);
  }
  // Sibling s of `parent`'s children (own triangles first, then child nodes) in list k: its kept
  // elements.
  std::uint32_t Size(std::uint32_t k, std::uint32_t parent, std::uint32_t sibling) const {
    const glm::uvec4 l = c.tree.tl_links[parent];
    return sibling >= l.w ? NodeSize(k, l.x + sibling - l.w) : (TriangleKept(k, l.z + sibling) ? 1u : 0u);
  }
  // The kept elements of the roots before `n` (n = kTlNoParent: of every root, the list's length).
  std::uint32_t RootOffset(std::uint32_t k, std::uint32_t n) const {
    std::uint32_t rel = 0;
    for (const std::uint32_t r : c.tree.tl_roots) {
      if (r == n) break;
      rel += NodeSize(k, r);
    }
    return rel;
  }
  bool Kept(std::uint32_t k, std::uint32_t e) const { return e < nodes ? NodeSize(k, e) > 0 : TriangleKept(k, e - nodes); }
  // Phase Rank: a kept element's offset after its parent.
  std::uint32_t Rank(std::uint32_t k, std::uint32_t e) const {
    if (!Kept(k, e)) return 0;
    const glm::vec3 axis = Xyz(c.directions[k]);
    std::uint32_t parent, me;  // me: e's place among its parent's children (own triangles first)
    if (e < nodes) {
      parent = c.tree.tl_parents[e];
      if (parent == layout::kTlNoParent) return RootOffset(k, e);
      const glm::uvec4 l = c.tree.tl_links[parent];
      me = l.w + (e - l.x);
    } else {
      parent = c.tree.tl_owners[e - nodes];
      me = e - nodes - c.tree.tl_links[parent].z;
    }
    const glm::uvec4 l = c.tree.tl_links[parent];
    const std::uint32_t siblings = l.w + l.y, key = Key(axis, parent, me);
    std::uint32_t r = 1;
    for (std::uint32_t b = 0; b < siblings; b += layout::kTlLoopBlock)
      for (std::uint32_t s = b; s < std::min(siblings, b + layout::kTlLoopBlock); ++s) {
        const std::uint32_t ks = Key(axis, parent, s);
        if (ks < key || (ks == key && s < me)) r += Size(k, parent, s);
      }
    return r;
  }
  // Phase Place: a kept element's position is the offsets summed up to its root.
  void Place(std::uint32_t k, std::uint32_t e, TlListArrays& out) const {
    const std::uint32_t length = RootOffset(k, layout::kTlNoParent);
    if (e == 0) out.lengths[k] = length;
    if (!Kept(k, e)) return;
    const std::size_t base = std::size_t{k} * E();
    std::uint32_t pos = rel[base + e];
    std::uint32_t x = e < nodes ? c.tree.tl_parents[e] : c.tree.tl_owners[e - nodes];
    for (std::uint32_t d = 0; d <= layout::kTlMaxDepth && x != layout::kTlNoParent; ++d, x = c.tree.tl_parents[x]) pos += rel[base + x];
    std::uint32_t escape;
    glm::uvec4 word;
    if (e < nodes) {
      const glm::vec4 s = c.tree.tl_spheres[e];
      word = {std::bit_cast<std::uint32_t>(s.x), std::bit_cast<std::uint32_t>(s.y), std::bit_cast<std::uint32_t>(s.z),
              std::bit_cast<std::uint32_t>(s.w)};
      escape = NodeSize(k, e);
      if (pos + escape >= length) escape = layout::kTlEscapeNone;
    } else {
      word = c.tree.tl_tri_words[c.tree.tl_triangles[e - nodes]];
      escape = pos + 1 >= length ? layout::kTlEscapeLast : 1u;
    }
    out.escapes[base + pos] = escape;
    out.words[base + pos] = word;
  }
};

}  // namespace

// Four phases, each a dispatch over every (list, element), each reading only what the phases before
// wrote (the scratch arrays `kept` and `rel`).
TlListArrays PassTlLists(const call::TlLists& c) {
  const std::uint32_t nodes = static_cast<std::uint32_t>(c.tree.Nodes()), E = static_cast<std::uint32_t>(c.tree.Elements());
  const std::uint32_t K = static_cast<std::uint32_t>(c.directions.size());
  const std::size_t total = std::size_t{K} * E;
  std::vector<glm::uvec2> kept(std::size_t{K} * nodes, glm::uvec2(0));
  std::vector<std::uint32_t> rel(total, 0);
  ListsPass pass{c, nodes, K, kept, rel};
  auto k_of = [&](std::size_t g) { return static_cast<std::uint32_t>(g / E); };
  auto e_of = [&](std::size_t g) { return static_cast<std::uint32_t>(g % E); };
  ParallelFor(total, [&](std::size_t g) { pass.Triangles(k_of(g), e_of(g)); });
  ParallelFor(total, [&](std::size_t g) { pass.Nodes(k_of(g), e_of(g)); });
  ParallelFor(total, [&](std::size_t g) { rel[g] = pass.Rank(k_of(g), e_of(g)); });
  TlListArrays out;
  out.escapes.assign(total, 0);
  out.words.assign(total, glm::uvec4(0));
  out.lengths.assign(K, 0);
  if (E == 0) return out;
  ParallelFor(total, [&](std::size_t g) { pass.Place(k_of(g), e_of(g), out); });
  return out;
}

namespace {

// One invocation of tl_heads.comp: the window of (triangle, case, list).
// An element's sphere (a sphere element) or vertices (a triangle element), for a rejection test.
template <typename Call, typename SphereTest, typename TriangleTest>
bool ElementRejected(const Call& c, std::uint32_t i, SphereTest&& sphere, TriangleTest&& triangle) {
  const glm::uvec4 w = c.words[i];
  if (!tl::IsTriangle(static_cast<tl::Escape>(c.escapes[i])))
    return sphere(glm::vec4(std::bit_cast<float>(w.x), std::bit_cast<float>(w.y), std::bit_cast<float>(w.z), std::bit_cast<float>(w.w)));
  return triangle(Xyz(c.vertices[w.x]), Xyz(c.vertices[w.y]), Xyz(c.vertices[w.z]));
}

// One invocation of tl_heads.comp: the window of (triangle, case, list).
glm::uvec2 HeadsWindow(const call::TlHeads& c, std::uint32_t K, std::uint32_t t, std::uint32_t cs, std::uint32_t k) {
  const std::uint32_t begin = c.first[k], end = c.first[k + 1];
  const glm::uvec4 w = c.tri_words[t];
  const tl::HeadPlanes p = tl::MakePlanes(Xyz(c.vertices[w.x]), Xyz(c.vertices[w.y]), Xyz(c.vertices[w.z]), cs, K, k, c.mode, c.margin);
  if (!p.valid) return {begin, end};
  return tl::ListWindow(c.escapes, begin, end, [&](std::uint32_t i) {
    return ElementRejected(
        c, i, [&](glm::vec4 s) { return tl::SphereRejected(p, s); },
        [&](glm::vec3 a, glm::vec3 b, glm::vec3 d) { return tl::TriangleRejected(p, a, b, d); });
  });
}

// One invocation of tl_cells.comp: the window of (cell, list).
glm::uvec2 CellsWindow(const call::TlCells& c, std::uint32_t k, std::uint32_t cell) {
  const tl::CellPlanes p = tl::MakeCellPlanes(c.frame, cell, c.margin);
  return tl::ListWindow(
      c.escapes, c.first[k], c.first[k + 1],
      [&](std::uint32_t i) {
        return ElementRejected(
            c, i, [&](glm::vec4 s) { return tl::CellSphereRejected(p, s); },
            [&](glm::vec3 a, glm::vec3 b, glm::vec3 d) { return tl::CellTriangleRejected(p, a, b, d); });
      });
}

}  // namespace

TlWindows PassTlHeads(const call::TlHeads& c) {
  const std::uint32_t K = static_cast<std::uint32_t>(c.first.size() - 1), T = static_cast<std::uint32_t>(c.tri_words.size());
  const std::size_t total = std::size_t{T} * layout::kTlCases * K;
  TlWindows out;
  out.windows.assign(2 * total, 0u);
  ParallelForDynamic(total, 64, [&](std::size_t g) {
    const std::uint32_t k = static_cast<std::uint32_t>(g % K), cs = static_cast<std::uint32_t>(g / K % layout::kTlCases),
                        t = static_cast<std::uint32_t>(g / K / layout::kTlCases);
    const glm::uvec2 w = HeadsWindow(c, K, t, cs, k);
    out.windows[2 * g] = w.x;
    out.windows[2 * g + 1] = w.y;
  });
  return out;
}

TlWindows PassTlCells(const call::TlCells& c) {
  const std::uint32_t K = static_cast<std::uint32_t>(c.first.size() - 1);
  const std::size_t total = std::size_t{tl::CellCount(c.frame)} * K;
  TlWindows out;
  out.windows.assign(2 * total, 0u);
  ParallelForDynamic(total, 16, [&](std::size_t g) {
    const glm::uvec2 w = CellsWindow(c, static_cast<std::uint32_t>(g % K), static_cast<std::uint32_t>(g / K));
    out.windows[2 * g] = w.x;
    out.windows[2 * g + 1] = w.y;
  });
  return out;
}

TlWalks PassTlTrace(const call::TlTrace& c) { return TlTraceWith(c, nullptr); }

TlWalks TlTraceWith(const call::TlTrace& c, tl::SphereTest test) {
  const tl::ListsView view{c.first, c.escapes, c.words, c.vertices, c.cull != 0, c.heads, c.tri_words, c.windows};
  const std::size_t n = c.rays.size();
  TlWalks out;
  if (c.shadow)
    out.occluded.resize(n);
  else
    out.hits.resize(n);
  out.spheres.assign(n, 0);
  out.triangles.assign(n, 0);
  out.entries.assign(n, 0);
  ParallelForDynamic(n, 256, [&](std::size_t i) {
    tl::Stats s;
    const std::uint64_t hit = tl::Walk(view, c.rays[i], c.shadow != 0, &s, test);
    if (c.shadow)
      out.occluded[i] = hit != kMissPacked ? 1u : 0u;
    else
      out.hits[i] = hit;
    out.spheres[i] = static_cast<std::uint32_t>(s.spheres);
    out.triangles[i] = static_cast<std::uint32_t>(s.triangles);
    out.entries[i] = static_cast<std::uint32_t>(s.entries);
  });
  return out;
}

}  // namespace rayspace::emu
