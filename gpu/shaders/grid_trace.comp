#version 460
// grid.trace (Hunt and Mark's perspective grids, docs/grids.md): one invocation per ray. A point
// light's shadow ray finds its one cell of the light's grid from its direction (cube face, then
// (u, v)) and tests that cell's triangles, unless it ends before the cell's least distance. An area
// light's shadow ray walks the light's 3D perspective grid: its part in the core cube about the light
// through the regular grid, its part in each face's frustum as a 3D DDA along the straight line it is
// in perspective space. Every other ray clips itself to the regular grid's box and steps through it cell by cell (3D DDA),
// stopping at the first hit (shadow) or once its best hit lies before the cell's exit (closest).
// Closest hits keep the packed (t, id) minimum, so ties resolve as every other tracer's do. Loops run
// in blocks (lavapipe ends a loop after 65,535 iterations). Mirrors emu PassGridTrace.
#include "common.glsl"
#include "grid.glsl"
#define WATERTIGHT_SWAP_FAULT 0xFFFFFFFFu  // no range-swap fault here
#include "watertight.glsl"

layout(std430, binding = kGridTraceBindFirst) readonly buffer First { uint first[]; };
layout(std430, binding = kGridTraceBindTriangles) readonly buffer CellTriangles { uint cell_triangles[]; };
layout(std430, binding = kGridTraceBindMinDist) readonly buffer MinDist { float min_dist[]; };
layout(std430, binding = kGridTraceBindLights) readonly buffer LightGrids { uvec4 light_grids[]; };
layout(std430, binding = kGridTraceBindOrigins) readonly buffer Origins { vec4 origins[]; };
layout(std430, binding = kGridTraceBindVolume) readonly buffer Volume { GridVolume vol; };
layout(std430, binding = kGridTraceBindSceneTris) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = kGridTraceBindRays) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = kGridTraceBindHits) writeonly buffer Hits { uint64_t hits[]; };
layout(std430, binding = kGridTraceBindOccluded) writeonly buffer Occluded { uint occluded[]; };
layout(std430, binding = kGridTraceBindSteps) writeonly buffer Steps { uint steps_out[]; };
layout(std430, binding = kGridTraceBindTests) writeonly buffer Tests { uint tests_out[]; };
layout(std430, binding = kGridTraceBindBoxes) readonly buffer Boxes { vec4 boxes[]; };
layout(std430, binding = kGridTraceBindSlices) readonly buffer Slices { float slices[]; };
layout(push_constant) uniform Block { GridTracePush pc; };

const uint64_t kMiss = 0xFFFFFFFFFFFFFFFFul;
const uint kNone = 0xFFFFFFFFu;
const uint kBlock = 4096u;
float Inf() { return uintBitsToFloat(0x7F800000u); }

Ray r;
float ray_u = 0.0, ray_v = 0.0;  // a perspective ray's (u, v) on its face
uint64_t best = kMiss;
uint tests = 0u, steps = 0u;

bool Done() { return pc.shadow != 0u && best != kMiss; }

// The triangles of one cell, in ascending ids, against the whole range (tmin, tmax); in a perspective
// cell (`boxed`) only those whose projection's (u, v) rectangle holds the ray's.
void TestCell(uint cell, bool boxed) {
  const uint b = first[cell];
  uint e = first[cell + 1u];
  // Fault 4: the last triangle of every cell is never tested.
  if (kFault == 4u && e > b) e -= 1u;
  const vec3 org = r.origin_tmin.xyz, dir = r.direction_tmax.xyz;
  for (uint i0 = b; i0 < e && !Done(); i0 += kBlock) {
    for (uint i = i0; i < min(e, i0 + kBlock) && !Done(); ++i) {
      const uint t = cell_triangles[i];
      if (t == r.info.y) continue;
      if (boxed) {
        const vec4 box = boxes[i];
        if (!(ray_u >= box.x && ray_v >= box.y && ray_u <= box.z && ray_v <= box.w)) continue;
      }
      ++tests;
      const Triangle tr = triangles[t];
      float th, det;
      if (WatertightSided(org, dir, tr.v0.xyz, tr.v1.xyz, tr.v2.xyz, r.origin_tmin.w, r.direction_tmax.w, th, det)) {
        const uint64_t packed = (uint64_t(floatBitsToUint(th)) << 32) | uint64_t(t);
        if (packed < best) best = packed;
      }
    }
  }
}

