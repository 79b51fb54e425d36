#version 460
// tl.lists: the host's bounding-sphere tree ordered and flattened into K traversal lists, one
// invocation per (list, tree element), in four dispatches. Triangles and Nodes count, per list, the
// triangles kept below each node (all, or with back-face culling those some ray of the list's class
// may meet from the front) and the nodes left with one (integer atomics: the same sums in any
// order). Rank: the element's offset after its parent (1 + the kept subtrees of the siblings its
// parent's order puts first). Place: its position, the offsets summed up to its root, where it
// writes its escape and word. Within a dispatch no invocation reads what another writes, so the
// lists are the same for any schedule. Mirrors emu PassTlLists.
#include "common.glsl"
#define TL_FLIPPED_SPHERE_TEST false
#include "tl.glsl"

layout(std430, binding = kTlListsBindLinks) readonly buffer Links { uvec4 links[]; };
layout(std430, binding = kTlListsBindSpheres) readonly buffer Spheres { vec4 spheres[]; };
layout(std430, binding = kTlListsBindParents) readonly buffer Parents { uint parents[]; };
layout(std430, binding = kTlListsBindSizes) readonly buffer Sizes { uint sizes[]; };
layout(std430, binding = kTlListsBindRoots) readonly buffer Roots { uint roots[]; };
layout(std430, binding = kTlListsBindTriangles) readonly buffer Refs { uint refs[]; };
layout(std430, binding = kTlListsBindOwners) readonly buffer Owners { uint owners[]; };
layout(std430, binding = kTlListsBindTriWords) readonly buffer TriWords { uvec4 tri_words[]; };
layout(std430, binding = kTlListsBindVertices) readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = kTlListsBindDirections) readonly buffer Directions { vec4 directions[]; };
layout(std430, binding = kTlListsBindRel) buffer Rel { uint rel[]; };
layout(std430, binding = kTlListsBindEscapes) writeonly buffer Escapes { uint escapes[]; };
layout(std430, binding = kTlListsBindWords) writeonly buffer Words { uvec4 words[]; };
layout(std430, binding = kTlListsBindKept) buffer KeptCounts { uvec2 kept[]; };
layout(std430, binding = kTlListsBindLengths) writeonly buffer Lengths { uint lengths[]; };
layout(push_constant) uniform Block { TlListsPush pc; };

bool TriangleKept(uint k, uint ref) {
  if (pc.cull == 0u) return true;
  const uvec4 w = tri_words[refs[ref]];
  const bool culled = TlCulled(vertices[w.x].xyz, vertices[w.y].xyz, vertices[w.z].xyz, pc.lists, k);
  // Fault 4: back-face culling drops the triangles every ray of the class meets from the front.
  if (kFault == 4u) return !TlCulled(vertices[w.x].xyz, vertices[w.z].xyz, vertices[w.y].xyz, pc.lists, k);
  return !culled;
}
uint NodeSize(uint k, uint n) {
  const uvec2 x = kept[k * pc.nodes + n];
  return x.x == 0u ? 0u : x.x + x.y;
}
// Phases Triangles and Nodes: 1 added to a kept-count of `from` and of each of its ancestors.
void AddUp(uint k, uint from, uint component) {
  uint x = from;
  for (uint d = 0u; d <= kTlMaxDepth && x != kTlNoParent; ++d, x = parents[x]) {
    if (component == 0u)
      atomicAdd(kept[k * pc.nodes + x].x, 1u);
    else
      atomicAdd(kept[k * pc.nodes + x].y, 1u);
  }
}

