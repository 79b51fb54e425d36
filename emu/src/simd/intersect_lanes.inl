// emu::IntersectWatertight on a lane type L (lanes_avx2.cpp, lanes_avx512.cpp), rays varying across
// lanes and one triangle: every lane performs the scalar test's operations in its order (each
// intrinsic one IEEE operation, no FMA) with the per-ray axis permutation done by selects, so each
// lane answers as the scalar test does, bit for bit (tests/intersect_simd_test.cpp).
//
// Besides what cone_lanes.inl uses, L provides Div, SelectV(c, a, b) = c ? a : b on values, Not,
// EqInt(p, k) (lanes whose int at p is k) and Store.

using intersect_lanes::RayArrays;
using intersect_lanes::Triangle;

struct V3 {
  typename L::V x, y, z;
};

inline typename L::V MaxAbs1(const V3& a) { return L::MaxOrdered(L::MaxOrdered(L::Abs(a.x), L::Abs(a.y)), L::Abs(a.z)); }

// emu: Max(MaxAbs(A0, B0), MaxAbs(C0, C0)). The instruction's max, not GLSL's: they differ only
// when an operand is NaN, and a lane with a NaN coordinate of the vertices or the origin misses
// whatever its scale: t = A0.n / d.n is NaN (n is NaN when a vertex is).
inline typename L::V Largest(const V3& A0, const V3& B0, const V3& C0) {
  const typename L::V mc = MaxAbs1(C0);
  return L::MaxOrdered(L::MaxOrdered(MaxAbs1(A0), MaxAbs1(B0)), L::MaxOrdered(mc, mc));
}

// Component k of a point for each lane (k = 0, 1, 2 per lane).
struct Pick {
  typename L::M is0, is1;
  explicit Pick(const std::int32_t* k) : is0(L::EqInt(k, 0)), is1(L::EqInt(k, 1)) {}
  typename L::V operator()(const V3& a) const { return L::SelectV(is0, a.x, L::SelectV(is1, a.y, a.z)); }
};

// The sheared 2D vertex: (P[kx] - sx P[kz], P[ky] - sy P[kz]).
inline void Shear(const V3& P, const Pick& kx, const Pick& ky, const Pick& kz, typename L::V sx, typename L::V sy, typename L::V& px,
                  typename L::V& py) {
  const typename L::V pz = kz(P);
  px = L::Sub(kx(P), L::Mul(sx, pz));
  py = L::Sub(ky(P), L::Mul(sy, pz));
}

inline V3 Minus(const float p[3], const V3& o) { return {L::Sub(L::Set(p[0]), o.x), L::Sub(L::Set(p[1]), o.y), L::Sub(L::Set(p[2]), o.z)}; }
inline V3 Scaled(const V3& a, typename L::V k) { return {L::Mul(a.x, k), L::Mul(a.y, k), L::Mul(a.z, k)}; }

// Woop's inside decision: no edge function of the opposite sign to another, and a non-zero sum.
inline typename L::M Inside(typename L::V u, typename L::V v, typename L::V w) {
  const typename L::V zero = L::Set(0.0f);
  const typename L::M neg = L::Or(L::Or(L::template Cmp<_CMP_LT_OQ>(u, zero), L::template Cmp<_CMP_LT_OQ>(v, zero)),
                                  L::template Cmp<_CMP_LT_OQ>(w, zero));
  const typename L::M pos = L::Or(L::Or(L::template Cmp<_CMP_GT_OQ>(u, zero), L::template Cmp<_CMP_GT_OQ>(v, zero)),
                                  L::template Cmp<_CMP_GT_OQ>(w, zero));
  const typename L::V det = L::Add(L::Add(u, v), w);
  return L::Not(L::Or(L::And(neg, pos), L::template Cmp<_CMP_EQ_OQ>(det, zero)));
}

