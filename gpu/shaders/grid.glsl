// Shared by the grid kernels (grid_trace.comp, grid_build.comp).
#ifndef RAYSPACE_GRID_GLSL
#define RAYSPACE_GRID_GLSL

// --closed-models: whether the triangle faces away from the point o (emu grid::FacesAway: the
// watertight test's scaled plane normal, o behind the plane).
bool FacesAway(vec3 v0, vec3 v1, vec3 v2, vec3 o) {
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0;
  const float ke = InversePowerOfTwo(MaxAbs(e1, e2));
  const vec3 n0 = Cross3(e1 * ke, e2 * ke);
  const float kn = InversePowerOfTwo(MaxAbs(n0, n0));
  precise const vec3 n = n0 * kn;
  precise const vec3 w = o - v0;
  return Dot3(n, w) < 0.0;
}

#endif  // RAYSPACE_GRID_GLSL
