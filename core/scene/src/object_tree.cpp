// The object tree's build (rayspace/object_tree.h). Breadth-first through a queue, so that a node's
// children are appended together and its consecutive ids follow; geometry in double, each sphere
// rounded outward to float once.
#include "rayspace/object_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "rayspace/error.h"

namespace rayspace {
namespace {

// A float at least x (x finite, >= 0), one float step further out: double's own rounding of the
// distance it bounds is then covered too.
float OutwardFloat(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return std::nextafter(f, std::numeric_limits<float>::infinity());
}

glm::dvec3 Vertex(const layout::Triangle& t, int k) {
  const glm::vec4& v = k == 0 ? t.v0 : k == 1 ? t.v1 : t.v2;
  return {v.x, v.y, v.z};
}

glm::dvec3 Centroid(const layout::Triangle& t) { return (Vertex(t, 0) + Vertex(t, 1) + Vertex(t, 2)) / 3.0; }

// The sphere centred at the centre of the triangles' tight bounding box holding all their vertices
// (and their spheres, when given).
glm::vec4 NodeSphere(std::span<const layout::Triangle> tris, std::span<const glm::vec4> spheres, const std::vector<std::uint32_t>& set) {
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const std::uint32_t i : set)
    for (const glm::vec4& v : {tris[i].v0, tris[i].v1, tris[i].v2}) {
      RS_CHECK_MSG(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z), "object tree: triangle {} has a non-finite vertex", i);
      lo = glm::min(lo, glm::vec3(v));
      hi = glm::max(hi, glm::vec3(v));
    }
  const glm::vec3 c = lo * 0.5f + hi * 0.5f;  // halves first: no overflow for extreme boxes
  double r = 0.0;
  for (const std::uint32_t i : set) {
    for (int k = 0; k < 3; ++k) r = std::max(r, glm::length(Vertex(tris[i], k) - glm::dvec3(c)));
    if (!spheres.empty()) {
      const glm::vec4& s = spheres[i];
      r = std::max(r, glm::length(glm::dvec3(s.x, s.y, s.z) - glm::dvec3(c)) + static_cast<double>(s.w));
    }
  }
  return {c, OutwardFloat(r)};
}

struct Pending {
  std::uint32_t node, depth;
  std::vector<std::uint32_t> set;
};

// Toczek et al.'s split of a node's set: big triangles stay (own), the rest go to the octant of
// their centroid about the centre (bit 0 x, 1 y, 2 z: centroid above the centre).
void Split(std::span<const layout::Triangle> tris, const std::vector<std::uint32_t>& set, glm::vec4 sphere,
           const ObjectTreeOptions& o, std::vector<std::uint32_t>& own, std::array<std::vector<std::uint32_t>, 8>& octant) {
  const glm::dvec3 c(sphere.x, sphere.y, sphere.z);
  const double big = static_cast<double>(o.big_fraction) * sphere.w;
  for (const std::uint32_t i : set) {
    const glm::dvec3 g = Centroid(tris[i]);
    double rt = 0.0;
    for (int k = 0; k < 3; ++k) rt = std::max(rt, glm::length(Vertex(tris[i], k) - g));
    if (rt >= big) {
      own.push_back(i);
      continue;
    }
    const int bits = (g.x > c.x ? 1 : 0) | (g.y > c.y ? 2 : 0) | (g.z > c.z ? 4 : 0);
    octant[static_cast<std::size_t>(bits)].push_back(i);
  }
}

// Builds one node from `p.set`; its non-empty octants become children appended (together) to the
// node array and queued.
void BuildNode(std::span<const layout::Triangle> tris, std::span<const glm::vec4> spheres, const ObjectTreeOptions& o, Pending p,
               ObjectTree& tree, std::deque<Pending>& queue) {
  constexpr std::uint32_t kMaxDepth = 64;
  ObjectTreeNode& node = tree.nodes[p.node];
  node.sphere = NodeSphere(tris, spheres, p.set);
  std::vector<std::uint32_t> own;
  std::array<std::vector<std::uint32_t>, 8> octant;
  if (p.set.size() > o.leaf_triangles && p.depth < kMaxDepth) Split(tris, p.set, node.sphere, o, own, octant);
  const bool progress = std::none_of(octant.begin(), octant.end(), [&](const auto& g) { return g.size() == p.set.size(); });
  if (own.empty() && std::all_of(octant.begin(), octant.end(), [](const auto& g) { return g.empty(); }))
    own = p.set;  // a leaf
  else if (!progress)
    own = p.set, octant = {};  // every triangle in one octant again (coincident centroids): stop here
  node.first_tri = static_cast<std::uint32_t>(tree.triangles.size());
  node.tris = static_cast<std::uint32_t>(own.size());
  tree.triangles.insert(tree.triangles.end(), own.begin(), own.end());
  node.first_child = static_cast<std::uint32_t>(tree.nodes.size());
  node.children = 0;
  for (auto& g : octant) {
    if (g.empty()) continue;
    const std::uint32_t id = static_cast<std::uint32_t>(tree.nodes.size());
    tree.nodes.push_back({});
    tree.depth.push_back(p.depth + 1);
    ++tree.nodes[p.node].children;
    queue.push_back({id, p.depth + 1, std::move(g)});
  }
}

}  // namespace

ObjectTree BuildObjectTree(std::span<const layout::Triangle> triangles, std::span<const glm::uvec4> objects,
                           const ObjectTreeOptions& options, std::span<const glm::vec4> tri_spheres) {
  RS_CHECK_MSG(tri_spheres.empty() || tri_spheres.size() == triangles.size(), "object tree: {} spheres for {} triangles",
               tri_spheres.size(), triangles.size());
  RS_CHECK_MSG(options.big_fraction > 0.0f && options.leaf_triangles >= 1, "object tree: big_fraction {} leaf_triangles {}",
               options.big_fraction, options.leaf_triangles);
  ObjectTree tree;
  std::deque<Pending> queue;
  for (const glm::uvec4& obj : objects) {
    RS_CHECK_MSG(std::size_t{obj.x} + obj.y <= triangles.size() && obj.y > 0, "object tree: object of triangles [{}, +{})", obj.x, obj.y);
    const std::uint32_t root = static_cast<std::uint32_t>(tree.nodes.size());
    tree.roots.push_back(root);
    tree.nodes.push_back({});
    tree.depth.push_back(0);
    std::vector<std::uint32_t> set(obj.y);
    for (std::uint32_t k = 0; k < obj.y; ++k) set[k] = obj.x + k;
    queue.push_back({root, 0, std::move(set)});
    // Objects one after another: each object's nodes are contiguous, breadth-first within it.
    while (!queue.empty()) {
      Pending p = std::move(queue.front());
      queue.pop_front();
      BuildNode(triangles, tri_spheres, options, std::move(p), tree, queue);
    }
  }
  return tree;
}

}  // namespace rayspace
