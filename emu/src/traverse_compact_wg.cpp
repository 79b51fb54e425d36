// traverse.compact on the workgroup model: mirrors gpu/shaders/traverse_compact.comp dispatch for
// dispatch (Groups, Test, Scan, Scatter) and phase for phase, with its push constants, tiles, rounds,
// shuffles, group spheres and row culling, packing, scratch and count buffers and its planted faults
// 1..6, so that --check-workgroups, --schedule and `--inject traverse.compact:N@emu` reach the
// kernel's structure and not only its result. The cone-sphere test is the pass-by-pass traversal's
// scalar cone::Test, bit for bit the kernel's ConeTest, and the group test cone::DeviceGroupMisses,
// the kernel's cone_cull.glsl. The host's parts (bindings of limited size) are not mirrored: one part
// covers the call, and parts only concatenate in slot order.
#include <algorithm>
#include <array>
#include <bit>

#include "rayspace/contract.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/cone_cull.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/error.h"

namespace rayspace::emu {
namespace {

using layout::kCompactBlock;
using layout::kCompactChunk;

using layout::kCompactCols;
using layout::kCompactRows;
using RowNodes = wg::Private<std::array<layout::ConeNode, kCompactRows>>;

// A row's 16-bit field of the top phase's packed counts.
std::uint32_t Field(const glm::uvec4& v, std::uint32_t r) { return (v[r >> 1] >> ((r & 1u) * 16u)) & 0xFFFFu; }

// The kernel's WorkgroupInclusiveAdd4: subgroup scans of the four words, one uvec4 per subgroup in
// shared memory, two barriers.
wg::Private<glm::uvec4> WorkgroupInclusiveAdd4(wg::Workgroup& w, wg::Shared<glm::uvec4>& tile, const wg::Private<glm::uvec4>& v,
                                               wg::Private<glm::uvec4>& total) {
  wg::Private<glm::uvec4> inclusive = w.Private<glm::uvec4>(), subgroup_sum = inclusive;
  for (int c = 0; c < 4; ++c) {  // subgroupInclusiveAdd / subgroupAdd of a uvec4 act per component
    wg::Private<std::uint32_t> x = w.Private<std::uint32_t>();
    w.Phase([&](wg::Inv& i) { x[i] = v[i][c]; });
    const wg::Private<std::uint32_t> in = w.SubgroupInclusiveAdd(x), sum = w.SubgroupAdd(x);
    w.Phase([&](wg::Inv& i) { inclusive[i][c] = in[i], subgroup_sum[i][c] = sum[i]; });
  }
  const wg::Private<bool> elect = w.SubgroupElect();
  w.Phase([&](wg::Inv& i) {
    if (elect[i]) tile[i.subgroup_id] = subgroup_sum[i];
  });
  w.Barrier();
  wg::Private<glm::uvec4> out = w.Private<glm::uvec4>();
  w.Phase([&](wg::Inv& i) {
    glm::uvec4 before(0u), all(0u);
    for (std::uint32_t k = 0; k < w.num_subgroups(); ++k) {
      const glm::uvec4 x = tile[k];
      if (k < i.subgroup_id) before += x;
      all += x;
    }
    total[i] = all;
    out[i] = before + inclusive[i];
  });
  w.Barrier();  // the tile is free for the next round
  return out;
}

// One part of traverse_compact.comp: the push constants and buffers the host binds, and the three
// dispatches over them.
class CompactKernel {
 public:
  CompactKernel(const layout::TraverseCompactPush& pc, In<glm::vec4> tri_spheres)
      : site_(KernelSite::Of("traverse.compact")), pc_(pc), tri_spheres_(tri_spheres) {
    // The host's new buffers hold the poison word; a planted fault that leaves words unwritten
    // leaves the same words here.
    scratch_.assign(pc.count, layout::kPoisonWord);
    counts_.assign(std::size_t{pc.blocks} + 1, layout::kPoisonWord);
    tested_.assign(std::size_t{pc.blocks} + 1, layout::kPoisonWord);
    out_.assign(pc.count, layout::kPoisonWord);
  }
  void BindTop(In<layout::ConeNode> top, In<layout::TriangleInfo> info, In<std::uint8_t> mask_rows) {
    nodes_ = top, info_ = info;
    if (pc_.use_mask != 0u) mask_tiles_ = PackMaskTiles(mask_rows, pc_.blocks, pc_.objects);
  }
  void BindLevel(In<std::uint32_t> pairs, In<layout::ConeNode> nodes, In<std::uint32_t> first) {
    pairs_ = pairs, nodes_ = nodes, first_ = first;
  }

