// The watertight ray-triangle test of the final intersection kernels (intersect, intersect_tree);
// mirrors emu IntersectWatertight. Include after common.glsl; a kernel names the fault number that
// swaps tmin and tmax in the range check as WATERTIGHT_SWAP_FAULT first.
// det_out: the sheared triangle's signed area, positive when the ray meets the front (the side
// (v1 - v0) x (v2 - v0) points to).
bool WatertightSided(vec3 org, vec3 dir, vec3 v0, vec3 v1, vec3 v2, float tmin, float tmax, out float t_out, out float det_out) {
  det_out = 0.0;
  const vec3 a = abs(dir);
  int kz = 0;
  if (a.y > a[kz]) kz = 1;
  if (a.z > a[kz]) kz = 2;
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (dir[kz] < 0.0) {
    const int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  precise const float sx = Div(dir[kx], dir[kz]), sy = Div(dir[ky], dir[kz]);
  precise const vec3 A0 = v0 - org, B0 = v1 - org, C0 = v2 - org;
  const float ka = InversePowerOfTwo(max(MaxAbs(A0, B0), MaxAbs(C0, C0)));
  precise const vec3 A = A0 * ka, B = B0 * ka, C = C0 * ka;
  precise const float ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
  precise const float bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
  precise const float cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
  precise const float u = cx * by - cy * bx;
  precise const float v = ax * cy - ay * cx;
  precise const float w = bx * ay - by * ax;
  if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return false;
  precise const float det = (u + v) + w;
  if (det == 0.0) return false;
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0;
  const float ke = InversePowerOfTwo(MaxAbs(e1, e2));
  const vec3 n0 = Cross3(e1 * ke, e2 * ke);
  const float kn = InversePowerOfTwo(MaxAbs(n0, n0));
  precise const vec3 n = n0 * kn;
  precise const float t0 = Div(Dot3(A0, n), Dot3(dir, n));
  // kFaultUlp4: t four ULP too far, beyond what any conformant device computes.
  const float t = kFault == kFaultUlp4 ? uintBitsToFloat(floatBitsToUint(t0) + 4u) : t0;
  // WATERTIGHT_SWAP_FAULT: tmin and tmax swapped in the range check (every hit rejected).
  if (kFault == WATERTIGHT_SWAP_FAULT ? !(t > tmax && t < tmin) : !(t > tmin && t < tmax)) return false;
  t_out = t;
  det_out = det;
  return true;
}

bool Watertight(vec3 org, vec3 dir, vec3 v0, vec3 v1, vec3 v2, float tmin, float tmax, out float t_out) {
  float det;
  return WatertightSided(org, dir, v0, v1, v2, tmin, tmax, t_out, det);
}
