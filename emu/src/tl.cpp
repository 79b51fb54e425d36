// Traversal lists (rayspace/emu/tl/tl.h): the build in double from the object tree, the walk in
// float with the kernels' operations (intersect.h), so that a GLSL kernel can repeat it.
#include "rayspace/emu/tl/tl.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "rayspace/contract.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/error.h"

namespace rayspace::emu::tl {
namespace {

struct Child {
  double key;
  bool triangle;
  std::uint32_t id;  // triangle: scene index; otherwise tree node
};

struct Flattener {
  std::span<const layout::Triangle> tris;
  const ObjectTree& tree;
  const std::vector<Word>& tri_words;
  glm::dvec3 axis;
  Order order;
  Lists& out;

  double TriangleKey(std::uint32_t i) const {
    const layout::Triangle& t = tris[i];
    double lo = INFINITY, hi = -INFINITY;
    for (const glm::vec4& v : {t.v0, t.v1, t.v2}) {
      const double p = glm::dot(glm::dvec3(v.x, v.y, v.z), axis);
      lo = std::min(lo, p);
      hi = std::max(hi, p);
    }
    return order == Order::kEarliestFirst ? lo : hi;
  }
  double NodeKey(std::uint32_t n) const {
    const glm::vec4& s = tree.nodes[n].sphere;
    const double p = glm::dot(glm::dvec3(s.x, s.y, s.z), axis);
    return order == Order::kEarliestFirst ? p - s.w : p + s.w;
  }
  // Own triangles (input order) then child nodes (octant order); the stable sort keeps that order
  // among equal keys, so the result depends on nothing but the tree and the direction.
  std::vector<Child> Children(std::uint32_t n) const {
    const ObjectTreeNode& node = tree.nodes[n];
    std::vector<Child> c;
    for (std::uint32_t j = 0; j < node.tris; ++j) {
      const std::uint32_t t = tree.triangles[node.first_tri + j];
      c.push_back({TriangleKey(t), true, t});
    }
    for (std::uint32_t j = 0; j < node.children; ++j) c.push_back({NodeKey(node.first_child + j), false, node.first_child + j});
    std::stable_sort(c.begin(), c.end(), [](const Child& a, const Child& b) { return a.key < b.key; });
    return c;
  }
  // Depth first; a sphere's escape is the size of its subtree (its super-sibling follows it).
  void Emit(std::uint32_t n) {
    const std::size_t at = out.words.size();
    const glm::vec4& s = tree.nodes[n].sphere;
    out.words.push_back({std::bit_cast<std::uint32_t>(s.x), std::bit_cast<std::uint32_t>(s.y), std::bit_cast<std::uint32_t>(s.z),
                         std::bit_cast<std::uint32_t>(s.w)});
    out.escapes.push_back(0);
    for (const Child& c : Children(n)) {
      if (!c.triangle) {
        Emit(c.id);
        continue;
      }
      out.words.push_back(tri_words[c.id]);
      out.escapes.push_back(1);
    }
    out.escapes[at] = static_cast<Escape>(out.words.size() - at);
  }
};

// An escape past the list's end is the paper's special value: 0 for the last triangle, -1 for a
// sphere on the last branch.
void MarkEnds(Lists& out, std::size_t begin) {
  const std::size_t end = out.escapes.size();
  for (std::size_t i = begin; i < end; ++i)
    if (i + static_cast<std::size_t>(out.escapes[i]) >= end) out.escapes[i] = out.escapes[i] == 1 ? kEscapeLast : kEscapeNone;
}

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

std::vector<glm::vec3> Directions(std::uint32_t k) {
  if (k == 1) return {{1, 0, 0}};
  if (k == 2) return {{1, 0, 0}, {-1, 0, 0}};
  if (k == 6) return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  std::vector<glm::vec3> d;
  const float c = static_cast<float>(1.0 / std::sqrt(3.0));
  for (std::uint32_t b = 0; b < 8; ++b) d.push_back({(b & 1) ? -c : c, (b & 2) ? -c : c, (b & 4) ? -c : c});
  return d;
}

}  // namespace

bool ValidListCount(std::uint32_t k) { return k == 1 || k == 2 || k == 6 || k == 8; }

std::uint64_t Lists::Bytes() const {
  return escapes.size() * sizeof(Escape) + words.size() * sizeof(Word) + vertices.size() * sizeof(Vertex) +
         first.size() * sizeof(std::uint32_t);
}

Lists Build(std::span<const layout::Triangle> triangles, const Options& options) {
  RS_CHECK_MSG(ValidListCount(options.lists), "traversal lists: {} lists (1, 2, 6 or 8)", options.lists);
  Lists out;
  out.count = options.lists;
  out.directions = Directions(options.lists);
  const std::vector<Word> tri_words = ShareVertices(triangles, out.vertices);
  ObjectTree tree;
  if (!triangles.empty()) {
    const glm::uvec4 all(0u, static_cast<std::uint32_t>(triangles.size()), 0u, 0u);
    tree = BuildObjectTree(triangles, std::span<const glm::uvec4>(&all, 1), options.tree);
  }
  out.first.push_back(0);
  for (const glm::vec3& d : out.directions) {
    const std::size_t begin = out.words.size();
    Flattener f{triangles, tree, tri_words, glm::dvec3(d), options.order, out};
    for (const std::uint32_t root : tree.roots) f.Emit(root);
    MarkEnds(out, begin);
    out.first.push_back(static_cast<std::uint32_t>(out.words.size()));
  }
  return out;
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

// Along the unit direction u, the centre lies at a and at distance b from the line. The ray's part
// [t0, t1] (in length) meets the sphere only if b <= r and [a - r, a + r] meets [t0, t1]; both are
// checked with the sphere grown by the cone test's slacks (contract.h), which cover the rounding of
// v, u, a, b and the t scaling (a few ulps of |a| + b, of t), so the test only ever accepts more.
bool SphereMayHit(glm::vec3 org, glm::vec3 dir, float tmin, float tlimit, glm::vec4 sphere) {
  const float len = Length(dir);
  const glm::vec3 v = Xyz(sphere) - org;
  const glm::vec3 u(dir.x / len, dir.y / len, dir.z / len);
  const float a = Dot(v, u), b = Length(Cross(v, u));
  if (!std::isfinite(a) || !std::isfinite(b)) return true;  // out of float range: keep
  const float r = (sphere.w * layout::kRadiusSlack + (Abs(a) + b) * layout::kTestSlack) +
                  std::bit_cast<float>(layout::kRadiusFloorBits);
  if (b > r) return false;
  const float t0 = tmin * len, t1 = tlimit * len;
  if (a + r < t0 - Abs(t0) * layout::kTestSlack) return false;
  return !(a - r > t1 + Abs(t1) * layout::kTestSlack);
}

namespace {

struct Walker {
  const Lists& lists;
  glm::vec3 org, dir;
  float tmin, tmax;
  std::uint32_t ignore;
  WatertightRay wr;
  std::uint64_t best = kMissPacked;
  Stats stats;

  bool Triangle(const Word& w) {
    ++stats.triangles;
    if (w.w == ignore) return false;
    float t;
    if (!IntersectWatertight(wr, Xyz(lists.vertices[w.x]), Xyz(lists.vertices[w.y]), Xyz(lists.vertices[w.z]), tmin, tmax, t))
      return false;
    best = std::min(best, PackHit(t, w.w));
    return true;
  }
  // The paper's loop: a hit sphere leads to its first child (next element), a missed one to its
  // escape; following 0 or -1 ends the walk. A sphere is pruned beyond the best hit so far, not
  // strictly before it, so that a tie at the same t with a lower id is still found.
  void Walk(bool any) {
    const std::uint32_t k = ListFor(lists.count, dir);
    std::int64_t i = lists.first[k];
    if (i == lists.first[k + 1]) return;
    Escape next;
    do {
      next = lists.escapes[static_cast<std::size_t>(i)];
      const Word& w = lists.words[static_cast<std::size_t>(i)];
      if (IsTriangle(next)) {
        if (Triangle(w) && any) return;
      } else {
        ++stats.spheres;
        const float limit = best == kMissPacked ? tmax : HitT(best);
        const glm::vec4 s(std::bit_cast<float>(w.x), std::bit_cast<float>(w.y), std::bit_cast<float>(w.z), std::bit_cast<float>(w.w));
        if (SphereMayHit(org, dir, tmin, limit, s)) next = 1;
      }
      i += next;
    } while (next > 0);
  }
};

Walker MakeWalker(const Lists& lists, const layout::Ray& ray) {
  const glm::vec3 org = Xyz(ray.origin_tmin), dir = Xyz(ray.direction_tmax);
  return Walker{lists, org, dir, ray.origin_tmin.w, ray.direction_tmax.w, ray.info.y, SetupWatertight(org, dir), kMissPacked, {}};
}

void AddStats(Stats* to, const Stats& s) {
  if (to == nullptr) return;
  to->spheres += s.spheres;
  to->triangles += s.triangles;
}

}  // namespace

std::uint64_t Closest(const Lists& lists, const layout::Ray& ray, Stats* stats) {
  Walker w = MakeWalker(lists, ray);
  w.Walk(false);
  AddStats(stats, w.stats);
  return w.best;
}

bool Any(const Lists& lists, const layout::Ray& ray, Stats* stats) {
  Walker w = MakeWalker(lists, ray);
  w.Walk(true);
  AddStats(stats, w.stats);
  return w.best != kMissPacked;
}

}  // namespace rayspace::emu::tl