  // The host's submit (phase A, Scan, Scatter) and read-back: the total after the scanned counts,
  // the tests after the block tests.
  Compacted Run() {
    // Level and Scatter on the kernel's grid of at most kCompactStrideGroups, striding over the blocks.
    const std::uint32_t grid = std::min(pc_.blocks, layout::kCompactStrideGroups);
    if (pc_.phase == layout::kTraverseCompactPhaseTop) {
      const std::uint64_t round = std::uint64_t{wg::LocalSize()} * kCompactCols;
      const auto rounds = static_cast<std::uint32_t>((pc_.tris + round - 1) / round);
      const glm::vec4 poison(std::bit_cast<float>(layout::kPoisonWord));
      groups_.assign(std::max<std::size_t>(1, std::size_t{rounds} * wg::LocalSize()), poison);
      objects_.assign(std::max<std::size_t>(1, std::size_t{rounds} * wg::LocalSize()), layout::kPoisonWord);
      DispatchKernel(site_, "Groups", rounds, [&](wg::Workgroup& w) { GroupsOfRound(w); });
      DispatchKernel(site_, "Test", (pc_.blocks + kCompactRows - 1) / kCompactRows, [&](wg::Workgroup& w) { TestTopTile(w); });
    } else {
      DispatchKernel(site_, "Test", grid, [&](wg::Workgroup& w) {
        for (std::uint32_t g = w.id(); g < pc_.blocks; g += grid) TestBlock(w, g);
      });
    }
    DispatchKernel(site_, "Scan", 1, [&](wg::Workgroup& w) { ScanBlocks(w); });
    DispatchKernel(site_, "Scatter", grid, [&](wg::Workgroup& w) {
      for (std::uint32_t g = w.id(); g < pc_.blocks; g += grid) ScatterBlock(w, g);
    });
    const std::uint32_t total = counts_[pc_.blocks];
    RS_CHECK_MSG(total <= pc_.count, "traverse.compact: {} survivors of {} slots", total, pc_.count);
    Compacted r;
    r.pairs.assign(out_.begin(), out_.begin() + total);
    r.tested = tested_[pc_.blocks];
    return r;
  }

 private:
  // RowBits: bit r set when row0 + r's node may meet triangles of `object` (traverse.comp's
  // object-mask rule: a slot whose triangle's object the node misses runs no test); one word of the
  // packed mask per tile and object.
  std::uint32_t RowBits(std::uint32_t object, std::uint32_t row0, std::uint32_t rows) const {
    if (pc_.use_mask == 0u) return (1u << rows) - 1u;
    return mask_tiles_[std::size_t{row0 / kCompactRows} * pc_.objects + object];
  }

  // Each invocation's row nodes: RowNode's subgroupShuffle of lane r's node when lanes 0 ..
  // kCompactRows - 1 of its subgroup are there (SharedRows' ballot), else a load. The shuffles run
  // once per tile here, once per round in the kernel: the same values (mine does not change).
  RowNodes NodesOfRows(wg::Workgroup& w, std::uint32_t row0, std::uint32_t rows, wg::Private<bool>& shared_rows) {
    wg::Private<layout::ConeNode> mine = w.Private<layout::ConeNode>();
    w.Phase([&](wg::Inv& i) { mine[i] = nodes_[pc_.t0 + row0 + std::min(i.lane, rows - 1u)]; });
    const wg::Private<glm::uvec4> ballot = w.SubgroupBallot(w.Private<bool>(true));
    constexpr std::uint32_t kLow = (1u << kCompactRows) - 1u;
    const auto full = [&](const wg::Inv& i) { return w.subgroup_size() >= kCompactRows && (ballot[i].x & kLow) == kLow; };
    RowNodes out = w.Private<std::array<layout::ConeNode, kCompactRows>>();
    w.Phase([&](wg::Inv& i) { shared_rows[i] = full(i); });
    for (std::uint32_t r = 0; r < rows; ++r) {
      wg::Private<std::uint32_t> src = w.Private<std::uint32_t>();
      w.Phase([&](wg::Inv& i) { src[i] = full(i) ? r : i.lane; });  // a short subgroup reads memory instead
      const wg::Private<layout::ConeNode> shuffled = w.SubgroupShuffle(mine, src);
      w.Phase([&](wg::Inv& i) { out[i][r] = full(i) ? shuffled[i] : nodes_[pc_.t0 + row0 + r]; });
    }
    return out;
  }