// A point light's shadow ray: the cell of its direction in its light's grid; an eye ray: in the eye's
// (--primary grid) (emu grid::DirectionFace and grid::FaceCell); kNone when there is none or the ray
// does not start at the grid's origin.
uint PerspectiveCell() {
  uint index = kNone;
  if (pc.shadow != 0u && r.info.z == kRayShadow) index = r.info.w;
  if (pc.shadow == 0u && r.info.z == kRayPrimary) index = pc.eye;
  if (index >= pc.lights) return kNone;
  const uvec4 g = light_grids[index];
  const vec4 o = origins[index];
  if (g.x == kGridNoLight || g.z != 0u || o.x != r.origin_tmin.x || o.y != r.origin_tmin.y || o.z != r.origin_tmin.z) return kNone;
  const vec3 d = r.direction_tmax.xyz;
  const vec3 a = abs(d);
  if (!(max(max(a.x, a.y), a.z) > 0.0)) return kNone;
  const uint major = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
  const float m = a[major];
  const uint face = 2u * major + (d[major] < 0.0 ? 1u : 0u);
  const float u = Div(d[(major + 1u) % 3u], m), v = Div(d[(major + 2u) % 3u], m);
  ray_u = u;
  ray_v = v;
  const uint n = g.y;
  precise const float half_n = float(n) * 0.5;
  precise const float x = (u + 1.0) * half_n, y = (v + 1.0) * half_n;
  uint i = min(uint(max(x, 0.0)), n - 1u);
  const uint j = min(uint(max(y, 0.0)), n - 1u);
  // Fault 1: the cell one column off.
  if (kFault == 1u) i = min(i + 1u, n - 1u);
  return g.x + (face * n + j) * n + i;
}

// 3D DDA through the regular grid over (tmin, tmax) clipped to its box (emu StepRegular).
void StepRegular(float tmin, float tmax) {
  const vec3 org = r.origin_tmin.xyz, dir = r.direction_tmax.xyz;
  vec3 inv;
  float t0 = tmin, t1 = tmax;
  bool outside = false;
  for (int a = 0; a < 3; ++a) {
    // An axis the ray does not move along: no quotient of a zero divisor (Vulkan bounds none), the
    // ray is in the box's slab or nowhere in it (emu BoxClip).
    if (dir[a] == 0.0) {
      inv[a] = 0.0;
      outside = outside || org[a] < vol.lo[a] || org[a] > vol.hi[a];
      continue;
    }
    inv[a] = Div(1.0, dir[a]);
    precise float ta = (vol.lo[a] - org[a]) * inv[a];
    precise float tb = (vol.hi[a] - org[a]) * inv[a];
    if (inv[a] < 0.0) {
      const float s = ta;
      ta = tb;
      tb = s;
    }
    t0 = max(t0, ta);
    t1 = min(t1, tb);
  }
  if (outside || !(t0 <= t1)) return;
  ivec3 at, stp;
  vec3 next;
  for (int a = 0; a < 3; ++a) {
    precise const float p = org[a] + dir[a] * t0;
    precise const float x = (p - vol.lo[a]) * vol.inv_cell[a];
    at[a] = int(uint(min(max(x, 0.0), float(vol.dims[a] - 1u))));
    stp[a] = dir[a] > 0.0 ? 1 : (dir[a] < 0.0 ? -1 : 0);
    precise const float boundary = vol.lo[a] + float(at[a] + (stp[a] > 0 ? 1 : 0)) * vol.cell[a];
    precise const float tn = (boundary - org[a]) * inv[a];
    next[a] = stp[a] == 0 ? Inf() : tn;
  }
  const uint guard_end = vol.dims.x + vol.dims.y + vol.dims.z;
  for (uint guard = 0u; guard < guard_end; ++guard) {
    ++steps;
    TestCell(vol.dims.w + (uint(at.z) * vol.dims.y + uint(at.y)) * vol.dims.x + uint(at.x), false);
    if (Done()) return;
    int a = 0;
    if (next.y < next[a]) a = 1;
    if (next.z < next[a]) a = 2;
    const float exit_t = next[a];
    if (best != kMiss && uintBitsToFloat(uint(best >> 32)) < exit_t) return;
    if (!(exit_t <= t1)) return;
    // Fault 3: a step along z skips the next slice.
    at[a] += (kFault == 3u && a == 2) ? 2 * stp[a] : stp[a];
    if (at[a] < 0 || at[a] >= int(vol.dims[a])) return;
    precise const float boundary = vol.lo[a] + float(at[a] + (stp[a] > 0 ? 1 : 0)) * vol.cell[a];
    precise const float tn = (boundary - org[a]) * inv[a];
    next[a] = tn;
  }
}

// An area light's shadow ray: its light's 3D grid; a closest-hit ray other than an eye ray: the 3D
// grid about the eye (--grid-secondary perspective); kNone when there is none (emu grid::VolumeGridOf).
uint VolumeOf() {
  uint index = kNone;
  if (pc.shadow != 0u && r.info.z == kRayShadow) index = r.info.w;
  if (pc.shadow == 0u && r.info.z != kRayPrimary) index = pc.secondary;
  if (index >= pc.lights) return kNone;
  const uvec4 g = light_grids[index];
  return g.x != kGridNoLight && g.z != 0u ? index : kNone;
}