// Rays [j, j + W) against tri: bit i set when ray j + i hits with tmin < t < tmax; t[i] its distance.
inline std::uint32_t RaysLanes(const RayArrays& r, const Triangle& tri, std::uint32_t j, float* t_out) {
  using V = typename L::V;
  const V3 org{L::Load(r.ox + j), L::Load(r.oy + j), L::Load(r.oz + j)};
  const V3 A0 = Minus(tri.v0, org), B0 = Minus(tri.v1, org), C0 = Minus(tri.v2, org);
  const V ka = L::InversePowerOfTwo(Largest(A0, B0, C0));
  const V3 A = Scaled(A0, ka), B = Scaled(B0, ka), C = Scaled(C0, ka);
  const Pick kx(r.kx + j), ky(r.ky + j), kz(r.kz + j);
  const V sx = L::Load(r.sx + j), sy = L::Load(r.sy + j);
  V ax, ay, bx, by, cx, cy;
  Shear(A, kx, ky, kz, sx, sy, ax, ay);
  Shear(B, kx, ky, kz, sx, sy, bx, by);
  Shear(C, kx, ky, kz, sx, sy, cx, cy);
  const V u = L::Sub(L::Mul(cx, by), L::Mul(cy, bx)), v = L::Sub(L::Mul(ax, cy), L::Mul(ay, cx)),
          w = L::Sub(L::Mul(bx, ay), L::Mul(by, ax));
  // t = A0.n / d.n (emu Dot order).
  const V nx = L::Set(tri.n[0]), ny = L::Set(tri.n[1]), nz = L::Set(tri.n[2]);
  const V num = L::Add(L::Add(L::Mul(A0.x, nx), L::Mul(A0.y, ny)), L::Mul(A0.z, nz));
  const V den = L::Add(L::Add(L::Mul(L::Load(r.dx + j), nx), L::Mul(L::Load(r.dy + j), ny)), L::Mul(L::Load(r.dz + j), nz));
  const V t = L::Div(num, den);
  const typename L::M in_range =
      L::And(L::template Cmp<_CMP_GT_OQ>(t, L::Load(r.tmin + j)), L::template Cmp<_CMP_LT_OQ>(t, L::Load(r.tmax + j)));
  L::Store(t_out, t);
  return L::Bits(L::And(Inside(u, v, w), in_range));
}

// One ray against W triangles (grid.trace's cell lists): the same operations per lane as RaysLanes,
// with the ray's axis permutation fixed, so the component picks need no selects.
inline std::uint32_t TrianglesLanes(const intersect_lanes::OneRay& r, const intersect_lanes::TriangleLanes& tris, float* t_out) {
  using V = typename L::V;
  const auto load = [&](int f) { return L::Load(tris.v[f]); };
  const auto minus = [&](int f) { return V3{L::Sub(load(f), L::Set(r.org[0])), L::Sub(load(f + 1), L::Set(r.org[1])), L::Sub(load(f + 2), L::Set(r.org[2]))}; };
  const V3 A0 = minus(0), B0 = minus(3), C0 = minus(6);
  const V ka = L::InversePowerOfTwo(Largest(A0, B0, C0));
  const V3 A = Scaled(A0, ka), B = Scaled(B0, ka), C = Scaled(C0, ka);
  const auto pick = [](const V3& p, std::int32_t k) { return k == 0 ? p.x : (k == 1 ? p.y : p.z); };
  const V sx = L::Set(r.sx), sy = L::Set(r.sy);
  const auto shear = [&](const V3& P, V& px, V& py) {
    const V pz = pick(P, r.kz);
    px = L::Sub(pick(P, r.kx), L::Mul(sx, pz));
    py = L::Sub(pick(P, r.ky), L::Mul(sy, pz));
  };
  V ax, ay, bx, by, cx, cy;
  shear(A, ax, ay);
  shear(B, bx, by);
  shear(C, cx, cy);
  const V u = L::Sub(L::Mul(cx, by), L::Mul(cy, bx)), v = L::Sub(L::Mul(ax, cy), L::Mul(ay, cx)),
          w = L::Sub(L::Mul(bx, ay), L::Mul(by, ax));
  const V nx = load(9), ny = load(10), nz = load(11);
  const V num = L::Add(L::Add(L::Mul(A0.x, nx), L::Mul(A0.y, ny)), L::Mul(A0.z, nz));
  const V den = L::Add(L::Add(L::Mul(L::Set(r.dir[0]), nx), L::Mul(L::Set(r.dir[1]), ny)), L::Mul(L::Set(r.dir[2]), nz));
  const V t = L::Div(num, den);
  const typename L::M in_range = L::And(L::template Cmp<_CMP_GT_OQ>(t, L::Set(r.tmin)), L::template Cmp<_CMP_LT_OQ>(t, L::Set(r.tmax)));
  L::Store(t_out, t);
  return L::Bits(L::And(Inside(u, v, w), in_range));
}
