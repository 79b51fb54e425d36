// The buffers the traversal-list passes read and write (rayspace/contract.h, kTlLists* and kTlTrace*):
// the host's tree as tl.lists reads it, the lists it writes, and what tl.trace returns per ray.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "rayspace/emu/fields.h"

namespace rayspace::emu {

// The bounding-sphere tree and the shared vertices, built on the host (tl::PrepareTree). Element e of
// a list is node e when e < nodes, else the triangle reference e - nodes.
struct TlTreeView {
  std::span<const glm::uvec4> tl_links;        // per node: first_child, children, first_tri, tris
  std::span<const glm::vec4> tl_spheres;       // per node
  std::span<const std::uint32_t> tl_parents;   // per node: parent, or layout::kTlNoParent
  std::span<const std::uint32_t> tl_sizes;     // per node: its subtree's elements
  std::span<const std::uint32_t> tl_roots;     // in list order
  std::span<const std::uint32_t> tl_triangles; // per triangle reference: scene triangle
  std::span<const std::uint32_t> tl_owners;    // per triangle reference: its node
  std::span<const glm::uvec4> tl_tri_words;    // per scene triangle: vertex indices and id
  std::span<const glm::vec4> tl_vertices;      // shared: xyz, w = 1
  std::size_t Nodes() const { return tl_links.size(); }
  std::size_t Elements() const { return tl_links.size() + tl_triangles.size(); }
  RS_FIELDS(tl_links, tl_spheres, tl_parents, tl_sizes, tl_roots, tl_triangles, tl_owners, tl_tri_words, tl_vertices)
};

// K lists in slots of E elements, list k at [k E, k E + lengths[k]) (the rest of its slot zero):
// per element its escape (the bits of a signed offset) and its 128-bit word.
struct TlListArrays {
  std::vector<std::uint32_t> escapes;
  std::vector<glm::uvec4> words;
  std::vector<std::uint32_t> lengths;
  RS_FIELDS(escapes, words, lengths)
};

// Per (scene triangle, case, list): the window [head, tail) of the packed lists its rays walk, as two
// words at 2 ((triangle kTlCases + case) K + list).
struct TlWindows {
  std::vector<std::uint32_t> windows;
  RS_FIELDS(windows)
};

// Per ray: its closest hit (closest-hit batches) or whether it is occluded (shadow batches; the other
// array is empty), and the sphere and triangle elements its walk tested.
struct TlWalks {
  std::vector<std::uint64_t> hits;
  std::vector<std::uint32_t> occluded, spheres, triangles;
  RS_FIELDS(hits, occluded, spheres, triangles)
  // Per ray, the list entries its walk passed (tl::Stats::entries): counted by the emulator's walk for
  // the statistics (Toczek et al.'s "traversed nodes" read as entries); tl_trace.comp does not write
  // it, so a backend's walks leave it empty and it is not one of the compared fields.
  std::vector<std::uint32_t> entries;
};

}  // namespace rayspace::emu
