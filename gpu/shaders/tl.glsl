// Shared by the traversal-list kernels (tl_lists.comp, tl_trace.comp): the keys that order a node's
// children and the walk's sphere test and list choice, each mirroring its emulator function in
// emu/src/tl.cpp operation for operation. Include after common.glsl.

// A float as an unsigned integer of the same order (-0 before +0), a NaN after everything (emu Ordered).
uint OrderedKey(float f) {
  if (isnan(f)) return 0xFFFFFFFFu;
  const uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}

uint TlSphereKey(vec4 s, vec3 axis, uint order) {
  const float p = Dot3(s.xyz, axis);
  precise const float k = order == kTlOrderEarliestFirst ? p - s.w : p + s.w;
  return OrderedKey(k);
}

// min and max by comparisons in a fixed order (GLSL's min/max leave NaN operands open).
uint TlTriangleKey(vec3 v0, vec3 v1, vec3 v2, vec3 axis, uint order) {
  const float p1 = Dot3(v1, axis), p2 = Dot3(v2, axis);
  float k = Dot3(v0, axis);
  if (order == kTlOrderEarliestFirst) {
    if (p1 < k) k = p1;
    if (p2 < k) k = p2;
  } else {
    if (p1 > k) k = p1;
    if (p2 > k) k = p2;
  }
  return OrderedKey(k);
}

// The list of a ray's direction class among K lists (emu tl::ListFor).
uint TlListFor(uint K, vec3 d) {
  if (K == 2u) return d.x < 0.0 ? 1u : 0u;
  if (K == 6u) {
    const vec3 a = abs(d);
    int k = 0;
    if (a.y > a[k]) k = 1;
    if (a.z > a[k]) k = 2;
    return uint(2 * k) + (d[k] < 0.0 ? 1u : 0u);
  }
  if (K == 8u) return (d.x < 0.0 ? 1u : 0u) | (d.y < 0.0 ? 2u : 0u) | (d.z < 0.0 ? 4u : 0u);
  return 0u;
}

// May the ray's part [tmin, tlimit] meet the sphere, conservatively (emu tl::SphereMayHit)?
// TL_FLIPPED_SPHERE_TEST plants the flipped distance test.
bool TlSphereMayHit(vec3 org, vec3 dir, float tmin, float tlimit, vec4 s) {
  const float len = Length3(dir);
  precise const vec3 v = s.xyz - org;
  const vec3 u = vec3(Div(dir.x, len), Div(dir.y, len), Div(dir.z, len));
  const float a = Dot3(v, u), b = Length3(Cross3(v, u));
  if (isnan(a) || isinf(a) || isnan(b) || isinf(b)) return true;
  precise const float r = (s.w * kRadiusSlack + (abs(a) + b) * kTestSlack) + uintBitsToFloat(kRadiusFloorBits);
  if (TL_FLIPPED_SPHERE_TEST ? b < r : b > r) return false;
  precise const float t0 = tmin * len, t1 = tlimit * len;
  precise const float lo = t0 - abs(t0) * kTestSlack, hi = t1 + abs(t1) * kTestSlack;
  precise const float near = a + r, far = a - r;
  if (near < lo) return false;
  return !(far > hi);
}

// Back-face culling's test (emu tl::Culled): may list k of K drop the triangle, every direction of
// its class meeting its back, with a margin for the float normal's rounding?
bool TlCulled(vec3 v0, vec3 v1, vec3 v2, uint K, uint k) {
  if (K != 6u && K != 8u) return false;
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0;
  const vec3 n = Cross3(e1, e2);
  precise const float m = kTlCullMargin * (MaxAbs(e1, e1) * MaxAbs(e2, e2));
  if (!(m >= uintBitsToFloat(0x0D800000u) && m <= uintBitsToFloat(0x71800000u))) return false;  // 2^-100, 2^100
  if (K == 8u) {
    const float sx = (k & 1u) != 0u ? -n.x : n.x, sy = (k & 2u) != 0u ? -n.y : n.y, sz = (k & 4u) != 0u ? -n.z : n.z;
    return sx > m && sy > m && sz > m;
  }
  const uint a = k / 2u, b = a == 2u ? 0u : a + 1u, c = b == 2u ? 0u : b + 1u;
  const float na = (k & 1u) != 0u ? -n[a] : n[a];
  precise const float side = na - (abs(n[b]) + abs(n[c]));
  precise const float m3 = 3.0 * m;
  return side > m3;
}

// The facet normals of list k's direction class (emu tl::Facets): 2 lists: the signed x axis; 8: the
// three signed axes; 6: s e_a +- e_b and s e_a +- e_c; 1: none. Returns how many.
uint TlFacets(uint count, uint k, out vec3 m[4]) {
  if (count == 2u) {
    m[0] = vec3(k == 1u ? -1.0 : 1.0, 0.0, 0.0);
    return 1u;
  }
  if (count == 8u) {
    m[0] = vec3((k & 1u) != 0u ? -1.0 : 1.0, 0.0, 0.0);
    m[1] = vec3(0.0, (k & 2u) != 0u ? -1.0 : 1.0, 0.0);
    m[2] = vec3(0.0, 0.0, (k & 4u) != 0u ? -1.0 : 1.0);
    return 3u;
  }
  if (count != 6u) return 0u;
  const uint a = k / 2u, b = a == 2u ? 0u : a + 1u, c = b == 2u ? 0u : b + 1u;
  const float s = (k & 1u) != 0u ? -1.0 : 1.0;
  for (uint j = 0u; j < 4u; ++j) {
    vec3 v = vec3(0.0);
    v[a] = s;
    v[j < 2u ? b : c] = (j & 1u) != 0u ? -1.0 : 1.0;
    m[j] = v;
  }
  return 4u;
}

// The least (starting rays) or greatest (ending rays) of the triangle's projections on m, by
// comparisons in vertex order (emu tl::FacetBound).
float TlFacetBound(vec3 m, vec3 v0, vec3 v1, vec3 v2, bool ends) {
  const float a = Dot3(m, v0), b = Dot3(m, v1), d = Dot3(m, v2);
  float x = a;
  if (ends ? b > x : b < x) x = b;
  if (ends ? d > x : d < x) x = d;
  return x;
}