  // An invocation's triangles of a round: kCompactCols spheres from col0 (loaded after the row cull,
  // only for a subgroup with a live row) and, per triangle, bit r set when row r tests it (the object
  // mask).
  struct Round {
    std::array<glm::vec4, kCompactCols> sphere{};
    std::array<std::uint32_t, kCompactCols> may{};
  };
  // The last object's row bits, kept across an invocation's rounds as the kernel keeps them.
  struct ObjectBits {
    std::uint32_t object = layout::kCompactMixedObjects, bits = 0;
  };
  // `shared_object`: the invocation's object word from Groups (its triangles' one object, or
  // kCompactMixedObjects: then each triangle's own).
  Round LoadRound(std::uint32_t row0, std::uint32_t rows, std::uint32_t col0, std::uint32_t shared_object,
                  ObjectBits& last) const {
    Round in;
    for (std::uint32_t k = 0; k < kCompactCols && col0 + k < pc_.tris; ++k) {
      const std::uint32_t o = shared_object != layout::kCompactMixedObjects ? shared_object : info_[pc_.b0 + col0 + k].ids.y;
      if (o != last.object) last.bits = RowBits(o, row0, rows);
      last.object = o;
      in.may[k] = last.bits;
    }
    return in;
  }

  // Phase Groups for round w.id() of the top phase: each subgroup's group sphere of its lanes'
  // triangles by subgroup min/max (the box of the centres, its centre, the largest reach widened),
  // written by the subgroup's first lane; a negative radius where the bound may not judge a member.
  // Each invocation writes its triangles' one object, or kCompactMixedObjects.
  void GroupsOfRound(wg::Workgroup& w) {
    const std::uint32_t c0 = w.id() * w.local_size() * kCompactCols;
    // Columns by rank; every subgroup of the model is Aligned (linear and full), so each group is judged.
    const wg::Private<std::uint32_t> rank = WorkgroupRank(w, WorkgroupTile(w));
    const auto valid = [&](const wg::Inv& i, std::uint32_t k) { return c0 + rank[i] * kCompactCols + k < pc_.tris; };
    const auto sphere = [&](const wg::Inv& i, std::uint32_t k) {
      return tri_spheres_[pc_.b0 + c0 + rank[i] * kCompactCols + k];
    };
    wg::Private<glm::vec3> lo = w.Private<glm::vec3>(), hi = lo;
    wg::Private<std::uint32_t> ok = w.Private<std::uint32_t>();
    w.Phase([&](wg::Inv& i) {
      glm::vec3 l(layout::kDeviceCullLimit), h(-layout::kDeviceCullLimit);
      bool good = true;
      for (std::uint32_t k = 0; k < kCompactCols; ++k) {
        if (!valid(i, k)) continue;
        good = good && cone::DeviceCullable(sphere(i, k));
        l = glm::min(l, glm::vec3(sphere(i, k))), h = glm::max(h, glm::vec3(sphere(i, k)));
      }
      lo[i] = l, hi[i] = h, ok[i] = good ? 1u : 0u;
      std::uint32_t object = layout::kCompactMixedObjects;
      for (std::uint32_t k = 0; k < kCompactCols && valid(i, k); ++k) {
        // Fault 7: the first triangle's object taken for all of the invocation's triangles.
        const std::uint32_t o = pc_.use_mask == 0u ? 0u : info_[pc_.b0 + c0 + rank[i] * kCompactCols + k].ids.y;
        if (k == 0)
          object = o;
        else if (o != object && site_.fault != 7u)
          object = layout::kCompactMixedObjects;
      }
      objects_[std::size_t{w.id()} * w.local_size() + rank[i]] = object;
    });
    lo = w.SubgroupReduce(lo, [](glm::vec3 a, glm::vec3 b) { return glm::min(a, b); });
    hi = w.SubgroupReduce(hi, [](glm::vec3 a, glm::vec3 b) { return glm::max(a, b); });
    ok = w.SubgroupReduce(ok, [](std::uint32_t a, std::uint32_t b) { return std::min(a, b); });
    wg::Private<float> reach = w.Private<float>();
    w.Phase([&](wg::Inv& i) {
      const glm::vec3 c = (lo[i] + hi[i]) * 0.5f;
      float r = 0.0f;
      for (std::uint32_t k = 0; k < kCompactCols; ++k)
        if (valid(i, k)) r = std::max(r, cone::DeviceReach(sphere(i, k), c));
      reach[i] = r;
    });
    reach = w.SubgroupReduce(reach, [](float a, float b) { return std::max(a, b); });
    const wg::Private<bool> elect = w.SubgroupElect();
    w.Phase([&](wg::Inv& i) {
      if (!elect[i]) return;
      const float radius = reach[i] * layout::kDeviceCullRadiusUp;
      const glm::vec3 c = (lo[i] + hi[i]) * 0.5f;
      groups_[std::size_t{w.id()} * w.num_subgroups() + i.subgroup_id] = glm::vec4(c, ok[i] ? radius : -1.0f);
    });
  }