// Clips [t0, t1] to where g0 + g1 t >= 0 (emu ClipLinear).
void ClipLinear(float g0, float g1, inout float t0, inout float t1) {
  if (g1 > 0.0)
    t0 = max(t0, Div(-g0, g1));
  else if (g1 < 0.0)
    t1 = min(t1, Div(-g0, g1));
  else if (g0 < 0.0)
    t1 = -Inf();
}

// The ray's range within region `region` of a 3D grid: a face's frustum beyond the near plane, or
// (kGridFaces) the core (emu RegionRange).
void RegionRange(vec3 oq, vec3 dir, float zn, uint region, inout float t0, inout float t1) {
  if (region == kGridFaces) {
    precise const float h = zn * kGridCoreWiden;
    for (int a = 0; a < 3; ++a) {
      precise const float lo_g = h - oq[a], hi_g = h + oq[a];
      ClipLinear(lo_g, -dir[a], t0, t1);
      ClipLinear(hi_g, dir[a], t0, t1);
    }
    return;
  }
  const uint major = region / 2u, ua = (major + 1u) % 3u, vb = (major + 2u) % 3u;
  const float sgn = region % 2u == 0u ? 1.0 : -1.0;
  precise const float m0 = sgn * oq[major], dm = sgn * dir[major];
  precise const float wide = 1.0 + kGridFaceSlack;
  precise const float g_near = m0 - zn * kGridNearShrink;
  ClipLinear(g_near, dm, t0, t1);
  precise const float wm0 = wide * m0, wdm = wide * dm;
  precise const float a0 = wm0 - oq[ua], a1 = wdm - dir[ua], b0 = wm0 + oq[ua], b1 = wdm + dir[ua];
  precise const float c0 = wm0 - oq[vb], c1 = wdm - dir[vb], d0 = wm0 + oq[vb], d1 = wdm + dir[vb];
  ClipLinear(a0, a1, t0, t1);
  ClipLinear(b0, b1, t0, t1);
  ClipLinear(c0, c1, t0, t1);
  ClipLinear(d0, d1, t0, t1);
}

// A point of face f in perspective space: cell coordinates of (u, v) and r = 1 / m, m kept at or
// beyond the near plane (emu Perspective). Returns m.
float Perspective(vec3 q, uint f, float half_n, float near, out vec3 p) {
  const uint major = f / 2u, ua = (major + 1u) % 3u, vb = (major + 2u) % 3u;
  const float sgn = f % 2u == 0u ? 1.0 : -1.0;
  precise const float sm = sgn * q[major];
  const float m = max(sm, near);
  precise const float px = (Div(q[ua], m) + 1.0) * half_n, py = (Div(q[vb], m) + 1.0) * half_n;
  p = vec3(px, py, Div(1.0, m));
  return m;
}

// The next depth boundary's fraction of the way (emu: bounds[slice + (step > 0)]).
float NextSlice(uint base, int slice, int stp, float p0z, float dz) {
  precise const float num = slices[base + uint(slice + (stp > 0 ? 1 : 0))] - p0z;
  return Div(num, dz);
}
float NextColumn(int at, int stp, float p0, float d) {
  precise const float num = float(at + (stp > 0 ? 1 : 0)) - p0;
  return Div(num, d);
}

