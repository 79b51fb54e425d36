#version 460
// The grids' build (docs/grids.md, "The build as kernels"; mirrors emu PassGridCount, PassGridEmit and
// PassGridCells, whose binning is emu/src/grid_bin.h), one grid a call, in phases:
//   kGridBuildPhaseCount      one invocation per triangle: per face its span of cells, the references
//                             in all, a 2D grid's least distance
//   kGridBuildPhaseBlockSums  grid.emit: reduce-then-scan of the counts over blocks of kScanBlock
//   kGridBuildPhaseScanSums   triangles (as trim), each triangle's first reference
//   kGridBuildPhaseOffsets
//   kGridBuildPhaseEmit       one invocation per reference: its triangle by a binary search over the
//                             offsets, its cell from the triangle's spans
//   kGridBuildPhaseGather     grid.cells, one invocation per reference in the sort's order
//   kGridBuildPhaseCells      one invocation per cell: its offset, a lower bound over the sorted cells
//   kGridBuildPhaseMin        one invocation per sorted reference: atomicMin of its least distance
// lavapipe counts the iterations of every loop of an invocation against one budget of 65,535
// (gallivm's loop limiter, set once per shader call): no invocation here loops over cells or lists,
// so none comes near it. The binning computes in double as the host does; the float-control mode
// below keeps Mesa from folding (a - b) + b to a in 64-bit arithmetic, which the emulator rounds.
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#include "common.glsl"
#include "grid.glsl"
#include "workgroup.glsl"

spirv_execution_mode(extensions = ["SPV_KHR_float_controls"], capabilities = [4466], 4461, 64);

layout(std430, binding = kGridBuildBindTriangles) readonly buffer Tris { Triangle tris[]; };
layout(std430, binding = kGridBuildBindGrid) readonly buffer GridB { GridBuildGrid grid; };
layout(std430, binding = kGridBuildBindSlices) readonly buffer Slices { float slices[]; };
layout(std430, binding = kGridBuildBindCounts) buffer Counts { uint counts[]; };
layout(std430, binding = kGridBuildBindDist) buffer Dist { float dist[]; };
layout(std430, binding = kGridBuildBindSpans) buffer SpansB { uvec4 spans[]; };
layout(std430, binding = kGridBuildBindSpanBoxes) buffer SpanBoxes { vec4 span_boxes[]; };
layout(std430, binding = kGridBuildBindSums) buffer Sums { uint sums[]; };
layout(std430, binding = kGridBuildBindOffsets) buffer Offsets { uint offsets[]; };
layout(std430, binding = kGridBuildBindCells) buffer Cells { uint ref_cells[]; };
layout(std430, binding = kGridBuildBindRefTris) buffer RefTris { uint ref_tris[]; };
layout(std430, binding = kGridBuildBindBoxes) buffer Boxes { vec4 ref_boxes[]; };
layout(std430, binding = kGridBuildBindOrder) readonly buffer Order { uint order[]; };
layout(std430, binding = kGridBuildBindFirst) writeonly buffer First { uint first[]; };
layout(std430, binding = kGridBuildBindListTris) buffer ListTris { uint list_tris[]; };
layout(std430, binding = kGridBuildBindListBoxes) writeonly buffer ListBoxes { vec4 list_boxes[]; };
layout(std430, binding = kGridBuildBindMinDist) buffer MinDist { uint min_dist[]; };  // float bits
layout(push_constant) uniform Block { GridBuildPush pc; };