  // The kernel's LiveRows: per subgroup, the rows less those whose node provably misses the group
  // Groups wrote for the subgroup and round (cone::DeviceGroupMisses, lane r for row r); all rows
  // under the printed test or where the rows' nodes are not shared.
  wg::Private<std::uint32_t> LiveRows(wg::Workgroup& w, const RowNodes& node, const wg::Private<bool>& shared_rows,
                                      std::uint32_t round, std::uint32_t rows) const {
    const std::uint32_t all_rows = (1u << rows) - 1u;
    wg::Private<std::uint32_t> live = w.Private<std::uint32_t>(all_rows);
    if (pc_.cone_test != layout::kConeTestConservative) return live;
    // Fault 5: the margin planted at -1/2, which culls groups the test hits.
    const float margin = site_.fault == 5u ? -0.5f : layout::kDeviceCullMargin;
    wg::Private<bool> miss = w.Private<bool>();
    w.Phase([&](wg::Inv& i) {
      const glm::vec4 group = groups_[std::size_t{round} * w.num_subgroups() + i.subgroup_id];
      miss[i] = i.lane < rows && cone::DeviceGroupMisses(node[i][i.lane], group, pc_.eps, margin);
    });
    const wg::Private<glm::uvec4> ballot = w.SubgroupBallot(miss);
    w.Phase([&](wg::Inv& i) { live[i] = shared_rows[i] ? all_rows & ~ballot[i].x : all_rows; });
    return live;
  }

  // One invocation's round of TestTopTile: its triangles against the live rows; hit[r] bit k: column
  // col0 + k survives in row r. Returns the rows' survivor counts, 16 bits each.
  glm::uvec4 TestTopRound(const std::array<layout::ConeNode, kCompactRows>& node, const Round& in, std::uint32_t live,
                          std::uint32_t rows, std::array<std::uint32_t, kCompactRows>& hit) const {
    hit.fill(0u);
    for (std::uint32_t bits = live; bits != 0u; bits &= bits - 1u) {
      const auto r = static_cast<std::uint32_t>(std::countr_zero(bits));
      for (std::uint32_t k = 0; k < kCompactCols; ++k)
        if ((in.may[k] >> r & 1u) != 0u && cone::TestBy(pc_.cone_test, node[r], in.sphere[k], pc_.eps)) hit[r] |= 1u << k;
    }
    glm::uvec4 n(0u);
    for (std::uint32_t r = 0; r < rows; ++r) n[r >> 1] += static_cast<std::uint32_t>(std::popcount(hit[r])) << ((r & 1u) * 16u);
    return n;
  }

