// cone::TestOf<float> on a lane type L (lanes_avx2.cpp, lanes_avx512.cpp), included by
// each instruction set's unit after it defines L. Every lane performs the scalar test's operations
// in the scalar test's order, each intrinsic one IEEE operation (no FMA: explicit intrinsics only,
// and -ffp-contract=off), both branches computed and chosen by masks, and GLSL's max kept (L::Max),
// so each lane answers as the scalar test does, bit for bit (tests/cone_simd_test.cpp).
//
// L provides: V (W floats), M (W lane flags), W; Set, Load, Add, Sub, Mul, Sqrt, Abs, Max, MaxOrdered
// (the instruction: Max where no operand is NaN), AnyNaN,
// InversePowerOfTwo; Cmp<predicate>; Or, And, Select(c, a, b) = c ? a : b; Bits; and
// Emit(bits, first, shift, out) writing first + (lane << shift) for each set lane, returning the count.
// A sixteen-lane L also provides Load2, Set2 and Emit2, which fill its two halves from two sources
// (two pairs of at most eight children in one test).
// The including unit includes rayspace/contract.h (kRadiusSlack, kTestSlack) first.


struct NodeV {
  typename L::V x, y, z, r, ax, ay, az, cosa, sina;
};
struct SphereV {
  typename L::V x, y, z, r;
};

inline typename L::V Dot3(typename L::V ax, typename L::V ay, typename L::V az, typename L::V bx, typename L::V by,
                          typename L::V bz) {
  return L::Add(L::Add(L::Mul(ax, bx), L::Mul(ay, by)), L::Mul(az, bz));
}

inline typename L::M TestLanes(const NodeV& n, const SphereV& s, typename L::V eps) {
  using V = typename L::V;
  using M = typename L::M;
  const V zero = L::Set(0.0f);
  const M full = L::template Cmp<_CMP_LE_OQ>(n.cosa, L::Set(-1.0f));
  const V v0x = L::Sub(s.x, n.x), v0y = L::Sub(s.y, n.y), v0z = L::Sub(s.z, n.z);
  const V R0 = L::Add(L::Mul(L::Add(s.r, n.r), L::Set(layout::kRadiusSlack)), eps);
  // GLSL's max differs from the instruction's only when an operand is NaN: the instruction alone
  // unless some lane has a NaN (a sum of the operands is NaN then, and sometimes when it is not).
  const bool nan = L::AnyNaN(L::Add(L::Add(v0x, v0y), L::Add(v0z, R0)));
  const V m = nan ? L::Max(L::Max(L::Max(L::Abs(v0x), L::Abs(v0y)), L::Abs(v0z)), R0)
                  : L::MaxOrdered(L::MaxOrdered(L::MaxOrdered(L::Abs(v0x), L::Abs(v0y)), L::Abs(v0z)), R0);
  // At the apex or out of float range: keep.
  const M out_of_range = L::Or(L::template Cmp<_CMP_NGT_UQ>(m, zero), L::template Cmp<_CMP_NLT_UQ>(m, L::Set(INFINITY)));
  const V k = L::InversePowerOfTwo(m);
  const V vx = L::Mul(v0x, k), vy = L::Mul(v0y, k), vz = L::Mul(v0z, k);
  const V a = Dot3(vx, vy, vz, n.ax, n.ay, n.az);
  // b = |v x axis| (emu Cross, then Length).
  const V cx = L::Sub(L::Mul(vy, n.az), L::Mul(vz, n.ay));
  const V cy = L::Sub(L::Mul(vz, n.ax), L::Mul(vx, n.az));
  const V cz = L::Sub(L::Mul(vx, n.ay), L::Mul(vy, n.ax));
  const V b = L::Sqrt(Dot3(cx, cy, cz, cx, cy, cz));
  const V sv = L::Sub(L::Mul(b, n.cosa), L::Mul(a, n.sina));
  const V cv = L::Add(L::Mul(a, n.cosa), L::Mul(b, n.sina));
  // Inside the cone: s < 0, or s = 0 with c >= 0.
  const M inside = L::Or(L::template Cmp<_CMP_LT_OQ>(sv, zero),
                         L::And(L::template Cmp<_CMP_EQ_OQ>(sv, zero), L::template Cmp<_CMP_GE_OQ>(cv, zero)));
  const V R = L::Add(L::Mul(R0, k), L::Mul(L::Add(L::Abs(a), b), L::Set(layout::kTestSlack)));
  const M surface = L::template Cmp<_CMP_LE_OQ>(sv, R);                                  // c > 0
  const M apex = L::template Cmp<_CMP_LE_OQ>(Dot3(vx, vy, vz, vx, vy, vz), L::Mul(R, R));  // else
  const M near = L::Select(L::template Cmp<_CMP_GT_OQ>(cv, zero), surface, apex);
  return L::Or(L::Or(full, out_of_range), L::Or(inside, near));
}

inline std::uint32_t Tail(std::uint32_t bits, std::uint32_t left) {
  return left < static_cast<std::uint32_t>(L::W) ? bits & ((1u << left) - 1u) : bits;
}

