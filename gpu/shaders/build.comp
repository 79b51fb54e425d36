#version 460
// Hierarchy build: phase 0 makes level-1 nodes from sorted rays (eqs. 3.8-3.11, 3.14-3.15), phase 1
// makes a level from the one below (eqs. 3.12-3.15); mirrors emu PassBuildLeaves / PassBuildParents.
#include "common.glsl"
#include "cone.glsl"

layout(std430, binding = 0) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = 1) readonly buffer Order { uint order[]; };
layout(std430, binding = 2) readonly buffer First { uint first[]; };
layout(std430, binding = 3) readonly buffer Below { ConeNode below[]; };
layout(std430, binding = 4) writeonly buffer Nodes { ConeNode nodes[]; };
layout(push_constant) uniform Push { uint count; uint phase; } pc;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  const uint f0 = first[i], f1 = first[i + 1u];
  ConeNode n;
  if (pc.phase == 0u) {
    const Ray r0 = rays[order[f0]];
    n.sphere = vec4(r0.origin_tmin.xyz, 0.0);
    n.cone = vec4(Normalize3(r0.direction_tmax.xyz), 1.0);
    n.extra = vec4(0.0, 1.0, 0.0, 0.0);
    n = Finish(n);
    for (uint j = f0 + 1u; j < f1; ++j) {
      const Ray r = rays[order[j]];
      // Fault 1: the float containment checks of each step are skipped.
      n = GrowNode(n, r.origin_tmin.xyz, Normalize3(r.direction_tmax.xyz), kFault != 1u);
    }
    nodes[i] = n;
    return;
  } else {
    n = below[f0];
    for (uint j = f0 + 1u; j < f1; ++j) n = Union(n, below[j]);
    for (uint j = f0; j < f1; ++j) {
      n = EncloseSphere(n, below[j].sphere.xyz, below[j].sphere.w);
      n = EncloseCone(n, below[j]);
    }
  }
  nodes[i] = Finish(n);
}
