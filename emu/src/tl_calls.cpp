// The contract of the traversal-list passes' inputs (emu/calls.h, `--algo tl`), checked before a saved
// or hand-made call runs: a call that passes runs on every backend without reading out of bounds and
// every loop of its kernel ends within lavapipe's bounds.
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "rayspace/contract.h"
#include "rayspace/emu/calls.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/error.h"

namespace rayspace::emu {
namespace {

// A forest: every node but the roots the child of exactly one node listed after it (so no cycle),
// parents and owners agreeing with the links, sizes the subtrees', depth at most kTlMaxDepth.
void CheckForest(std::string_view call, const TlTreeView& t) {
  const std::size_t nodes = t.Nodes(), refs = t.tl_triangles.size();
  if (t.tl_spheres.size() != nodes || t.tl_parents.size() != nodes || t.tl_sizes.size() != nodes || t.tl_owners.size() != refs)
    ThrowInput("{}: the tree's arrays differ in length", call);
  if (std::uint64_t{nodes} + refs > layout::kTlMaxElements)
    ThrowInput("{}: {} elements exceed the {} a list may hold", call, nodes + refs, layout::kTlMaxElements);
  std::vector<std::uint32_t> parent(nodes, layout::kTlNoParent), owner(refs, layout::kTlNoParent), depth(nodes, 0);
  for (std::size_t i = 0; i < nodes; ++i) {
    const glm::uvec4 l = t.tl_links[i];
    if (std::uint64_t{l.x} + l.y > nodes || std::uint64_t{l.z} + l.w > refs || (l.y > 0 && l.x <= i))
      ThrowInput("{}: input 'tl_links' element {} is out of range", call, i);
    // An empty node would be a sphere of escape 1, which reads as a triangle.
    if (l.y == 0 && l.w == 0) ThrowInput("{}: input 'tl_links' element {} is a node with no children and no triangles", call, i);
    for (std::uint32_t c = l.x; c < l.x + l.y; ++c) {
      if (parent[c] != layout::kTlNoParent) ThrowInput("{}: node {} has two parents", call, c);
      parent[c] = static_cast<std::uint32_t>(i);
      depth[c] = depth[i] + 1;
      if (depth[c] > layout::kTlMaxDepth) ThrowInput("{}: node {} lies deeper than {}", call, c, layout::kTlMaxDepth);
    }
    for (std::uint32_t j = l.z; j < l.z + l.w; ++j) {
      if (owner[j] != layout::kTlNoParent) ThrowInput("{}: triangle reference {} belongs to two nodes", call, j);
      owner[j] = static_cast<std::uint32_t>(i);
    }
  }
  if (parent != std::vector<std::uint32_t>(t.tl_parents.begin(), t.tl_parents.end()))
    ThrowInput("{}: input 'tl_parents' disagrees with 'tl_links'", call);
  if (owner != std::vector<std::uint32_t>(t.tl_owners.begin(), t.tl_owners.end()))
    ThrowInput("{}: input 'tl_owners' disagrees with 'tl_links'", call);
  std::vector<std::uint64_t> size(nodes, 0);
  for (std::size_t i = nodes; i-- > 0;) {
    const glm::uvec4 l = t.tl_links[i];
    size[i] = 1 + l.w;
    for (std::uint32_t c = l.x; c < l.x + l.y; ++c) size[i] += size[c];
    if (size[i] != t.tl_sizes[i]) ThrowInput("{}: input 'tl_sizes' element {} is {}, its subtree holds {}", call, i, t.tl_sizes[i], size[i]);
  }
  std::uint64_t rooted = 0;
  std::vector<bool> seen(nodes, false);
  for (const std::uint32_t r : t.tl_roots) {
    if (r >= nodes || parent[r] != layout::kTlNoParent || seen[r]) ThrowInput("{}: input 'tl_roots' names node {}, not a distinct root", call, r);
    seen[r] = true;
    rooted += size[r];
  }
  if (rooted != nodes + refs) ThrowInput("{}: the roots' subtrees hold {} of the {} elements", call, rooted, nodes + refs);
}

}  // namespace

void CheckInputs(const call::TlLists& c) {
  const TlTreeView& t = c.tree;
  CheckForest(c.kName, t);
  const std::size_t k = c.directions.size();
  if (!tl::ValidListCount(static_cast<std::uint32_t>(k))) ThrowInput("{}: {} directions (1, 2, 6 or 8 lists)", c.kName, k);
  if (c.order > layout::kTlOrderLatestLast) ThrowInput("{}: order {} is neither earliest-first (0) nor latest-last (1)", c.kName, c.order);
  if (c.cull > 1) ThrowInput("{}: cull {} is neither 0 nor 1", c.kName, c.cull);
  for (std::size_t j = 0; j < t.tl_triangles.size(); ++j)
    if (t.tl_triangles[j] >= t.tl_tri_words.size()) ThrowInput("{}: input 'tl_triangles' element {} is out of range", c.kName, j);
  for (std::size_t i = 0; i < t.tl_tri_words.size(); ++i) {
    const glm::uvec4 w = t.tl_tri_words[i];
    if (w.x >= t.tl_vertices.size() || w.y >= t.tl_vertices.size() || w.z >= t.tl_vertices.size())
      ThrowInput("{}: input 'tl_tri_words' element {} names a vertex out of range", c.kName, i);
    if (w.w >= t.tl_tri_words.size())
      ThrowInput("{}: input 'tl_tri_words' element {} names triangle {}, out of range [0, {})", c.kName, i, w.w, t.tl_tri_words.size());
  }
}

namespace {

void CheckLists(std::string_view call, std::span<const std::uint32_t> first, std::span<const std::uint32_t> escapes,
                std::span<const glm::uvec4> words, std::span<const glm::vec4> vertices) {
  if (first.empty()) ThrowInput("{}: input 'first' is empty", call);
  std::size_t bad = 0;
  const std::string e = tl::ListsError({first, escapes, words, vertices}, &bad);
  if (!e.empty()) ThrowInput("{}: the lists: {}", call, e);
}

void CheckTriWords(std::string_view call, std::span<const glm::uvec4> tri_words, std::size_t vertices) {
  for (std::size_t i = 0; i < tri_words.size(); ++i) {
    const glm::uvec4 w = tri_words[i];
    if (w.x >= vertices || w.y >= vertices || w.z >= vertices)
      ThrowInput("{}: input 'tri_words' element {} names a vertex out of range", call, i);
  }
}

}  // namespace

std::string WindowsError(std::span<const std::uint32_t> first, std::span<const std::uint32_t> windows, std::size_t groups,
                         std::size_t* bad) {
  const std::size_t K = first.size() - 1;
  if (windows.size() != 2 * groups * K)
    return fmt::format("{} words for {} groups (triangle cases or cells) x {} lists (2 each)", windows.size(), groups, K);
  for (std::size_t g = 0; g < windows.size() / 2; ++g) {
    const std::size_t k = g % K;
    if (windows[2 * g] > windows[2 * g + 1] || windows[2 * g] < first[k] || windows[2 * g + 1] > first[k + 1]) {
      if (bad) *bad = 2 * g;
      return fmt::format("window {} [{}, {}) is not inside its list [{}, {})", g, windows[2 * g], windows[2 * g + 1], first[k],
                         first[k + 1]);
    }
  }
  return {};
}

void CheckInputs(const call::TlHeads& c) {
  CheckLists(c.kName, c.first, c.escapes, c.words, c.vertices);
  CheckTriWords(c.kName, c.tri_words, c.vertices.size());
  if (c.mode != layout::kTlHeadsSimple && c.mode != layout::kTlHeadsRegular)
    ThrowInput("{}: mode {} is neither simple (1) nor regular (2)", c.kName, c.mode);
  if (!(c.margin >= 0.0f) || !std::isfinite(c.margin)) ThrowInput("{}: margin {} is not a finite number >= 0", c.kName, c.margin);
  if (std::uint64_t{c.tri_words.size()} * layout::kTlCases * (c.first.size() - 1) > std::uint64_t{1} << 31)
    ThrowInput("{}: {} triangles x {} lists make too many windows", c.kName, c.tri_words.size(), c.first.size() - 1);
}

void CheckInputs(const call::TlTrace& c) {
  CheckLists(c.kName, c.first, c.escapes, c.words, c.vertices);
  if (c.shadow > 1) ThrowInput("{}: shadow {} is neither 0 nor 1", c.kName, c.shadow);
  if (c.cull > 1) ThrowInput("{}: cull {} is neither 0 nor 1", c.kName, c.cull);
  if (c.heads > layout::kTlHeadsCells)
    ThrowInput("{}: heads {} is not off (0), simple (1), regular (2) or cells (3)", c.kName, c.heads);
  if (c.heads == layout::kTlHeadsOff) return;
  if (c.heads == layout::kTlHeadsCells) {
    // Per cell K windows; an eye ray naming a cell beyond them walks its whole list.
    const std::size_t K = c.first.size() - 1;
    const std::string e = c.windows.size() % (2 * K) ? fmt::format("{} words are not 2 per list of whole cells", c.windows.size())
                                                      : WindowsError(c.first, c.windows, c.windows.size() / (2 * K));
    if (!e.empty()) ThrowInput("{}: input 'windows': {}", c.kName, e);
    return;
  }
  CheckTriWords(c.kName, c.tri_words, c.vertices.size());
  const std::string e = WindowsError(c.first, c.windows, c.tri_words.size() * layout::kTlCases);
  if (!e.empty()) ThrowInput("{}: input 'windows': {}", c.kName, e);
}

void CheckInputs(const call::GridTrace& c) {
  if (c.shadow > 1) ThrowInput("{}: shadow {} is neither 0 nor 1", c.kName, c.shadow);
  if (c.closed > 1) ThrowInput("{}: closed {} is neither 0 nor 1", c.kName, c.closed);
  if (c.first.empty()) ThrowInput("{}: input 'first' is empty (it ends with the total)", c.kName);
  const std::size_t cells = c.first.size() - 1;
  for (std::size_t i = 0; i < cells; ++i)
    if (c.first[i] > c.first[i + 1]) ThrowInput("{}: input 'first' element {} is {}, above the next, {}", c.kName, i, c.first[i], c.first[i + 1]);
  if (c.first[cells] != c.cell_triangles.size())
    ThrowInput("{}: input 'first' ends at {}, not at the {} cell triangles", c.kName, c.first[cells], c.cell_triangles.size());
  for (std::size_t i = 0; i < c.cell_triangles.size(); ++i)
    if (c.cell_triangles[i] >= c.triangles.size())
      ThrowInput("{}: input 'cell_triangles' element {} names triangle {}, out of range [0, {})", c.kName, i, c.cell_triangles[i], c.triangles.size());
  if (c.min_dist.size() > cells) ThrowInput("{}: input 'min_dist' holds {} cells, more than the {} cells", c.kName, c.min_dist.size(), cells);
  if (c.boxes.size() != c.first[c.min_dist.size()])
    ThrowInput("{}: input 'boxes' holds {} rectangles, not one per reference of the {} perspective cells ({})", c.kName, c.boxes.size(),
               c.min_dist.size(), c.first[c.min_dist.size()]);
  if (c.volume.size() != 4 || c.volume_dims.size() != 1) ThrowInput("{}: inputs 'volume'/'volume_dims' do not hold 4 and 1 entries", c.kName);
  const glm::uvec4 d = c.volume_dims[0];
  const std::uint64_t regular_end = std::uint64_t{d.x} * d.y * d.z + d.w;
  if (d.x == 0 || d.y == 0 || d.z == 0 || regular_end > cells || d.w > c.min_dist.size())
    ThrowInput("{}: input 'volume_dims' ({}, {}, {} from cell {}) runs past the {} cells", c.kName, d.x, d.y, d.z, d.w, cells);
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(c.volume[0][k]) || !(c.volume[1][k] > 0.0f) || !std::isfinite(c.volume[1][k]) || !std::isfinite(c.volume[3][k]))
      ThrowInput("{}: input 'volume' is not a finite box of positive cells", c.kName);
  if (c.light_grids.size() != c.origins.size()) ThrowInput("{}: inputs 'light_grids' and 'origins' differ in length", c.kName);
  if (c.eye != layout::kGridNoLight && c.eye >= c.light_grids.size())
    ThrowInput("{}: eye {} names no entry of the {} in 'light_grids'", c.kName, c.eye, c.light_grids.size());
  if (c.secondary != layout::kGridNoLight && c.secondary >= c.light_grids.size())
    ThrowInput("{}: secondary {} names no entry of the {} in 'light_grids'", c.kName, c.secondary, c.light_grids.size());
  for (std::size_t l = 0; l < c.light_grids.size(); ++l) {
    const glm::uvec4 g = c.light_grids[l];
    if (g.x == layout::kGridNoLight) continue;
    if (g.z != 0) {  // an area light's 3D grid, after the regular grid
      const std::uint64_t need = std::uint64_t{layout::kGridFaces} * g.y * g.y * g.z;
      if (g.y == 0 || g.y > 4096u || g.z > layout::kGridMaxSlices || g.x < regular_end || g.x + need > cells)
        ThrowInput("{}: input 'light_grids' element {} (3D grid: first cell {}, {}x{}x{}) lies outside cells [{}, {})", c.kName, l, g.x, g.y,
                   g.y, g.z, regular_end, cells);
      if (std::uint64_t{g.w} + std::uint64_t{layout::kGridFaces} * (g.z + 1) > c.slices.size())
        ThrowInput("{}: input 'light_grids' element {} reads slices past the {} in 'slices'", c.kName, l, c.slices.size());
      if (!(c.origins[l].w > 0.0f) || !std::isfinite(c.origins[l].w))
        ThrowInput("{}: input 'origins' element {}: core half-side {} is not a finite number > 0", c.kName, l, c.origins[l].w);
      continue;
    }
    if (g.y == 0 || g.y > 4096u || std::uint64_t{g.x} + std::uint64_t{layout::kGridFaces} * g.y * g.y > c.min_dist.size())
      ThrowInput("{}: input 'light_grids' element {} (first cell {}, {} per side) runs past the {} perspective cells", c.kName, l, g.x, g.y,
                 c.min_dist.size());
  }
}

void CheckInputs(const call::TlCells& c) {
  CheckLists(c.kName, c.first, c.escapes, c.words, c.vertices);
  if (!(c.margin >= 0.0f) || !std::isfinite(c.margin)) ThrowInput("{}: margin {} is not a finite number >= 0", c.kName, c.margin);
  if (c.frame.dims.x == 0 || c.frame.dims.y == 0 || c.frame.dims.x > 65536u || c.frame.dims.y > 65536u)
    ThrowInput("{}: frame size {}x{} is out of range [1, 65536]", c.kName, c.frame.dims.x, c.frame.dims.y);
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(c.frame.eye[k]) || !std::isfinite(c.frame.pixel_origin[k]) || !std::isfinite(c.frame.pixel_dx[k]) ||
        !std::isfinite(c.frame.pixel_dy[k]))
      ThrowInput("{}: the frame's eye or pixel directions are not finite", c.kName);
}

}  // namespace rayspace::emu