inline std::size_t SpheresRun(const Node& n, const SphereArrays& s, std::uint32_t i0, std::uint32_t i1, float eps, const Output& o) {
  const NodeV node{L::Set(n.x),  L::Set(n.y),  L::Set(n.z),    L::Set(n.r),   L::Set(n.ax),
                   L::Set(n.ay), L::Set(n.az), L::Set(n.cosa), L::Set(n.sina)};
  const typename L::V e = L::Set(eps);
  std::size_t count = 0;
  for (std::uint32_t i = i0; i < i1; i += L::W) {
    const SphereV sph{L::Load(s.x + i), L::Load(s.y + i), L::Load(s.z + i), L::Load(s.r + i)};
    const std::uint32_t bits = Tail(L::Bits(TestLanes(node, sph, e)), i1 - i);
    count += L::Emit(bits, o.first + (i << o.shift), o.shift, o.out + count);
  }
  return count;
}

inline std::size_t NodesRun(const NodeArrays& n, const float sphere[4], std::uint32_t k0, std::uint32_t k1, float eps,
                            const Output& o) {
  const SphereV sph{L::Set(sphere[0]), L::Set(sphere[1]), L::Set(sphere[2]), L::Set(sphere[3])};
  const typename L::V e = L::Set(eps);
  std::size_t count = 0;
  for (std::uint32_t k = k0; k < k1; k += L::W) {
    const NodeV node{L::Load(n.x + k),  L::Load(n.y + k),  L::Load(n.z + k),    L::Load(n.r + k),   L::Load(n.ax + k),
                     L::Load(n.ay + k), L::Load(n.az + k), L::Load(n.cosa + k), L::Load(n.sina + k)};
    const std::uint32_t bits = Tail(L::Bits(TestLanes(node, sph, e)), k1 - k);
    count += L::Emit(bits, o.first + (k << o.shift), o.shift, o.out + count);
  }
  return count;
}

// One pair of a level: its parent's children [k0, k1), its sphere and the value of child 0.
struct PairRef {
  std::uint32_t k0, k1;
  const float* sphere;
  std::uint32_t first;
};

inline PairRef RefOf(const PairLevel& lv, std::size_t p) {
  const std::uint32_t parent = lv.base_up + (lv.pairs[p] >> lv.bits), tri = lv.pairs[p] & ((1u << lv.bits) - 1u);
  return {lv.first[parent], lv.first[parent + 1], lv.spheres4 + 4 * static_cast<std::size_t>(tri), tri - (lv.base << lv.bits)};
}

template <class LL>
NodeV LoadTwo(const NodeArrays& n, std::uint32_t a, std::uint32_t b) {
  return {LL::Load2(n.x + a, n.x + b),   LL::Load2(n.y + a, n.y + b),   LL::Load2(n.z + a, n.z + b),
          LL::Load2(n.r + a, n.r + b),   LL::Load2(n.ax + a, n.ax + b), LL::Load2(n.ay + a, n.ay + b),
          LL::Load2(n.az + a, n.az + b), LL::Load2(n.cosa + a, n.cosa + b), LL::Load2(n.sina + a, n.sina + b)};
}

// Pairs a and b, each of at most eight children, in the two halves of one sixteen-lane test; node
// holds a's children in the low half and b's in the high half.
template <class LL>
std::size_t TwoPairs(const NodeV& node, const PairRef& a, const PairRef& b, float eps, int bits, std::uint32_t* out) {
  const SphereV sph{LL::Set2(a.sphere[0], b.sphere[0]), LL::Set2(a.sphere[1], b.sphere[1]), LL::Set2(a.sphere[2], b.sphere[2]),
                    LL::Set2(a.sphere[3], b.sphere[3])};
  const std::uint32_t valid = ((1u << (a.k1 - a.k0)) - 1u) | (((1u << (b.k1 - b.k0)) - 1u) << 8);
  const std::uint32_t hits = LL::Bits(TestLanes(node, sph, LL::Set(eps))) & valid;
  return LL::Emit2(hits, a.first + (a.k0 << bits), b.first + (b.k0 << bits), bits, out);
}

// A level's pairs in order. With sixteen lanes, two pairs of at most eight children share a test;
// consecutive pairs mostly share their parent (a top node's surviving triangles are consecutive),
// and then its children are loaded into both halves once for the whole run.
template <class LL = L>
std::size_t PairsRun(const NodeArrays& n, const PairLevel& lv, std::size_t p0, std::size_t p1, float eps, std::uint32_t* out,
                     std::uint64_t* tested) {
  std::size_t count = 0;
  std::uint64_t t = 0;
  [[maybe_unused]] std::uint32_t loaded = ~0u;  // the parent whose children `both` holds twice
  [[maybe_unused]] NodeV both{};
  for (std::size_t p = p0; p < p1; ++p) {
    const PairRef a = RefOf(lv, p);
    t += a.k1 - a.k0;
    if constexpr (LL::W == 16) {
      if (a.k1 - a.k0 <= 8 && p + 1 < p1) {
        const PairRef b = RefOf(lv, p + 1);
        if (b.k1 - b.k0 <= 8) {
          t += b.k1 - b.k0;
          if (a.k0 == b.k0 && loaded != a.k0) {
            both = LoadTwo<LL>(n, a.k0, a.k0);
            loaded = a.k0;
          }
          count += TwoPairs<LL>(a.k0 == b.k0 ? both : LoadTwo<LL>(n, a.k0, b.k0), a, b, eps, lv.bits, out + count);
          ++p;
          continue;
        }
      }
    }
    count += NodesRun(n, a.sphere, a.k0, a.k1, eps, Output{a.first, lv.bits, out + count});
  }
  *tested += t;
  return count;
}