// std::min, std::max and std::clamp of the emulator, operand order included.
double MinD(double a, double b) { return b < a ? b : a; }
double MaxD(double a, double b) { return a < b ? b : a; }
double ClampD(double x, double lo, double hi) { return x < lo ? lo : (hi < x ? hi : x); }
double DotD(dvec3 a, dvec3 b) {
  precise double s = a.x * b.x + a.y * b.y;
  precise double r = s + a.z * b.z;
  return r;
}
double LengthD(dvec3 v) { return sqrt(DotD(v, v)); }
dvec3 CrossD(dvec3 a, dvec3 b) {
  precise dvec3 c = dvec3(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
  return c;
}

// A convex polygon of at most 8 vertices: a triangle clipped by at most five planes.
struct Poly {
  dvec3 p[8];
  int n;
};

// Sutherland-Hodgman: the part of `a` where dot(plane, p) >= 0 (emu ClipHalfSpace).
Poly ClipHalfSpace(Poly a, dvec3 plane) {
  Poly b;
  b.n = 0;
  for (int i = 0; i < a.n; ++i) {
    const dvec3 p = a.p[i], q = a.p[(i + 1) % a.n];
    const double dp = DotD(plane, p), dq = DotD(plane, q);
    if (dp >= 0.0lf) b.p[b.n++] = p;
    if ((dp >= 0.0lf) != (dq >= 0.0lf)) {
      precise const double f = dp / (dp - dq);
      precise const dvec3 x = p + (q - p) * f;
      b.p[b.n++] = x;
    }
  }
  return b;
}

dvec3 Vertex(vec4 v) { return dvec3(v.xyz); }
// A component picked by a run-time index (the emulator's p[axis]), and a vector with one replaced.
double Comp(dvec3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }
dvec3 WithComp(dvec3 v, int k, double x) { return dvec3(k == 0 ? x : v.x, k == 1 ? x : v.y, k == 2 ? x : v.z); }
// The grid's cells (the checked inputs keep the count below 2^32).
uint CellCount() {
  const uint n = grid.shape.y;
  if (grid.shape.x == kGridKindPerspective) return kGridFaces * n * n;
  if (grid.shape.x == kGridKindVolume) return kGridFaces * n * n * grid.shape.z;
  return n * grid.shape.z * grid.shape.w;
}
bool Margins() { return (grid.flags.x & kGridBuildMargins) != 0u; }
bool Cull() { return (grid.flags.x & kGridBuildCull) != 0u; }

// The cells [c0, c1] an extent [lo, hi] in face coordinates covers of n (emu CellRange).
uvec2 CellRange(double lo, double hi, uint n, double slack) {
  precise const double half_n = 0.5lf * double(n);
  precise const double x0 = floor((lo + 1.0lf) * half_n - slack), x1 = floor((hi + 1.0lf) * half_n + slack);
  return uvec2(uint(ClampD(x0, 0.0lf, double(n) - 1.0lf)), uint(ClampD(x1, 0.0lf, double(n) - 1.0lf)));
}

// The face's axes (emu AxesOf): the major one, the two that become u and v, and its sign.
ivec3 Axes(uint face) {
  const int major = int(face / 2u);
  return ivec3(major, (major + 1) % 3, (major + 2) % 3);
}
double SignOf(uint face) { return face % 2u == 0u ? 1.0lf : -1.0lf; }

// A face side's plane (w m - a >= 0, w m + a >= 0, ... ) of emu FaceCellRange and BinVolume.
dvec3 SidePlane(uint face, int side, double w) {
  const ivec3 ax = Axes(face);
  const dvec3 plane = WithComp(dvec3(0.0lf), ax.x, SignOf(face) * w);
  return WithComp(plane, side < 2 ? ax.y : ax.z, side % 2 == 0 ? -1.0lf : 1.0lf);
}

// A face's span (emu grid::bin::Span, packed as Pack does): columns i0..i1, rows j0..j1, slices k0..k1.
// Fault 1 of grid.count: a span loses its last column.
uvec4 Span(uint i0, uint i1, uint j0, uint j1, uint k0, uint k1) {
  if (kFault == 1u && i1 > i0) i1 -= 1u;
  return uvec4(i0 | (i1 << 16), j0 | (j1 << 16), k0 | (k1 << 16), 1u);
}
uint SpanSize(uvec4 s) {
  if (s.w == 0u) return 0u;
  return ((s.x >> 16) - (s.x & 0xFFFFu) + 1u) * ((s.y >> 16) - (s.y & 0xFFFFu) + 1u) * ((s.z >> 16) - (s.z & 0xFFFFu) + 1u);
}

// A 2D grid about the centre (emu PerspectiveSpans, FaceCellRange): per face the rectangle of cells.
void PerspectiveSpans(uint t, Triangle tr) {
  const uint n = grid.shape.y;
  const bool margins = Margins();
  if (Cull() && !FacesAway(tr.v0.xyz, tr.v1.xyz, tr.v2.xyz, grid.centre.xyz)) return;
  const dvec3 o = Vertex(grid.centre);
  precise const dvec3 r0 = Vertex(tr.v0) - o, r1 = Vertex(tr.v1) - o, r2 = Vertex(tr.v2) - o;
  const double w = 1.0lf + (margins ? double(kGridFaceSlack) : 0.0lf);
  for (uint f = 0u; f < kGridFaces; ++f) {
    const ivec3 ax = Axes(f);
    const double sgn = SignOf(f);
    Poly poly;
    poly.n = 3;
    poly.p[0] = r0, poly.p[1] = r1, poly.p[2] = r2;
    for (int side = 0; side < 4 && poly.n > 0; ++side) poly = ClipHalfSpace(poly, SidePlane(f, side, w));
    if (poly.n == 0) continue;
    double lo0 = 1.0lf / 0.0lf, lo1 = lo0, hi0 = -lo0, hi1 = -lo0;
    for (int i = 0; i < poly.n; ++i) {
      const dvec3 p = poly.p[i];
      precise const double m = sgn * Comp(p, ax.x);
      if (!(m > 0.0lf)) {  // the triangle passes through the centre: every cell of the face
        lo0 = lo1 = -(1.0lf / 0.0lf);
        hi0 = hi1 = 1.0lf / 0.0lf;
        break;
      }
      precise const double u = Comp(p, ax.y) / m, v = Comp(p, ax.z) / m;
      lo0 = MinD(lo0, u), hi0 = MaxD(hi0, u);
      lo1 = MinD(lo1, v), hi1 = MaxD(hi1, v);
    }
    const double slack = margins ? double(kGridCellSlack) : 0.0lf;
    const uvec2 cu = CellRange(lo0, hi0, n, slack), cv = CellRange(lo1, hi1, n, slack);
    // The (u, v) rectangle, rounded outwards to float and widened by the face's slack.
    const double uv_slack = margins ? double(kGridFaceSlack) : 0.0lf, ulp = margins ? 1e-12lf : 0.0lf;
    precise const double d0 = MaxD(-2.0lf, lo0 - uv_slack) - ulp, d1 = MaxD(-2.0lf, lo1 - uv_slack) - ulp;
    precise const double u0 = MinD(2.0lf, hi0 + uv_slack) + ulp, u1 = MinD(2.0lf, hi1 + uv_slack) + ulp;
    spans[t * kGridFaces + f] = Span(cu.x, cu.y, cv.x, cv.y, 0u, 0u);
    span_boxes[t * kGridFaces + f] = vec4(float(d0), float(d1), float(u0), float(u1));
  }
}

// Every point of the light's box strictly in front of the triangle's plane (emu FrontFromBox).
bool FrontFromBox(Triangle tr) {
  const dvec3 a = Vertex(tr.v0);
  precise const dvec3 e1 = Vertex(tr.v1) - a, e2 = Vertex(tr.v2) - a;
  const dvec3 nrm = CrossD(e1, e2);
  const dvec3 lo = Vertex(grid.light_lo), hi = Vertex(grid.light_hi);
  for (int k = 0; k < 8; ++k) {
    precise const dvec3 p = dvec3((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, (k & 4) != 0 ? hi.z : lo.z) - a;
    if (!(DotD(nrm, p) > 0.0lf)) return false;
  }
  return true;
}

// The depth slice of r on a face whose D + 1 boundaries start at b (emu SliceOf).
uint SliceOf(double r, uint b, uint depth) {
  uint k = 0u;
  for (uint j = 1u; j < depth; ++j) k += r <= double(slices[b + j]) ? 1u : 0u;
  return k;
}

// A 3D perspective grid about the centre (emu VolumeSpans).
void VolumeSpans(uint t, Triangle tr) {
  const uint n = grid.shape.y, depth = grid.shape.z;
  const bool margins = Margins();
  if (Cull() && FrontFromBox(tr)) return;
  const dvec3 o = Vertex(grid.centre);
  const double depth_slack = margins ? 1.0lf / 1024.0lf : 0.0lf;
  precise const float near_f = grid.centre.w * kGridNearShrink;
  precise const double near = double(near_f) * (1.0lf - depth_slack);
  const double slack = margins ? double(kGridCellSlack) : 0.0lf;
  const double w = 1.0lf + (margins ? double(kGridFaceSlack) : 0.0lf);
  precise const dvec3 r0 = Vertex(tr.v0) - o, r1 = Vertex(tr.v1) - o, r2 = Vertex(tr.v2) - o;
  for (uint f = 0u; f < kGridFaces; ++f) {
    const ivec3 ax = Axes(f);
    const double sgn = SignOf(f);
    Poly poly;
    poly.n = 3;
    poly.p[0] = r0, poly.p[1] = r1, poly.p[2] = r2;
    const dvec3 plane = WithComp(dvec3(0.0lf), ax.x, sgn);
    for (int side = 0; side < 5 && poly.n > 0; ++side) {
      if (side == 4) {  // beyond the near plane, as a plane through p - near * axis
        precise const dvec3 shift = plane * near;
        for (int i = 0; i < poly.n; ++i) {
          precise const dvec3 q = poly.p[i] - shift;
          poly.p[i] = q;
        }
        poly = ClipHalfSpace(poly, plane);
        for (int i = 0; i < poly.n; ++i) {
          precise const dvec3 q = poly.p[i] + shift;
          poly.p[i] = q;
        }
        continue;
      }
      poly = ClipHalfSpace(poly, SidePlane(f, side, w));
    }
    if (poly.n == 0) continue;
    double lo0 = 1.0lf / 0.0lf, lo1 = lo0, lo2 = lo0, hi0 = -lo0, hi1 = -lo0, hi2 = -lo0;
    for (int i = 0; i < poly.n; ++i) {
      const dvec3 p = poly.p[i];
      precise const double m = MaxD(sgn * Comp(p, ax.x), near);
      precise const double u = Comp(p, ax.y) / m, v = Comp(p, ax.z) / m, r = 1.0lf / m;
      lo0 = MinD(lo0, u), hi0 = MaxD(hi0, u);
      lo1 = MinD(lo1, v), hi1 = MaxD(hi1, v);
      lo2 = MinD(lo2, r), hi2 = MaxD(hi2, r);
    }
    const uvec2 cu = CellRange(lo0, hi0, n, slack), cv = CellRange(lo1, hi1, n, slack);
    const uint b = grid.flags.y + f * (depth + 1u);
    precise const double rn = hi2 * (1.0lf + depth_slack), rf = lo2 * (1.0lf - depth_slack);
    const uint k0 = SliceOf(rn, b, depth), k1 = SliceOf(rf, b, depth);
    spans[t * kGridFaces + f] = Span(cu.x, cu.y, cv.x, cv.y, k0, k1);
  }
}

// The regular grid: the cells of the triangle's bounding box, as face 0 (emu RegularSpans).
void RegularSpans(uint t, Triangle tr) {
  const uvec3 dims = grid.shape.yzw;
  const double slack = Margins() ? double(kGridCellSlack) : 0.0lf;
  const dvec3 a = Vertex(tr.v0), b = Vertex(tr.v1), c = Vertex(tr.v2);
  uvec3 c0, c1;
  for (int k = 0; k < 3; ++k) {
    const double ak = Comp(a, k), bk = Comp(b, k), ck = Comp(c, k);
    const double tlo = MinD(ak, MinD(bk, ck)), thi = MaxD(ak, MaxD(bk, ck));
    const double lo = double(grid.centre[k]), cell = double(grid.cell[k]);
    precise const double x0 = floor((tlo - lo) / cell - slack), x1 = floor((thi - lo) / cell + slack);
    c0[k] = uint(ClampD(x0, 0.0lf, double(dims[k]) - 1.0lf));
    c1[k] = uint(ClampD(x1, 0.0lf, double(dims[k]) - 1.0lf));
  }
  // Fault 3 of grid.count: one layer short along z.
  if (kFault == 3u && c1.z > c0.z) c1.z -= 1u;
  spans[t * kGridFaces] = Span(c0.x, c1.x, c0.y, c1.y, c0.z, c1.z);
}

// Every face's span of triangle t (emu SpansOf): those it does not reach stay 0.
void SpansOf(uint t) {
  for (uint f = 0u; f < kGridFaces; ++f) spans[t * kGridFaces + f] = uvec4(0u);
  if (grid.shape.x == kGridKindPerspective)
    for (uint f = 0u; f < kGridFaces; ++f) span_boxes[t * kGridFaces + f] = vec4(0.0);
  const Triangle tr = tris[t];
  if (grid.shape.x == kGridKindPerspective)
    PerspectiveSpans(t, tr);
  else if (grid.shape.x == kGridKindVolume)
    VolumeSpans(t, tr);
  else
    RegularSpans(t, tr);
}

// The cell of column i, row j, slice k of face f (emu grid::bin::CellOf).
uint CellOf(uint f, uint i, uint j, uint k) {
  const uint n = grid.shape.y;
  if (grid.shape.x == kGridKindRegular) return (k * grid.shape.z + j) * n + i;
  return ((f * (grid.shape.x == kGridKindVolume ? grid.shape.z : 1u) + k) * n + j) * n + i;
}

// The least distance from the centre to the triangle (emu PointTriangleDistance, Ericson's closest
// point), in double.
double PointTriangleDistance(dvec3 p, dvec3 a, dvec3 b, dvec3 c) {
  precise const dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = DotD(ab, ap), d2 = DotD(ac, ap);
  if (d1 <= 0.0lf && d2 <= 0.0lf) return LengthD(ap);
  precise const dvec3 bp = p - b;
  const double d3 = DotD(ab, bp), d4 = DotD(ac, bp);
  if (d3 >= 0.0lf && d4 <= d3) return LengthD(bp);
  precise const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0lf && d1 >= 0.0lf && d3 <= 0.0lf && d1 - d3 > 0.0lf) {  // edge regions: edges of some length
    precise const dvec3 q = p - (a + ab * (d1 / (d1 - d3)));
    return LengthD(q);
  }
  precise const dvec3 cp = p - c;
  const double d5 = DotD(ab, cp), d6 = DotD(ac, cp);
  if (d6 >= 0.0lf && d5 <= d6) return LengthD(cp);
  precise const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0lf && d2 >= 0.0lf && d6 <= 0.0lf && d2 - d6 > 0.0lf) {
    precise const dvec3 q = p - (a + ac * (d2 / (d2 - d6)));
    return LengthD(q);
  }
  precise const double va = d3 * d6 - d5 * d4;
  precise const double e43 = d4 - d3, e56 = d5 - d6;
  if (va <= 0.0lf && e43 >= 0.0lf && e56 >= 0.0lf && e43 + e56 > 0.0lf) {
    precise const dvec3 q = p - (b + (c - b) * (e43 / (e43 + e56)));
    return LengthD(q);
  }
  precise const double denom = va + vb + vc;
  if (!(denom != 0.0lf)) {  // degenerate: the nearest vertex
    const double la = LengthD(ap), lb = LengthD(bp), lc = LengthD(cp);
    double m = la;
    if (lb < m) m = lb;
    if (lc < m) m = lc;
    return m;
  }
  precise const double v = vb / denom, w = vc / denom;
  precise const dvec3 q = p - (a + ab * v + ac * w);
  return LengthD(q);
}

