#version 460
// Hierarchy build: phase Leaves makes level-1 nodes from sorted rays (eqs. 3.8-3.11, 3.14-3.15),
// Parents makes a level from the one below (eqs. 3.12-3.15); mirrors emu PassBuildLeaves / PassBuildParents.
#include "common.glsl"
#include "cone.glsl"
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

void main() {
  const uint i = GlobalIndex();
  if (i >= pc.count) return;
  const uint f0 = first[i], f1 = first[i + 1u];
  ConeNode n;
  if (pc.phase == kBuildPhaseLeaves) {
    const Ray r0 = RayAt(f0);
    n.sphere = vec4(r0.origin_tmin.xyz, 0.0);
    n.cone = vec4(Normalize3(r0.direction_tmax.xyz), 1.0);
    n.extra = vec4(0.0, 1.0, 0.0, 0.0);
    n = Finish(n);
    for (uint j = f0 + 1u; j < f1; ++j) {
      const Ray r = RayAt(j);
      // Fault 1: the float containment checks of each step are skipped.
      n = GrowNode(n, r.origin_tmin.xyz, Normalize3(r.direction_tmax.xyz), kFault != 1u);
    }
    nodes[i] = n;
    return;
  } else {
    n = BelowAt(f0);
    for (uint j = f0 + 1u; j < f1; ++j) n = Union(n, BelowAt(j));
    for (uint j = f0; j < f1; ++j) {
      const ConeNode b = BelowAt(j);
      n = EncloseSphere(n, b.sphere.xyz, b.sphere.w);
      n = EncloseCone(n, b);
    }
  }
  nodes[i] = Finish(n);
}
