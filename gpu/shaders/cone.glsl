// Cone-sphere node arithmetic, the GLSL twin of emu/include/rayspace/emu/cone.h (same operations in
// the same order; see docs/hierarchy.md).
// kRadiusSlack, kAngleSlack and kTestSlack: rayspace/contract.h.

float NextUp(float x) {
  if (isnan(x) || isinf(x) && x > 0.0) return x;
  if (x == 0.0) return uintBitsToFloat(1u);
  const uint b = floatBitsToUint(x);
  return uintBitsToFloat(x > 0.0 ? b + 1u : b - 1u);
}
float NextDown(float x) { return -NextUp(-x); }

ConeNode FullSphereCone(ConeNode n) {
  n.cone = vec4(1.0, 0.0, 0.0, -1.0);
  n.extra.x = 0.0;
  return n;
}
bool IsFull(ConeNode n) { return n.cone.w <= -1.0; }

ConeNode Loosen(ConeNode n) {
  if (IsFull(n)) return n;
  const float c = n.cone.w, s = n.extra.x;
  precise const float a = kAngleSlack * s;
  precise const float cm = c - a;
  precise const float b = kAngleSlack * c;
  precise const float sp = s + b;
  const float c2 = NextDown(cm), s2 = NextUp(sp);
  if (c2 <= -1.0 || s2 < 0.0) return FullSphereCone(n);
  n.cone.w = c2;
  n.extra.x = min(1.0, s2);
  return n;
}

ConeNode EncloseDirection(ConeNode n, vec3 r) {
  if (IsFull(n)) return n;
  const vec3 x = n.cone.xyz;
  const float c = Dot3(x, r), sr = Length3(Cross3(x, r));
  precise const float inside = n.extra.x * c - n.cone.w * sr;
  if (inside >= 0.0) return n;
  n.cone.w = clamp(c, -1.0, 1.0);
  n.extra.x = min(1.0, sr);
  if (n.cone.w <= -1.0) n = FullSphereCone(n);
  return n;
}

ConeNode EncloseCone(ConeNode n, ConeNode child) {
  if (IsFull(n)) return n;
  if (IsFull(child)) return FullSphereCone(n);
  const vec3 x = n.cone.xyz, xc = child.cone.xyz;
  const float c = Dot3(x, xc), sr = Length3(Cross3(x, xc));
  precise const float cs = c * child.cone.w - sr * child.extra.x;
  precise const float ss = sr * child.cone.w + c * child.extra.x;
  if (ss < 0.0 || cs <= -1.0) return FullSphereCone(n);
  precise const float inside = n.extra.x * cs - n.cone.w * ss;
  if (inside >= 0.0) return n;
  n.cone.w = clamp(cs, -1.0, 1.0);
  n.extra.x = min(1.0, ss);
  return n;
}

ConeNode EncloseSphere(ConeNode n, vec3 c, float r) {
  precise const vec3 d = c - n.sphere.xyz;
  precise const float need = ScaledLength3(d) + r;
  if (need > n.sphere.w) n.sphere.w = need;
  return n;
}

ConeNode Finish(ConeNode n) {
  const float radius_floor = uintBitsToFloat(kRadiusFloorBits);  // 2^-122
  precise const float r = n.sphere.w * kRadiusSlack + radius_floor;
  n.sphere.w = NextUp(r);
  return Loosen(n);
}

vec4 SphereUnion(vec4 a, vec4 b) {
  precise const vec3 s = a.xyz + b.xyz;
  precise const vec3 c = s * 0.5;
  precise const vec3 d = b.xyz - a.xyz;
  precise const float r = ScaledLength3(d) * 0.5 + max(a.w, b.w);
  return vec4(c, r);
}

ConeNode GrowCone(ConeNode n, vec3 r) {
  if (IsFull(n)) return n;
  const vec3 x = n.cone.xyz;
  const float cosphi = n.cone.w, sinphi = n.extra.x;
  const float c = Dot3(x, r);
  if (c >= cosphi) return n;
  precise const vec3 qv = x * c - r;
  const float ql = Length3(qv);
  if (!(ql > 0.0)) return FullSphereCone(n);
  precise const vec3 q = vec3(Div(qv.x, ql), Div(qv.y, ql), Div(qv.z, ql));
  precise const vec3 e = x * cosphi + q * sinphi;
  precise const vec3 s = e + r;
  const float sl = Length3(s);
  if (!(sl > 0.0)) return FullSphereCone(n);
  precise const vec3 xn = vec3(Div(s.x, sl), Div(s.y, sl), Div(s.z, sl));
  n.cone = vec4(xn, min(1.0, Dot3(xn, r)));
  n.extra.x = min(1.0, Length3(Cross3(xn, r)));
  return n;
}

