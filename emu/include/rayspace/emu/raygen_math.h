// Per-ray math of the ray generation passes (thesis eqs. 3.1-3.7), templated over the scalar like
// intersect.h: float in the emulated passes, verify::SpecReal when the diff bounds what a device may
// compute. Each returns false when the surface spawns no ray.
#pragma once
#include <limits>

#include "rayspace/emu/intersect.h"

namespace rayspace::emu {

template <typename S>
bool Finite3(Vec3<S> v) {
  const S max(std::numeric_limits<float>::max());
  return Abs(v.x) <= max && Abs(v.y) <= max && Abs(v.z) <= max;
}

// Shadow ray from the light at o towards the point p: unit direction d and distance dist (eqs. 3.1-3.2).
template <typename S>
bool ShadowDirection(Vec3<S> p, Vec3<S> o, Vec3<S>& d, S& dist) {
  const Vec3<S> v = p - o;
  dist = Length(v);
  if (!(dist > S(0.0f)) || !Finite3(v)) return false;  // light on the point: no direction
  d = Vec3<S>(v.x / dist, v.y / dist, v.z / dist);
  return true;
}

// --shadow-rule lit: whether the light lies in front of the surface, n.l > 0, with the shading
// normal n turned to the side the ray arrived on (`view`, the incoming direction) and l = -d, the unit
// vector to the light. Exactly the test the shade pass makes before it lights a point (shade_math.h):
// -d is bit for bit the shade pass's l, so a ray this test drops would have added nothing.
template <typename S>
bool LightInFront(Vec3<S> d, Vec3<S> n, Vec3<S> view) {
  if (Dot(n, view) > S(0.0f)) n = -n;
  return Dot(-d, n) > S(0.0f);
}

// Mirror direction i - 2 n (n.i) (eq. 3.4).
template <typename S>
Vec3<S> ReflectionDirection(Vec3<S> i, Vec3<S> n) {
  const S ni = Dot(n, i);
  const S k = S(2.0f) * ni;
  return Vec3<S>(i.x - n.x * k, i.y - n.y * k, i.z - n.z * k);
}

// Refracted direction for relative index `ior` (eqs. 3.6-3.7); false on total internal reflection.
// Entering when the ray meets the normal's front side; leaving flips the normal and the ratio.
template <typename S>
bool RefractionDirection(Vec3<S> i, Vec3<S> n, S ior, Vec3<S>& d) {
  S cosi = Dot(i, n);
  S ri = S(1.0f) / ior;
  if (cosi > S(0.0f)) {
    n = -n;
    cosi = -cosi;
    ri = ior;
  }
  const S k = S(1.0f) - (ri * ri) * (S(1.0f) - cosi * cosi);
  if (k < S(0.0f)) return false;
  const S a = ri * cosi + Sqrt(k);
  d = Vec3<S>(i.x * ri - n.x * a, i.y * ri - n.y * a, i.z * ri - n.z * a);
  return true;
}

}  // namespace rayspace::emu
