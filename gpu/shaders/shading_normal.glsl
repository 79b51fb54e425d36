// Shared by the raster fragment stage and the hit-surface kernel; needs Dot3, Cross3, Normalize3,
// MaxAbs and InversePowerOfTwo defined before it is included.
// Barycentric shading normal from signed sub-areas (emu ShadingNormal).
vec3 ShadingNormalOf(Triangle t, TriangleNormals tn, vec3 p) {
  const vec3 v0 = t.v0.xyz, v1 = t.v1.xyz, v2 = t.v2.xyz;
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0, q0 = v0 - p, q1 = v1 - p, q2 = v2 - p;
  const float k = InversePowerOfTwo(max(max(MaxAbs(e1, e2), MaxAbs(q0, q1)), MaxAbs(q2, q2)));
  const vec3 n = Cross3(e1 * k, e2 * k);
  const float a0 = Dot3(Cross3(q1 * k, q2 * k), n);
  const float a1 = Dot3(Cross3(q2 * k, q0 * k), n);
  const float a2 = Dot3(Cross3(q0 * k, q1 * k), n);
  precise const float sum = (a0 + a1) + a2;
  precise vec3 s = vec3(0.0);
  if (sum != 0.0) {
    precise const float w0 = Div(a0, sum), w1 = Div(a1, sum), w2 = Div(a2, sum);
    for (int k = 0; k < 3; ++k) s[k] = (tn.n0[k] * w0 + tn.n1[k] * w1) + tn.n2[k] * w2;
  }
  const float len2 = Dot3(s, s);
  if (!(len2 > 0.0) || !(len2 <= 3.0e38)) {
    const float nl = Dot3(n, n);
    if (!(nl > 0.0) || !(nl <= 3.0e38)) return tn.n0.xyz;
    return Normalize3(n);
  }
  return Normalize3(s);
}

