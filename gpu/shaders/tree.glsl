// The joint descent's shared code (tree_roots, tree_expand, tree_test, tree_step; mirrors
// emu/src/object_tree_traverse.cpp): the bindings of rayspace/contract.h's kTreeBind*, a pair's
// expansion into its candidates, the side test SplitCone and the counters. Include after common.glsl
// and cone.glsl. A kernel plants its expansion faults by defining TREE_FAULT_NO_OWN_TRIS,
// TREE_FAULT_NO_LAST_CONE_CHILD and TREE_FAULT_NO_SPLIT (booleans) first.
#ifndef TREE_FAULT_NO_OWN_TRIS
#define TREE_FAULT_NO_OWN_TRIS false
#endif
#ifndef TREE_FAULT_NO_LAST_CONE_CHILD
#define TREE_FAULT_NO_LAST_CONE_CHILD false
#endif
#ifndef TREE_FAULT_NO_SPLIT
#define TREE_FAULT_NO_SPLIT false
#endif

layout(std430, binding = kTreeBindConeNodes) readonly buffer ConeNodes { ConeNode cone_nodes[]; };
layout(std430, binding = kTreeBindConeBase) readonly buffer ConeBase { uint cone_base[]; };
layout(std430, binding = kTreeBindConeFirst) readonly buffer ConeFirst { uint cone_first[]; };
layout(std430, binding = kTreeBindSpheres) readonly buffer Spheres { vec4 tree_spheres[]; };
layout(std430, binding = kTreeBindLinks) readonly buffer Links { uvec4 tree_links[]; };
layout(std430, binding = kTreeBindDepth) readonly buffer Depth { uint tree_depth[]; };
layout(std430, binding = kTreeBindRoots) readonly buffer Roots { uint tree_roots[]; };
layout(std430, binding = kTreeBindTriSpheres) readonly buffer TriSpheres { vec4 tree_tri_spheres[]; };
layout(std430, binding = kTreeBindPairCone) readonly buffer PairCone { uint pair_cone[]; };
layout(std430, binding = kTreeBindPairItem) readonly buffer PairItem { uint pair_item[]; };
layout(std430, binding = kTreeBindOffsets) buffer Offsets { uint offsets[]; };
layout(std430, binding = kTreeBindFlags) buffer Flags { uint flags[]; };
layout(std430, binding = kTreeBindOutCone) buffer OutCone { uint out_cone[]; };
layout(std430, binding = kTreeBindOutItem) buffer OutItem { uint out_item[]; };
layout(std430, binding = kTreeBindCounters) buffer Counters { uint counters[]; };
layout(push_constant) uniform Block { TreePush pc; };

uint LevelOf(uint cone) { return cone >> kTreeLevelShift; }
uint NodeOf(uint cone) { return cone & kTreeNodeMask; }
uint ConeOf(uint level, uint node) { return (level << kTreeLevelShift) | node; }
bool IsTriangle(uint item) { return (item & kTreeItemTriangle) != 0u; }
ConeNode TreeCone(uint level, uint n) { return cone_nodes[cone_base[level] + n]; }
uint TreeFirst(uint level, uint n) { return cone_first[cone_base[level] + level + n]; }
vec4 SphereOf(uint item) { return IsTriangle(item) ? tree_tri_spheres[item & ~kTreeItemTriangle] : tree_spheres[item]; }
// 2 when the pair is final (a level-1 node or a ray with a triangle), else 1.
uint KindOf(uint cone, uint item) { return IsTriangle(item) && LevelOf(cone) <= 1u ? 2u : 1u; }

// emu SplitCone: refine the cone side? d^2 sin^2 > ((R - r) cos)^2, no contraction.
bool SplitCone(ConeNode n, vec4 o) {
  const float cosa = n.cone.w, sina = n.extra.x;
  if (!(cosa > 0.0)) return true;
  precise const float rhs = (o.w - n.sphere.w) * cosa;
  if (rhs < 0.0) return true;
  precise const float dx = o.x - n.sphere.x, dy = o.y - n.sphere.y, dz = o.z - n.sphere.z;
  precise const float d2 = (dx * dx + dy * dy) + dz * dz;
  precise const float lhs = d2 * (sina * sina);
  precise const float rr = rhs * rhs;
  return lhs > rr;
}

// A pair's candidates: the cone side's children [k0, k1) of `level`, or the object side's child
// nodes [k0, k1) then own triangles [t0, t1), tested against the cone at `level`.
struct Expansion {
  bool cone_side;
  uint level, k0, k1, t0, t1;
};
uint CountOf(Expansion e) { return (e.k1 - e.k0) + (e.t1 - e.t0); }

Expansion Expand(uint cone, uint item) {
  const uint L = LevelOf(cone), n = NodeOf(cone);
  Expansion e;
  const bool split = L > 0u && !TREE_FAULT_NO_SPLIT && SplitCone(TreeCone(L, n), tree_spheres[IsTriangle(item) ? 0u : item]);
  if (IsTriangle(item) || split) {
    const uint k0 = TreeFirst(L, n), k1 = TreeFirst(L, n + 1u);
    e.cone_side = true;
    e.level = L - 1u;
    e.k0 = k0;
    e.k1 = TREE_FAULT_NO_LAST_CONE_CHILD && k1 > k0 ? k1 - 1u : k1;
    e.t0 = 0u;
    e.t1 = 0u;
    return e;
  }
  const uvec4 o = tree_links[item];
  e.cone_side = false;
  e.level = L;
  e.k0 = o.x;
  e.k1 = o.x + o.y;
  e.t0 = o.z;
  e.t1 = o.z + (TREE_FAULT_NO_OWN_TRIS ? 0u : o.w);
  return e;
}

// Candidate k of pair (cone, item) under e.
uvec2 Candidate(Expansion e, uint cone, uint item, uint k) {
  if (e.cone_side) return uvec2(ConeOf(e.level, e.k0 + k), item);
  const uint nodes = e.k1 - e.k0;
  return uvec2(cone, k < nodes ? e.k0 + k : kTreeItemTriangle | (e.t0 + k - nodes));
}

bool TestCandidate(uvec2 c) { return ConeTest(TreeCone(LevelOf(c.x), NodeOf(c.x)), SphereOf(c.y), pc.eps); }

// Adds `tests` and `hits` of candidates like c (one cone level, one object-node depth or the
// triangle spheres) to the counters.
void AddCounts(uvec2 c, uint tests, uint hits) {
  if (tests == 0u) return;
  const uint L = LevelOf(c.x), base = 2u * pc.levels;
  atomicAdd(counters[L], tests);
  if (hits != 0u) atomicAdd(counters[pc.levels + L], hits);
  const uint at = IsTriangle(c.y) ? base + 2u * pc.depths : base + tree_depth[c.y];
  const uint stride = IsTriangle(c.y) ? 1u : pc.depths;
  atomicAdd(counters[at], tests);
  if (hits != 0u) atomicAdd(counters[at + stride], hits);
}
