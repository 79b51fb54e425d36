#version 460
// Hierarchy build: phase Leaves makes level-1 nodes from sorted rays (eqs. 3.8-3.11, 3.14-3.15),
// Parents makes a level from the one below (eqs. 3.12-3.15); mirrors emu PassBuildLeaves / PassBuildParents.
// A node is a fold over its rays or children in order (float operations do not reassociate, so the
// order is part of the node's bits): a subgroup builds one node, its lanes fetch the inputs in
// parallel and every lane runs the same fold over them.
#include "common.glsl"
#include "cone.glsl"
#include "workgroup.glsl"
#extension GL_KHR_shader_subgroup_shuffle : require
#include "paged.glsl"

// This dispatch builds nodes base .. base + count - 1 of the level: first and nodes hold just those
// (first one more); rays, order and the level below are read anywhere, so they are paged.
layout(std430, binding = kBuildBindFirst) readonly buffer First { uint first[]; };
layout(std430, binding = kBuildBindNodes) writeonly buffer Nodes { ConeNode nodes[]; };
PAGED_BUFFER(readonly, Rays, Ray, kBuildBindRays)
PAGED_LOAD(Rays, Ray)
PAGED_BUFFER(readonly, Order, uint, kBuildBindOrder)
PAGED_LOAD(Order, uint)
PAGED_BUFFER(readonly, Below, ConeNode, kBuildBindBelow)
PAGED_LOAD(Below, ConeNode)
layout(push_constant) uniform Block { BuildPush pc; };

Ray RayAt(uint sorted) { return LoadRays(LoadOrder(sorted, pc.order_page), pc.ray_page); }
ConeNode BelowAt(uint j) { return LoadBelow(j, pc.below_page); }

// The lanes of this subgroup that hold an invocation: fewer in a partial subgroup, and not
// necessarily the first ones (Vulkan promises neither unless full subgroups are required). Lanes
// fetch by their rank among them, and a fold takes the k-th fetch from the k-th active lane.
uint SubgroupLanes() { return subgroupBallotBitCount(subgroupBallot(true)); }
uint LaneRank() { return subgroupBallotExclusiveBitCount(subgroupBallot(true)); }
// The next active lane in lane order: `rest` starts as subgroupBallot(true) and loses its lowest bit.
uint NextLane(inout uvec4 rest) {
  const uint lane = subgroupBallotFindLSB(rest);
  rest[lane >> 5u] &= ~(1u << (lane & 31u));
  return lane;
}

ConeNode ShuffleNode(ConeNode n, uint lane) {
  ConeNode m;
  m.sphere = subgroupShuffle(n.sphere, lane);
  m.cone = subgroupShuffle(n.cone, lane);
  m.extra = subgroupShuffle(n.extra, lane);
  return m;
}

// A leaf over rays f0 .. f1 - 1 (sorted order): the lanes fetch and normalise `lanes` rays at a time
// (the paged, indirect loads), and every lane folds them in ray order from subgroupShuffle, so every
// lane holds the node the incremental build (eqs. 3.8-3.11) defines.
ConeNode Leaf(uint f0, uint f1, uint lanes) {
  ConeNode n;
  for (uint j0 = f0; j0 < f1; j0 += lanes) {
    const uint j = j0 + LaneRank();
    vec3 o = vec3(0.0), r = vec3(0.0);
    if (j < f1) {
      const Ray ray = RayAt(j);
      o = ray.origin_tmin.xyz;
      r = Normalize3(ray.direction_tmax.xyz);
    }
    const uint m = min(lanes, f1 - j0);
    uvec4 rest = subgroupBallot(true);
    uint before = 0u;
    for (uint k = 0u; k < m; ++k) {
      const uint lane = NextLane(rest);
      // Fault 2: each ray is grown with its predecessor's origin (a lane off by one).
      const vec3 ok = subgroupShuffle(o, kFault == 2u && k > 0u ? before : lane), rk = subgroupShuffle(r, lane);
      before = lane;
      if (j0 + k == f0) {
        n.sphere = vec4(ok, 0.0);
        n.cone = vec4(rk, 1.0);
        n.extra = vec4(0.0, 1.0, 0.0, 0.0);
        n = Finish(n);
      } else {
        // Fault 1: the float containment checks of each step are skipped.
        n = GrowNode(n, ok, rk, kFault != 1u);
      }
    }
  }
  return n;
}