// Rounded down to float, then by the slack (emu LeastDistance).
float LeastDistance(Triangle tr) {
  const bool margins = Margins();
  // Fault 2 of grid.count: the distance to the first vertex, not the closest point.
  precise const dvec3 to_v0 = Vertex(grid.centre) - Vertex(tr.v0);
  const double d = kFault == 2u ? LengthD(to_v0) : PointTriangleDistance(Vertex(grid.centre), Vertex(tr.v0), Vertex(tr.v1), Vertex(tr.v2));
  float df = float(d);
  if (margins && double(df) > d) df = uintBitsToFloat(floatBitsToUint(df) - 1u);  // the next float towards 0 (df > 0)
  precise const float slackened = df * kGridDistanceSlack;
  return margins ? slackened : df;
}

// The first sorted reference whose cell is not below `cell`.
uint LowerBound(uint cell) {
  uint lo = 0u, hi = pc.refs;
  for (uint step = 0u; step < 33u && lo < hi; ++step) {
    const uint mid = lo + (hi - lo) / 2u;
    if (ref_cells[order[mid]] < cell)
      lo = mid + 1u;
    else
      hi = mid;
  }
  return lo;
}

// The triangle of reference r: the last whose offset is not past r (pc.count triangles).
uint TriangleOf(uint r) {
  uint lo = 0u, hi = pc.count;  // the first offset past r lies in [lo, hi]
  for (uint step = 0u; step < 33u && lo < hi; ++step) {
    const uint mid = lo + (hi - lo) / 2u;
    if (offsets[mid] <= r)
      lo = mid + 1u;
    else
      hi = mid;
  }
  return lo - 1u;
}

