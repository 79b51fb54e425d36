#version 460
// tl.lists: the host's bounding-sphere tree ordered and flattened into K traversal lists, one
// invocation per (list, tree element), in two dispatches. Rank: the element's offset after its parent
// (1 + the subtrees of the siblings its parent's order puts first). Place: its position, the offsets
// summed up to its root, where it writes its escape and word. No invocation waits on another within
// a dispatch, so the lists are the same for any schedule. Mirrors emu PassTlLists.
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
layout(push_constant) uniform Block { TlListsPush pc; };

// Sibling s of `parent`'s children: its own triangles first, then its child nodes.
uint Key(vec3 axis, uint parent, uint s) {
  const uvec4 l = links[parent];
  if (s >= l.w) return TlSphereKey(spheres[l.x + s - l.w], axis, pc.order);
  // Fault 2: a triangle keyed by its first vertex only.
  const uvec4 w = tri_words[refs[l.z + s]];
  if (kFault == 2u) return TlTriangleKey(vertices[w.x].xyz, vertices[w.x].xyz, vertices[w.x].xyz, axis, pc.order);
  return TlTriangleKey(vertices[w.x].xyz, vertices[w.y].xyz, vertices[w.z].xyz, axis, pc.order);
}
uint Size(uint parent, uint s) {
  const uvec4 l = links[parent];
  return s >= l.w ? sizes[l.x + s - l.w] : 1u;
}

// In blocks of kTlLoopBlock roots, as every loop here.
uint RootOffset(uint n) {
  uint r = 0u;
  bool found = false;
  for (uint b = 0u; !found && b < pc.roots; b += kTlLoopBlock)
    for (uint i = b; !found && i < min(pc.roots, b + kTlLoopBlock); ++i) {
      found = roots[i] == n;
      if (!found) r += sizes[roots[i]];
    }
  return r;
}

uint Rank(uint k, uint e) {
  // Fault 3: every list ordered along the first list's direction.
  const vec3 axis = directions[kFault == 3u ? 0u : k].xyz;
  uint parent, me;
  if (e < pc.nodes) {
    parent = parents[e];
    if (parent == kTlNoParent) return RootOffset(e);
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
      if (ks < key || (ks == key && s < me)) r += Size(parent, s);
    }
  return r;
}

void Place(uint k, uint e, uint g) {
  const uint E = pc.nodes + pc.refs, base = k * E;
  uint pos = rel[g];
  uint x = e < pc.nodes ? parents[e] : owners[e - pc.nodes];
  for (uint d = 0u; d <= kTlMaxDepth && x != kTlNoParent; ++d, x = parents[x]) pos += rel[base + x];
  uint escape;
  uvec4 word;
  if (e < pc.nodes) {
    word = floatBitsToUint(spheres[e]);
    // Fault 1: a sphere's escape one element short (into its own subtree's last element).
    escape = sizes[e] - (kFault == 1u ? 1u : 0u);
    if (pos + sizes[e] >= E) escape = kTlEscapeNone;
  } else {
    word = tri_words[refs[e - pc.nodes]];
    escape = pos + 1u >= E ? kTlEscapeLast : 1u;
  }
  escapes[base + pos] = escape;
  words[base + pos] = word;
}

void main() {
  const uint g = GlobalIndex(), E = pc.nodes + pc.refs;
  if (g >= pc.lists * E) return;
  const uint k = g / E, e = g % E;
  if (pc.phase == kTlListsPhaseRank)
    rel[g] = Rank(k, e);
  else
    Place(k, e, g);
}
