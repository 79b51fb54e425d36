// The fused top level's group reject in float, the twin of emu cone::DeviceGroupMisses and its helpers
// (emu/include/rayspace/emu/cone_cull.h): the same operations in the same order, so both sides cull
// the same groups. Why it is conservative, with margins for any conformant device's rounding, is
// docs/performance.md, "Group culling on the device". Needs common.glsl (Dot3, ConeNode, Sqrt: exact
// under --strict-math).

bool DeviceCullable(vec4 s) {
  return abs(s.x) < kDeviceCullLimit && abs(s.y) < kDeviceCullLimit && abs(s.z) < kDeviceCullLimit && s.w >= 0.0 &&
         s.w < kDeviceCullLimit;
}

float DeviceReach(vec4 s, vec3 c) {
  precise const vec3 d = s.xyz - c;
  precise const float r = Sqrt(Dot3(d, d)) + s.w;
  return r;
}

bool DeviceCullableNode(ConeNode n) {
  precise const float axis2 = Dot3(n.cone.xyz, n.cone.xyz);
  precise const float angle2 = n.cone.w * n.cone.w + n.extra.x * n.extra.x;
  return DeviceCullable(n.sphere) && n.cone.w > -1.0 && abs(axis2 - 1.0) <= kDeviceCullUnit &&
         abs(angle2 - 1.0) <= kDeviceCullUnit;
}

// True only if ConeTest(n, s, eps) is false for every sphere s with |s - group.xyz| + s.w <= group.w.
// Fault 5 of traverse_compact.comp: the margin planted at -1/2, which culls groups the test hits.
bool DeviceGroupMisses(ConeNode n, vec4 group, float eps) {
  if (!DeviceCullableNode(n) || !DeviceCullable(group) || !(abs(eps) < kDeviceCullLimit)) return false;
  precise const vec3 v = group.xyz - n.sphere.xyz;
  const vec3 x = n.cone.xyz;
  const float a = Dot3(v, x);
  const vec3 c = Cross3(v, x);
  precise const float b = Sqrt(Dot3(c, c));
  precise const float f = b * n.cone.w - a * n.extra.x;
  precise const float len = Sqrt(Dot3(v, v));
  const float margin = kFault == 5u ? -0.5 : kDeviceCullMargin;
  precise const float bound = (group.w + n.sphere.w + abs(eps)) * (1.0 + margin) + margin * len + kDeviceCullFloor;
  return f > bound;
}