// Reference r: its cell, triangle and rectangle from its triangle's spans (emu PassGridEmit).
void Emit(uint r) {
  const uint t = TriangleOf(r);
  if (t >= pc.count) return;  // only a planted wrong offset leaves r before the first triangle
  uint q = r - offsets[t];
  for (uint f = 0u; f < kGridFaces; ++f) {
    const uvec4 s = spans[t * kGridFaces + f];
    const uint size = SpanSize(s);
    if (q >= size) {
      q -= size;
      continue;
    }
    const uint i0 = s.x & 0xFFFFu, j0 = s.y & 0xFFFFu, k0 = s.z & 0xFFFFu;
    const uint w = (s.x >> 16) - i0 + 1u, h = (s.y >> 16) - j0 + 1u;
    const uint cell = CellOf(f, i0 + q % w, j0 + q / w % h, k0 + q / (w * h));
    // Fault 2: a reference's cell the next one (within the grid).
    ref_cells[r] = kFault == 2u && cell + 1u < CellCount() ? cell + 1u : cell;
    ref_tris[r] = t;
    // Fault 3: the rectangle's u and v swapped.
    if (grid.shape.x == kGridKindPerspective) ref_boxes[r] = kFault == 3u ? span_boxes[t * kGridFaces + f].yxwz : span_boxes[t * kGridFaces + f];
    return;
  }
}

