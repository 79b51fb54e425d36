#version 460
// tl.heads: per (scene triangle, case, list) the window [head, tail) of the packed traversal list
// that a ray starting on the triangle (cases 0, 1) or ending on it (2, 3), on the side in front of
// it (even) or behind it (odd), must walk: every element outside it lies beyond the triangle's plane
// or, in regular mode, beyond a facet plane of the list's class, by more than the margin (Toczek et
// al. section 3.1). One invocation per window; the head skips subtrees beyond a plane and enters the
// spheres that are not, up to the first triangle kept, and starts right after the last subtree
// skipped; the tail descends the chain of subtrees after the head, one tree level at a time.
// Nothing is shared between invocations. Mirrors emu PassTlHeads (emu/src/tl.cpp) and the planes of
// emu/src/tl_heads.cpp.
#include "common.glsl"
#define TL_FLIPPED_SPHERE_TEST false
#include "tl.glsl"

layout(std430, binding = kTlHeadsBindFirst) readonly buffer First { uint first[]; };
layout(std430, binding = kTlHeadsBindEscapes) readonly buffer Escapes { int escapes[]; };
layout(std430, binding = kTlHeadsBindWords) readonly buffer Words { uvec4 words[]; };
layout(std430, binding = kTlHeadsBindVertices) readonly buffer Vertices { vec4 vertices[]; };
layout(std430, binding = kTlHeadsBindTriWords) readonly buffer TriWords { uvec4 tri_words[]; };
layout(std430, binding = kTlHeadsBindWindows) writeonly buffer Windows { uint windows[]; };
layout(push_constant) uniform Block { TlHeadsPush pc; };

// An upper bound of sqrt(2), a sextant facet normal's length (emu kSqrt2Up).
const float kSqrt2Up = 1.41421366;

vec3 n;
vec3 v0;
bool behind, ends;
float reach;
uint facets;
vec3 m[4];
float bound[4];
float len[4];

void MakePlanes(uint t, uint cs, uint k) {
  const uvec4 w = tri_words[t];
  v0 = vertices[w.x].xyz;
  const vec3 v1 = vertices[w.y].xyz, v2 = vertices[w.z].xyz;
  precise const vec3 e1 = v1 - v0, e2 = v2 - v0;
  n = Cross3(e1, e2);
  // Fault 1: the triangle's plane faces the other way.
  behind = ((cs & 1u) != 0u) != (kFault == 1u);
  ends = (cs & 2u) != 0u;
  precise const float r = pc.margin * Length3(n);
  reach = r;
  facets = 0u;
  if (pc.mode == kTlHeadsRegular) {
    // Fault 2: the facets of the opposite class.
    const uint kk = kFault == 2u ? (pc.lists == 8u ? 7u - k : k ^ 1u) : k;
    facets = TlFacets(pc.lists, kk, m);
  }
  for (uint j = 0u; j < facets; ++j) {
    bound[j] = TlFacetBound(m[j], v0, v1, v2, ends);
    len[j] = pc.lists == 6u ? kSqrt2Up : 1.0;
  }
}

bool Sliver(uint t) {
  const uvec4 w = tri_words[t];
  precise const vec3 e1 = vertices[w.y].xyz - vertices[w.x].xyz, e2 = vertices[w.z].xyz - vertices[w.x].xyz;
  const vec3 nn = Cross3(e1, e2);
  precise const float a = MaxAbs(nn, nn) * 32.0, b = MaxAbs(e1, e1) * MaxAbs(e2, e2);
  return !(a >= b);
}

float Side(vec3 x) {
  precise const vec3 d = x - v0;
  const float h = Dot3(n, d);
  return behind ? -h : h;
}

bool SphereRejected(vec4 s) {
  precise const float h = Side(s.xyz) + s.w * Length3(n);
  if (h < -reach) return true;
  for (uint j = 0u; j < facets; ++j) {
    const float x = Dot3(m[j], s.xyz);
    precise const float r = s.w * len[j], g = pc.margin * len[j];
    precise const float lo = x + r, hi = x - r, bl = bound[j] - g, bh = bound[j] + g;
    if (ends ? hi > bh : lo < bl) return true;
  }
  return false;
}

bool TriangleRejected(vec3 a, vec3 b, vec3 c) {
  if (Side(a) < -reach && Side(b) < -reach && Side(c) < -reach) return true;
  for (uint j = 0u; j < facets; ++j) {
    precise const float g = pc.margin * len[j], bl = bound[j] - g, bh = bound[j] + g;
    const float ya = Dot3(m[j], a), yb = Dot3(m[j], b), yc = Dot3(m[j], c);
    if (ends ? (ya > bh && yb > bh && yc > bh) : (ya < bl && yb < bl && yc < bl)) return true;
  }
  return false;
}

#include "tl_window.glsl"

uvec2 Window(uint t, uint cs, uint k) {
  const uint begin = first[k], end = first[k + 1u];
  if (Sliver(t)) return uvec2(begin, end);
  MakePlanes(t, cs, k);
  uvec2 w = ListWindow(begin, end);
  // Fault 3: the head one element past the first element kept.
  if (kFault == 3u && w.x + 1u < w.y) w.x += 1u;
  return w;
}

void main() {
  const uint g = GlobalIndex(), K = pc.lists, total = pc.triangles * kTlCases * K;
  if (g >= total) return;
  const uint k = g % K, cs = (g / K) % kTlCases, t = g / K / kTlCases;
  const uvec2 w = Window(t, cs, k);
  windows[2u * g] = w.x;
  windows[2u * g + 1u] = w.y;
}