vec4 ConeUnion(ConeNode a, ConeNode b, out float sin_out) {
  sin_out = 0.0;
  if (IsFull(a) || IsFull(b)) return vec4(1.0, 0.0, 0.0, -1.0);
  const vec3 x1 = a.cone.xyz, x2 = b.cone.xyz;
  precise const vec3 s = x1 + x2;
  const float sl = Length3(s);
  if (!(sl > 0.0)) return vec4(1.0, 0.0, 0.0, -1.0);
  const float c = clamp(Dot3(x1, x2), -1.0, 1.0);
  precise const float chp = (1.0 + c) * 0.5;
  precise const float shp = (1.0 - c) * 0.5;
  const float ch = Sqrt(chp), sh = Sqrt(shp);
  const bool a_wider = a.cone.w <= b.cone.w;
  const float cm = a_wider ? a.cone.w : b.cone.w, sm = a_wider ? a.extra.x : b.extra.x;
  precise const float cn = ch * cm - sh * sm;
  precise const float sn = sh * cm + ch * sm;
  if (sn < 0.0) return vec4(1.0, 0.0, 0.0, -1.0);
  sin_out = sn;
  precise const vec3 axis = vec3(Div(s.x, sl), Div(s.y, sl), Div(s.z, sl));
  return vec4(axis, cn);
}

// One step of a leaf build (emu cone::GrowNode); `check` false skips the float containment checks
// (the build pass's planted fault).
ConeNode GrowNode(ConeNode old, vec3 o, vec3 r, bool check) {
  ConeNode n = old;
  n.sphere = SphereUnion(n.sphere, vec4(o, 0.0));
  n = GrowCone(n, r);
  if (check) {
    n = EncloseSphere(n, old.sphere.xyz, old.sphere.w);
    n = EncloseSphere(n, o, 0.0);
    n = EncloseCone(n, old);
    n = EncloseDirection(n, r);
  }
  n = Finish(n);
  precise const float rays = old.extra.y + 1.0;
  n.extra.y = rays;
  return n;
}

ConeNode Union(ConeNode a, ConeNode b) {
  ConeNode n;
  n.sphere = SphereUnion(a.sphere, b.sphere);
  float sn;
  n.cone = ConeUnion(a, b, sn);
  precise const float rays = a.extra.y + b.extra.y;
  n.extra = vec4(sn, rays, 0.0, 0.0);
  if (n.cone.w <= -1.0) n = FullSphereCone(n);
  return n;
}

// Does the node's ray bundle possibly meet the sphere? Mirrors emu cone::Test.
bool ConeTest(ConeNode n, vec4 sphere, float eps) {
  if (IsFull(n)) return true;
  precise const vec3 v0 = sphere.xyz - n.sphere.xyz;
  precise const float R0 = (sphere.w + n.sphere.w) * kRadiusSlack + eps;
  const float m = max(max(max(abs(v0.x), abs(v0.y)), abs(v0.z)), R0);
  if (!(m > 0.0) || !(m < uintBitsToFloat(0x7F800000u))) return true;
  const float k = InversePowerOfTwo(m);
  precise const vec3 v = vec3(v0.x * k, v0.y * k, v0.z * k);
  const vec3 x = n.cone.xyz;
  const float a = Dot3(v, x);
  const float b = Length3(Cross3(v, x));
  const float cosa = n.cone.w, sina = n.extra.x;
  precise const float s = b * cosa - a * sina;
  precise const float c = a * cosa + b * sina;
  if (s < 0.0 || (s == 0.0 && c >= 0.0)) return true;
  precise const float R = R0 * k + (abs(a) + b) * kTestSlack;
  if (c > 0.0) return s <= R;
  precise const float rr = R * R;
  return Dot3(v, v) <= rr;
}

// --cone-test printed: eq. 3.16 as the thesis prints it, emu cone::PrintedTest with the traversal's
// eps widening the sphere; the same operations in the same order, each rounded on its own (precise:
// no contraction into FMAs), so both backends keep the same pairs. Cones at or past a half-space
// (cos alpha <= 0) are kept, where the equation's division by cos alpha would flip its sense.
// `signed_axis` (kConeTestPrintedSigned): the distance along the axis without its absolute value.
bool PrintedConeTest(ConeNode n, vec4 sphere, float eps, bool signed_axis) {
  const float c = n.cone.w, s = n.extra.x;
  if (!(c > 0.0)) return true;
  precise const float r = sphere.w + eps;
  precise const vec3 v = sphere.xyz - n.sphere.xyz;
  const vec3 x = n.cone.xyz;
  const float a = Dot3(v, x);
  precise const vec3 off = v - x * a;
  precise const float reach = n.sphere.w + r;
  precise const float lhs = (signed_axis ? a : abs(a)) * Div(s, c) + Div(reach, c);
  return lhs >= Length3(off);
}

// The test the push block's cone_test names (kConeTestConservative, kConeTestPrinted or
// kConeTestPrintedSigned).
bool ConeTestBy(uint cone_test, ConeNode n, vec4 sphere, float eps) {
  return cone_test == kConeTestConservative ? ConeTest(n, sphere, eps) : PrintedConeTest(n, sphere, eps, cone_test == kConeTestPrintedSigned);
}