void main() {
  const uint g = WorkGroupIndex(), l = gl_LocalInvocationID.x;
  uint total;
  if (pc.phase == kGridBuildPhaseCount) {
    const uint t = GlobalIndex();
    if (t >= pc.count) return;
    SpansOf(t);
    uint n = 0u;
    for (uint f = 0u; f < kGridFaces; ++f) n += SpanSize(spans[t * kGridFaces + f]);
    counts[t] = n;
    if (grid.shape.x == kGridKindPerspective) dist[t] = LeastDistance(tris[t]);
  } else if (pc.phase == kGridBuildPhaseBlockSums) {
    if (g >= pc.blocks) return;  // uniform: the whole workgroup leaves
    WORKGROUP_SUM(counts, g * kScanBlock, min(pc.count, (g + 1u) * kScanBlock), total);
    if (l == 0u) sums[g] = total;
  } else if (pc.phase == kGridBuildPhaseScanSums) {
    if (g != 0u) return;
    WORKGROUP_SCAN_IN_PLACE(sums, 0u, pc.blocks, WorkgroupRank(), total);
    if (l == 0u) sums[pc.blocks] = total;
  } else if (pc.phase == kGridBuildPhaseOffsets) {
    if (g >= pc.blocks) return;
    const uint end = min(pc.count, (g + 1u) * kScanBlock);
    uint run = sums[g];
    const uint r = WorkgroupRank();
    for (uint c0 = g * kScanBlock; c0 < end; c0 += kLocalSize) {
      const uint t = c0 + r;
      const uint c = t < end ? counts[t] : 0u;
      const uint s = run + (WorkgroupInclusiveAdd(c, total) - c);  // references of the triangles before t
      // Fault 1 of grid.emit: an inclusive scan where an exclusive one belongs.
      if (t < end) offsets[t] = kFault == 1u ? s + c : s;
      run += total;
    }
  } else if (pc.phase == kGridBuildPhaseEmit) {
    const uint r = GlobalIndex();
    if (r < pc.refs) Emit(r);
  } else if (pc.phase == kGridBuildPhaseGather) {
    const uint i = GlobalIndex();
    if (i >= pc.count) return;
    // Fault 3 of grid.cells: gathered in emit order.
    const uint r = kFault == 3u ? i : order[i];
    list_tris[i] = ref_tris[r];
    if (pc.blocks != 0u) list_boxes[i] = ref_boxes[r];  // a 2D grid's rectangles
  } else if (pc.phase == kGridBuildPhaseCells) {
    const uint cell = GlobalIndex();
    if (cell > pc.count) return;  // pc.count cells, then the total
    // Fault 1 of grid.cells: a cell's offset is its upper bound.
    first[cell] = LowerBound(kFault == 1u && cell < pc.count ? cell + 1u : cell);
    if (pc.blocks != 0u && cell < pc.count) min_dist[cell] = floatBitsToUint(1.0 / 0.0);
  } else {
    const uint i = GlobalIndex();
    if (i >= pc.count) return;
    const uint cell = ref_cells[order[i]];
    // Fault 2 of grid.cells: the last reference of each cell left out of its least distance.
    if (kFault == 2u && (i + 1u == pc.count || ref_cells[order[i + 1u]] != cell)) return;
    // Non-negative floats order as their bits: the minimum, whatever order the invocations run in.
    atomicMin(min_dist[cell], floatBitsToUint(dist[list_tris[i]]));
  }
}