  // Phase A at the top level for tile w.id(): rows [row0, row0 + rows) of the part, rounds of
  // local_size x kCompactCols triangles, one WorkgroupInclusiveAdd4 of the rows' counts a round.
  void TestTopTile(wg::Workgroup& w) {
    auto& tile = WorkgroupTile(w);
    auto& tile4 = w.Shared<glm::uvec4>(std::min(w.local_size(), layout::kMaxLocalSize / 4u), "wg_tile4");
    // The host refuses more subgroups than the kernel's wg_tile4 holds; so does the mirror.
    RS_CHECK_MSG(w.num_subgroups() <= layout::kMaxLocalSize / 4u, "traverse.compact: {} subgroups of {} exceed wg_tile4",
                 w.num_subgroups(), w.subgroup_size());
    const std::uint32_t row0 = w.id() * kCompactRows, rows = std::min(kCompactRows, pc_.blocks - row0);
    wg::Private<bool> shared_rows = w.Private<bool>();
    const RowNodes node = NodesOfRows(w, row0, rows, shared_rows);
    const wg::Private<std::uint32_t> rank = WorkgroupRank(w, tile);
    wg::Private<std::array<std::uint32_t, kCompactRows>> run = w.Private<std::array<std::uint32_t, kCompactRows>>(), hit = run;
    wg::Private<glm::uvec4> n = w.Private<glm::uvec4>(), sums = n;
    wg::Private<std::uint32_t> tests = w.Private<std::uint32_t>(), all_tests = tests;
    wg::Private<ObjectBits> last = w.Private<ObjectBits>();
    for (std::uint32_t c0 = 0; c0 < pc_.tris; c0 += w.local_size() * kCompactCols) {
      wg::Private<Round> in = w.Private<Round>();
      const std::uint32_t round = c0 / (w.local_size() * kCompactCols);
      w.Phase([&](wg::Inv& i) {
        // Without a mask every row tests every triangle: no object is read.
        const std::uint32_t shared_object =
            pc_.use_mask == 0u ? 0u : objects_[std::size_t{round} * w.local_size() + rank[i]];
        in[i] = LoadRound(row0, rows, c0 + rank[i] * kCompactCols, shared_object, last[i]);
        for (const std::uint32_t may : in[i].may) tests[i] += static_cast<std::uint32_t>(std::popcount(may));  // culled or not
      });
      const wg::Private<std::uint32_t> live = LiveRows(w, node, shared_rows, round, rows);
      w.Phase([&](wg::Inv& i) {
        // The spheres only for a subgroup with a live row, as the kernel loads them.
        if (live[i] != 0u)
          for (std::uint32_t k = 0; k < kCompactCols && c0 + rank[i] * kCompactCols + k < pc_.tris; ++k)
            in[i].sphere[k] = tri_spheres_[pc_.b0 + c0 + rank[i] * kCompactCols + k];
        n[i] = TestTopRound(node[i], in[i], live[i], rows, hit[i]);
      });
      const wg::Private<glm::uvec4> inclusive = WorkgroupInclusiveAdd4(w, tile4, n, sums);
      w.Phase([&](wg::Inv& i) {
        const glm::uvec4 before = inclusive[i] - n[i];  // fieldwise: no field borrows
        for (std::uint32_t r = 0; r < rows; ++r) {
          // Fault 3: every round starts at the row's start (the carry between rounds is dropped).
          std::uint32_t at = (row0 + r) * pc_.tris + (site_.fault == 3u ? 0u : run[i][r]) + Field(before, r);
          for (std::uint32_t bits = hit[i][r]; bits != 0u; bits &= bits - 1u)
            scratch_[at++] = ((pc_.t0 + row0 + r - pc_.id_base) << kPairTriangleBits) |
                             (c0 + rank[i] * kCompactCols + static_cast<std::uint32_t>(std::countr_zero(bits)));
          run[i][r] += Field(sums[i], r);
        }
      });
    }
    WorkgroupInclusiveAdd(w, tile, tests, all_tests, site_.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id != 0) return;
      for (std::uint32_t r = 0; r < rows; ++r) {
        // Fault 2: the last survivor of every block is dropped. Fault 4: the survivors reported as tests.
        counts_[row0 + r] = site_.fault == 2u && run[i][r] > 0u ? run[i][r] - 1u : run[i][r];
        tested_[row0 + r] = site_.fault == 4u ? run[i][r] : (r == 0 ? all_tests[i] : 0u);
      }
    });
  }

  // An invocation's (pair, chunk) of TestBlock: the pair's triangle and children from c0, the chunk's
  // first child kc, the children [a, b) it tests, and the survivors' bits (bit i: child kc + i).
  struct LevelChunk {
    bool valid = false;
    std::uint32_t parent = 0xFFFFFFFFu, tri_local = 0, c0 = 0, children = 0, kc = 0, a = 0, b = 0, hit = 0;
    glm::vec4 sphere{0.0f};
  };
  LevelChunk LoadChunk(std::uint32_t v, std::uint32_t chunks, std::uint32_t first, std::uint32_t end) const {
    const std::uint32_t cm = pc_.children_max, p = v / chunks;
    LevelChunk q;
    q.kc = (v - p * chunks) * kCompactChunk;
    q.valid = p * cm < end;
    if (!q.valid) return q;
    q.parent = pc_.base_up + (pairs_[p] >> kPairTriangleBits);
    q.tri_local = pairs_[p] & kPairTriangleMask;
    q.sphere = tri_spheres_[pc_.b0 + q.tri_local];
    q.c0 = first_[q.parent];
    q.children = first_[q.parent + 1u] - q.c0;
    // The chunk's children that the block holds (a block may begin or end inside a pair) and exist.
    q.a = std::max(std::max(first, p * cm) - p * cm, q.kc);
    q.b = std::max(q.a, std::min(std::min(end - p * cm, q.children), q.kc + kCompactChunk));
    return q;
  }