// An area light's shadow ray through its 3D perspective grid (emu StepVolume).
void StepVolume(uint index) {
  const uvec4 g = light_grids[index];
  const vec4 o = origins[index];
  const uint n = g.y, depth = g.z;
  const float zn = o.w;
  precise const float near = zn * kGridNearShrink;
  precise const float half_n = float(n) * 0.5;
  const vec3 org = r.origin_tmin.xyz, dir = r.direction_tmax.xyz;
  precise const vec3 oq = org - o.xyz;
  float T0 = r.origin_tmin.w, T1 = r.direction_tmax.w;
  for (int a = 0; a < 3; ++a) {
    precise const float lo_g = org[a] - vol.lo[a], hi_g = vol.hi[a] - org[a];
    ClipLinear(lo_g, dir[a], T0, T1);
    ClipLinear(hi_g, -dir[a], T0, T1);
  }
  if (!(T0 <= T1)) return;
  const uint kRegions = kGridFaces + 1u;
  float r0[7], r1[7];
  for (uint s = 0u; s < kRegions; ++s) {
    r0[s] = T0;
    r1[s] = T1;
    RegionRange(oq, dir, zn, s, r0[s], r1[s]);
  }
  uint done = 0u;
  const uint cells_per_face = n * n * depth;
  for (uint round = 0u; round < kRegions; ++round) {
    uint s = kRegions;
    for (uint x = 0u; x < kRegions; ++x)
      if ((done & (1u << x)) == 0u && r0[x] <= r1[x] && (s == kRegions || r0[x] < r0[s])) s = x;
    if (s == kRegions) return;
    done |= 1u << s;
    const float t0 = r0[s], t1 = r1[s];
    if (best != kMiss && uintBitsToFloat(uint(best >> 32)) < t0) return;
    if (s == kGridFaces) {  // the core: the regular grid's cells
      StepRegular(t0, t1);
      if (Done()) return;
      continue;
    }
    const uint base = g.w + s * (depth + 1u);
    vec3 p0, p1;
    precise const vec3 q0 = oq + dir * t0, q1 = oq + dir * t1;
    const float ma = Perspective(q0, s, half_n, near, p0);
    const float mb = Perspective(q1, s, half_n, near, p1);
    precise const vec3 delta = p1 - p0;
    ivec3 at, stp;
    vec3 next;
    for (int a = 0; a < 2; ++a) {
      at[a] = int(min(uint(max(p0[a], 0.0)), n - 1u));
      stp[a] = delta[a] > 0.0 ? 1 : (delta[a] < 0.0 ? -1 : 0);
      next[a] = stp[a] == 0 ? Inf() : NextColumn(at[a], stp[a], p0[a], delta[a]);
    }
    uint slice = 0u;
    for (uint j = 1u; j < depth; ++j) slice += p0.z <= slices[base + j] ? 1u : 0u;
    at.z = int(slice);
    stp.z = delta.z < 0.0 ? 1 : (delta.z > 0.0 ? -1 : 0);
    next.z = stp.z == 0 ? Inf() : NextSlice(base, at.z, stp.z, p0.z, delta.z);
    for (uint guard = 0u; guard < 2u * n + depth; ++guard) {
      ++steps;
      TestCell(g.x + s * cells_per_face + (uint(at.z) * n + uint(at.y)) * n + uint(at.x), false);
      if (Done()) return;
      int a = 0;
      if (next.y < next[a]) a = 1;
      if (next.z < next[a]) a = 2;
      const float exit_s = next[a];
      if (!(exit_s <= 1.0)) break;
      if (best != kMiss) {
        precise const float num = exit_s * ma, den = (1.0 - exit_s) * mb + exit_s * ma;
        // Fault 6: the exit's t taken as linear in the perspective fraction (no perspective correction).
        precise const float te = t0 + (t1 - t0) * (kFault == 6u ? exit_s : Div(num, den));
        if (uintBitsToFloat(uint(best >> 32)) < te) return;
      }
      // Fault 5: a step away from the light skips the next depth slice.
      at[a] += (kFault == 5u && a == 2 && stp.z > 0) ? 2 * stp[a] : stp[a];
      if (at[a] < 0 || at[a] >= int(a == 2 ? depth : n)) break;
      next[a] = a == 2 ? NextSlice(base, at.z, stp.z, p0.z, delta.z) : NextColumn(at[a], stp[a], p0[a], delta[a]);
    }
  }
}

void main() {
  const uint ray = GlobalIndex();
  if (ray >= pc.count) return;
  r = rays[ray];
  const uint cell = PerspectiveCell();
  const uint volume = VolumeOf();
  bool away = false;
  if ((cell != kNone || volume != kNone) && pc.shadow != 0u && pc.closed != 0u && r.info.y < uint(triangles.length())) {
    const Triangle own = triangles[r.info.y];
    // an area light's sample: the ray's origin; a point light: its position (a shadow ray's index)
    away = FacesAway(own.v0.xyz, own.v1.xyz, own.v2.xyz, volume != kNone ? r.origin_tmin.xyz : origins[r.info.w].xyz);
  }
  if (away) {
    best = 0ul;  // --closed-models: the surface faces away from its light, in shadow untraced
  } else if (volume != kNone) {
    StepVolume(volume);
  } else if (cell != kNone) {
    steps = 1u;
    // Fault 2: the cell's least distance taken 1/64 too far.
    precise const float dmin = kFault == 2u ? min_dist[cell] * 1.015625 : min_dist[cell];
    if (r.direction_tmax.w > dmin) TestCell(cell, true);
  } else {
    StepRegular(r.origin_tmin.w, r.direction_tmax.w);
  }
  if (pc.shadow != 0u)
    occluded[ray] = best != kMiss ? 1u : 0u;
  else
    hits[ray] = best;
  steps_out[ray] = steps;
  tests_out[ray] = tests;
}