// --child-merge pairwise (emu cone::PairwiseUnion): a stack of partial unions as a binary counter;
// the two newest merge (older first) while they hold equally many children.
ConeNode stack_nodes[33];
uint stack_held[33];
int stack_top = -1;

void PushChild(ConeNode c) {
  ++stack_top;
  stack_nodes[stack_top] = c;
  stack_held[stack_top] = 1u;
  while (stack_top >= 1 && stack_held[stack_top] == stack_held[stack_top - 1]) {
    stack_nodes[stack_top - 1] = Union(stack_nodes[stack_top - 1], stack_nodes[stack_top]);
    stack_held[stack_top - 1] *= 2u;
    --stack_top;
  }
}

// The partial unions left, folded newest first into the older ones.
ConeNode FoldStack() {
  ConeNode n = stack_nodes[stack_top];
  for (int i = stack_top - 1; i >= 0; --i) n = Union(stack_nodes[i], n);
  return n;
}

// A parent over children f0 .. f1 - 1 of the level below: their union in order (one after another,
// or pairwise), then every child enclosed in order (eqs. 3.12-3.15); the lanes fetch the children,
// every lane folds.
ConeNode Parent(uint f0, uint f1, uint lanes) {
  ConeNode n;
  const bool pairwise = pc.child_merge == kChildMergePairwise && f1 > f0 + 1u;
  stack_top = -1;
  for (uint pass = 0u; pass < 2u; ++pass) {
    if (pass == 1u && pairwise) n = FoldStack();
    for (uint j0 = f0; j0 < f1; j0 += lanes) {
      const uint j = j0 + LaneRank();
      ConeNode b;
      b.sphere = b.cone = b.extra = vec4(0.0);
      if (j < f1) b = BelowAt(j);
      const uint m = min(lanes, f1 - j0);
      uvec4 rest = subgroupBallot(true);
      for (uint k = 0u; k < m; ++k) {
        const ConeNode bk = ShuffleNode(b, NextLane(rest));
        if (pass == 0u && pairwise) {
          PushChild(bk);
        } else if (pass == 0u) {
          n = j0 + k == f0 ? bk : Union(n, bk);
        } else {
          n = EncloseSphere(n, bk.sphere.xyz, bk.sphere.w);
          n = EncloseCone(n, bk);
        }
      }
    }
  }
  return Finish(n);
}

// One subgroup per node, grid-stride over the dispatch's nodes: a workgroup takes SubgroupSlots()
// nodes whatever subgroups the device launched (any past them idle).
void main() {
  const uint lanes = SubgroupLanes(), slots = SubgroupSlots();
  const uint stride = gl_NumWorkGroups.x * gl_NumWorkGroups.y * slots;
  for (uint i = WorkGroupIndex() * slots + gl_SubgroupID; gl_SubgroupID < slots && i < pc.count; i += stride) {
    const uint f0 = first[i], f1 = first[i + 1u];
    // Fault 3: a parent leaves out its last child; fault 4: a leaf drops its last ray (lost tails).
    const bool lost_tail = kFault == (pc.phase == kBuildPhaseLeaves ? 4u : 3u) && f1 > f0 + 1u;
    const uint end = lost_tail ? f1 - 1u : f1;
    const ConeNode n = pc.phase == kBuildPhaseLeaves ? Leaf(f0, end, lanes) : Parent(f0, end, lanes);
    if (subgroupElect()) nodes[i] = n;
  }
}