  // The subgroup's verdict on sharing its pairs' children: the kernel's full && subgroupAll(!valid ||
  // parent == subgroupMin(parent)), here by a reduction over its lanes.
  wg::Private<bool> SharedChildren(wg::Workgroup& w, const wg::Private<LevelChunk>& q, const wg::Private<bool>& full) {
    // Fault 6: pairs whose parents have as many children are taken to share them (children ==
    // subgroupMax(children) in place of parent == subgroupMin(parent)).
    const bool fault = site_.fault == 6u;
    wg::Private<std::uint32_t> key = w.Private<std::uint32_t>(), odd = key;
    w.Phase([&](wg::Inv& i) { key[i] = fault ? q[i].children : q[i].parent; });
    const wg::Private<std::uint32_t> lead =
        w.SubgroupReduce(key, [fault](std::uint32_t x, std::uint32_t y) { return fault ? std::max(x, y) : std::min(x, y); });
    w.Phase([&](wg::Inv& i) { odd[i] = q[i].valid && key[i] != lead[i] ? 1u : 0u; });
    odd = w.SubgroupReduce(odd, [](std::uint32_t x, std::uint32_t y) { return std::max(x, y); });
    wg::Private<bool> shared = w.Private<bool>();
    w.Phase([&](wg::Inv& i) { shared[i] = full[i] && odd[i] == 0u; });
    return shared;
  }

  // The kernel's shared path: per step of subgroup_size children from the subgroup's lowest, lane j
  // loads child sc0 + k0 + j and every lane tests the shuffled nodes of its range [a, b). The steps
  // run to the workgroup's longest subgroup; a subgroup past its own end idles.
  void TestShared(wg::Workgroup& w, wg::Private<LevelChunk>& q, const wg::Private<bool>& shared) {
    wg::Private<std::uint32_t> c0 = w.Private<std::uint32_t>(), sa = c0, sb = c0;
    w.Phase([&](wg::Inv& i) {
      const bool chunk = q[i].a < q[i].b;
      c0[i] = q[i].c0, sa[i] = chunk ? q[i].a : 0xFFFFFFFFu, sb[i] = chunk ? q[i].b : 0u;
    });
    const wg::Private<std::uint32_t> sc0 = w.SubgroupReduce(c0, [](std::uint32_t x, std::uint32_t y) { return std::max(x, y); });
    sa = w.SubgroupReduce(sa, [](std::uint32_t x, std::uint32_t y) { return std::min(x, y); });
    sb = w.SubgroupReduce(sb, [](std::uint32_t x, std::uint32_t y) { return std::max(x, y); });
    std::uint32_t steps = 0;
    w.Phase([&](wg::Inv& i) {
      if (shared[i] && sa[i] < sb[i]) steps = std::max(steps, (sb[i] - sa[i] + w.subgroup_size() - 1) / w.subgroup_size());
    });
    for (std::uint32_t step = 0; step < steps; ++step) {
      wg::Private<layout::ConeNode> mine = w.Private<layout::ConeNode>();
      w.Phase([&](wg::Inv& i) {
        const std::uint32_t k = sa[i] + step * w.subgroup_size() + i.lane;
        if (shared[i] && sa[i] < sb[i] && k < sb[i]) mine[i] = nodes_[sc0[i] + k];
      });
      for (std::uint32_t j = 0; j < w.subgroup_size(); ++j) {
        // Only sharing subgroups shuffle (the kernel's are full); the others read their own lane.
        wg::Private<std::uint32_t> src = w.Private<std::uint32_t>();
        w.Phase([&](wg::Inv& i) { src[i] = shared[i] ? j : i.lane; });
        const wg::Private<layout::ConeNode> node = w.SubgroupShuffle(mine, src);
        w.Phase([&](wg::Inv& i) {
          const std::uint32_t k = sa[i] + step * w.subgroup_size() + j;
          if (!shared[i] || sa[i] >= sb[i] || k >= sb[i]) return;
          if (k >= q[i].a && k < q[i].b && cone::TestBy(pc_.cone_test, node[i], q[i].sphere, pc_.eps)) q[i].hit |= 1u << (k - q[i].kc);
        });
      }
    }
  }