// Sibling s of `parent`'s children: its own triangles first, then its child nodes.
uint Key(vec3 axis, uint parent, uint s) {
  const uvec4 l = links[parent];
  if (s >= l.w) return TlSphereKey(spheres[l.x + s - l.w], axis, pc.order);
  // Fault 2: a triangle keyed by its first vertex only.
  const uvec4 w = tri_words[refs[l.z + s]];
  if (kFault == 2u) return TlTriangleKey(vertices[w.x].xyz, vertices[w.x].xyz, vertices[w.x].xyz, axis, pc.order);
  return TlTriangleKey(vertices[w.x].xyz, vertices[w.y].xyz, vertices[w.z].xyz, axis, pc.order);
}
// Sibling s's kept elements in list k.
uint Size(uint k, uint parent, uint s) {
  const uvec4 l = links[parent];
  return s >= l.w ? NodeSize(k, l.x + s - l.w) : (TriangleKept(k, l.z + s) ? 1u : 0u);
}

// The kept elements of the roots before n (kTlNoParent: of all, the list's length), in blocks of
// kTlLoopBlock roots, as every loop here.
uint RootOffset(uint k, uint n) {
  uint r = 0u;
  bool found = false;
  for (uint b = 0u; !found && b < pc.roots; b += kTlLoopBlock)
    for (uint i = b; !found && i < min(pc.roots, b + kTlLoopBlock); ++i) {
      found = roots[i] == n;
      if (!found) r += NodeSize(k, roots[i]);
    }
  return r;
}

bool Kept(uint k, uint e) { return e < pc.nodes ? NodeSize(k, e) > 0u : TriangleKept(k, e - pc.nodes); }

uint Rank(uint k, uint e) {
  if (!Kept(k, e)) return 0u;
  // Fault 3: every list ordered along the first list's direction.
  const vec3 axis = directions[kFault == 3u ? 0u : k].xyz;
  uint parent, me;
  if (e < pc.nodes) {
    parent = parents[e];
    if (parent == kTlNoParent) return RootOffset(k, e);
    me = links[parent].w + (e - links[parent].x);
  } else {
    parent = owners[e - pc.nodes];
    me = e - pc.nodes - links[parent].z;
  }
  const uvec4 l = links[parent];
  const uint siblings = l.w + l.y, key = Key(axis, parent, me);
  uint r = 1u;
  for (uint b = 0u; b < siblings; b += kTlLoopBlock)
    for (uint s = b; s < min(siblings, b + kTlLoopBlock); ++s) {
      const uint ks = Key(axis, parent, s);
      if (ks < key || (ks == key && s < me)) r += Size(k, parent, s);
    }
  return r;
}

void Place(uint k, uint e, uint g) {
  const uint E = pc.nodes + pc.refs, base = k * E, length = RootOffset(k, kTlNoParent);
  if (e == 0u) lengths[k] = length;
  if (!Kept(k, e)) return;
  uint pos = rel[g];
  uint x = e < pc.nodes ? parents[e] : owners[e - pc.nodes];
  for (uint d = 0u; d <= kTlMaxDepth && x != kTlNoParent; ++d, x = parents[x]) pos += rel[base + x];
  uint escape;
  uvec4 word;
  if (e < pc.nodes) {
    word = floatBitsToUint(spheres[e]);
    // Fault 1: a sphere's escape one element short (into its own subtree's last element).
    const uint size = NodeSize(k, e);
    escape = size - (kFault == 1u ? 1u : 0u);
    if (pos + size >= length) escape = kTlEscapeNone;
  } else {
    word = tri_words[refs[e - pc.nodes]];
    escape = pos + 1u >= length ? kTlEscapeLast : 1u;
  }
  escapes[base + pos] = escape;
  words[base + pos] = word;
}

void main() {
  const uint g = GlobalIndex(), E = pc.nodes + pc.refs;
  if (g >= pc.lists * E) return;
  const uint k = g / E, e = g % E;
  if (pc.phase == kTlListsPhaseTriangles) {
    if (e >= pc.nodes && TriangleKept(k, e - pc.nodes)) AddUp(k, owners[e - pc.nodes], 0u);
  } else if (pc.phase == kTlListsPhaseNodes) {
    if (e < pc.nodes && kept[k * pc.nodes + e].x > 0u) AddUp(k, e, 1u);
  } else if (pc.phase == kTlListsPhaseRank) {
    rel[g] = Rank(k, e);
  } else {
    Place(k, e, g);
  }
}