  // Phase A one level down for block g: the block's (pair, chunk)s in rounds of local_size, one
  // an invocation, one WorkgroupInclusiveAdd of (survivors, tests) a round. Every invocation runs
  // every round (the scan's barriers are uniform); the kernel's `run` and `tests` are locals of each
  // invocation, equal in all of them.
  void TestBlock(wg::Workgroup& w, std::uint32_t g) {
    auto& tile = WorkgroupTile(w);
    const std::uint32_t first = g * kCompactBlock, end = std::min(pc_.count, first + kCompactBlock);
    const std::uint32_t cm = pc_.children_max, chunks = (cm + kCompactChunk - 1) / kCompactChunk;
    const wg::Private<glm::uvec4> ballot = w.SubgroupBallot(w.Private<bool>(true));
    wg::Private<bool> full = w.Private<bool>();
    w.Phase([&](wg::Inv& i) {  // subgroupBallotBitCount: all four words (subgroups of up to 128 lanes)
      const glm::uvec4 b = ballot[i];
      full[i] = static_cast<std::uint32_t>(std::popcount(b.x) + std::popcount(b.y) + std::popcount(b.z) + std::popcount(b.w)) ==
                w.subgroup_size();
    });
    const wg::Private<std::uint32_t> rank = WorkgroupRank(w, tile);
    wg::Private<std::uint32_t> run = w.Private<std::uint32_t>(), tests = run, sums = run;
    for (std::uint32_t v0 = first / cm * chunks; v0 / chunks * cm < end; v0 += w.local_size()) {
      wg::Private<LevelChunk> q = w.Private<LevelChunk>();
      w.Phase([&](wg::Inv& i) { q[i] = LoadChunk(v0 + rank[i], chunks, first, end); });
      const wg::Private<bool> shared = SharedChildren(w, q, full);
      w.Phase([&](wg::Inv& i) {
        if (shared[i]) return;
        for (std::uint32_t k = q[i].a; k < q[i].b; ++k)
          if (cone::TestBy(pc_.cone_test, nodes_[q[i].c0 + k], q[i].sphere, pc_.eps)) q[i].hit |= 1u << (k - q[i].kc);
      });
      TestShared(w, q, shared);
      wg::Private<std::uint32_t> n = w.Private<std::uint32_t>(), packed = n;
      w.Phase([&](wg::Inv& i) {
        n[i] = static_cast<std::uint32_t>(std::popcount(q[i].hit));
        packed[i] = n[i] | ((q[i].b - q[i].a) << 16);  // survivors and tests in one scan, 16 bits each
      });
      const wg::Private<std::uint32_t> inclusive = WorkgroupInclusiveAdd(w, tile, packed, sums, site_.fault);
      w.Phase([&](wg::Inv& i) {
        const std::uint32_t before = (inclusive[i] & 0xFFFFu) - n[i];
        // Fault 3: every round starts at the block's start (the carry between rounds is dropped).
        std::uint32_t at = first + (site_.fault == 3u ? 0u : run[i]) + before;
        // A store past the buffer (only a planted fault makes one) is not made. The device enables
        // no robust buffer access: its store lands in the guard words, which fail the call (docs/gpu.md).
        for (std::uint32_t bits = q[i].hit; bits != 0u; bits &= bits - 1u, ++at)
          if (at < pc_.count)
            scratch_[at] = ((q[i].c0 + q[i].kc + static_cast<std::uint32_t>(std::countr_zero(bits)) - pc_.base) << kPairTriangleBits) |
                           q[i].tri_local;
        run[i] += sums[i] & 0xFFFFu;
        tests[i] += sums[i] >> 16;
      });
    }
    w.Phase([&](wg::Inv& i) {
      if (i.local_id != 0) return;
      // Fault 2: the last survivor of every block is dropped. Fault 4: the survivors reported as tests.
      counts_[g] = site_.fault == 2u && run[i] > 0u ? run[i] - 1u : run[i];
      tested_[g] = site_.fault == 4u ? run[i] : tests[i];
    });
  }

  // Phase Scan (one workgroup): exclusive offsets of the blocks with the total last, and the sum of
  // their tests. The kernel's store of the total and WORKGROUP_SUM's loads share a barrier interval;
  // they touch different buffers, so the phase boundary between them here changes nothing.
  void ScanBlocks(wg::Workgroup& w) {
    auto& tile = WorkgroupTile(w);
    const std::uint32_t total = WorkgroupScanInPlace(w, tile, counts_.data(), pc_.blocks, WorkgroupRank(w, tile), site_.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id == 0) counts_[pc_.blocks] = total;
    });
    const wg::Private<std::uint32_t> sum = WorkgroupSum(
        w, tile, [&](std::uint32_t k) { return tested_[k]; }, 0u, pc_.blocks, site_.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id == 0) tested_[pc_.blocks] = sum[i];
    });
  }

  // Phase Scatter for block g: its survivors from its scratch region to its offset.
  void ScatterBlock(wg::Workgroup& w, std::uint32_t g) {
    const std::uint32_t at = counts_[g], n = counts_[g + 1u] - at;
    // Fault 1: the block lands at the next block's offset (the scan read as inclusive).
    const std::uint32_t dst = site_.fault == 1u ? counts_[g + 1u] : at;
    w.Phase([&](wg::Inv& i) {
      for (std::uint32_t k = i.local_id; k < n; k += w.local_size())
        if (dst + k < pc_.count && g * pc_.region + k < pc_.count)  // the bounds hold but for faults
          out_[dst + k] = scratch_[g * pc_.region + k];
    });
  }

  KernelSite site_;
  layout::TraverseCompactPush pc_;
  In<glm::vec4> tri_spheres_;
  In<layout::TriangleInfo> info_;
  std::vector<std::uint32_t> mask_tiles_;  // the object mask from top node t0, packed (PackMaskTiles)
  In<std::uint32_t> pairs_, first_;
  In<layout::ConeNode> nodes_;
  std::vector<std::uint32_t> scratch_, counts_, tested_, out_;
  std::vector<glm::vec4> groups_;        // top: per round and subgroup, Groups' group sphere
  std::vector<std::uint32_t> objects_;  // top: per round and invocation, Groups' object word
};

// The push constants of a part of `count` slots. The rounds' slot arithmetic is 32-bit, as in the
// kernel: the last round must not wrap.
layout::TraverseCompactPush Push(std::uint32_t phase, std::size_t count, float eps, std::uint32_t cone_test) {
  // A round's last pair's p * children_max (children_max <= 255, emu/src/calls.cpp) must not wrap either.
  RS_CHECK_MSG(count <= 0xffffffffu - layout::kMaxLocalSize * 256u, "traverse.compact: {} slots exceed 32-bit slot numbers",
               count);
  layout::TraverseCompactPush pc{};
  pc.phase = phase;
  pc.count = static_cast<std::uint32_t>(count);
  pc.blocks = (pc.count + kCompactBlock - 1) / kCompactBlock;  // the top level's: its rows (TraverseTopCompactedWorkgroups)
  pc.region = kCompactBlock;
  pc.eps = eps;
  pc.cone_test = cone_test;
  return pc;
}

}  // namespace

std::vector<std::uint32_t> PackMaskTiles(std::span<const std::uint8_t> mask, std::size_t rows, std::uint32_t objects) {
  RS_CHECK_MSG(mask.size() >= rows * objects, "traverse.compact: a mask of {} bytes for {} rows x {} objects", mask.size(), rows,
               objects);
  std::vector<std::uint32_t> tiles((rows + kCompactRows - 1) / kCompactRows * objects, 0u);
  for (std::size_t row = 0; row < rows; ++row)
    for (std::uint32_t o = 0; o < objects; ++o)
      if (mask[row * objects + o] != 0u) tiles[row / kCompactRows * objects + o] |= 1u << (row % kCompactRows);
  return tiles;
}

Compacted TraverseTopCompactedWorkgroups(const call::TraverseTop& c) {
  const std::uint32_t T = c.b1 - c.b0, objects = static_cast<std::uint32_t>(c.scene->objects.size());
  layout::TraverseCompactPush pc = Push(layout::kTraverseCompactPhaseTop, std::size_t{c.t1 - c.t0} * T, c.eps, c.cone_test);
  pc.t0 = c.t0;
  pc.b0 = c.b0;
  pc.tris = T;
  pc.blocks = T ? c.t1 - c.t0 : 0;  // a block is a row of T slots (none without triangles, as the host)
  pc.region = T;
  pc.objects = objects;
  pc.use_mask = c.object_mask.empty() ? 0u : 1u;
  pc.id_base = c.t0;
  CompactKernel k(pc, c.tri_spheres);
  k.BindTop(c.top, c.scene->info, pc.use_mask ? c.object_mask.subspan(std::size_t{c.t0} * objects) : In<std::uint8_t>{});
  return k.Run();
}

Compacted TraverseLevelCompactedWorkgroups(const call::TraverseLevel& c) {
  layout::TraverseCompactPush pc = Push(layout::kTraverseCompactPhaseLevel, c.pairs.size() * c.children_max, c.eps, c.cone_test);
  pc.b0 = c.b0;
  pc.base_up = c.base_up;
  pc.base = c.base;
  pc.children_max = c.children_max;
  CompactKernel k(pc, c.tri_spheres);
  k.BindLevel(c.pairs, c.nodes, c.first);
  return k.Run();
}

}  // namespace rayspace::emu
