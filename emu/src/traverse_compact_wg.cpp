// traverse.compact on the workgroup model: mirrors gpu/shaders/traverse_compact.comp dispatch for
// dispatch (Test, Scan, Scatter) and phase for phase, with its push constants, slot walk, packing,
// scratch and count buffers and its planted faults 1..4, so that --check-workgroups, --schedule and
// `--inject traverse.compact:N@emu` reach the kernel's structure and not only its result. The
// cone-sphere test is the pass-by-pass traversal's scalar cone::Test, bit for bit the kernel's
// ConeTest. The host's parts (bindings of limited size) are not mirrored: one part covers the call,
// and parts only concatenate in slot order.
#include <algorithm>
#include <array>

#include "rayspace/contract.h"
#include "rayspace/emu/cone.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/error.h"

namespace rayspace::emu {
namespace {

using layout::kCompactBlock;
using layout::kCompactRun;
// uint kept[kCompactRun]: the survivors of an invocation's slots in the current round.
using Kept = std::array<std::uint32_t, kCompactRun>;

// One part of traverse_compact.comp: the push constants and buffers the host binds, and the three
// dispatches over them.
class CompactKernel {
 public:
  CompactKernel(const layout::TraverseCompactPush& pc, In<glm::vec4> tri_spheres)
      : site_(KernelSite::Of("traverse.compact")), pc_(pc), tri_spheres_(tri_spheres) {
    scratch_.assign(pc.count, 0u);
    counts_.assign(std::size_t{pc.blocks} + 1, 0u);
    tested_.assign(std::size_t{pc.blocks} + 1, 0u);
    out_.assign(pc.count, 0u);
  }
  void BindTop(In<layout::ConeNode> top, In<layout::TriangleInfo> info, In<std::uint8_t> mask_rows) {
    nodes_ = top, info_ = info, mask_ = mask_rows;
  }
  void BindLevel(In<std::uint32_t> pairs, In<layout::ConeNode> nodes, In<std::uint32_t> first) {
    pairs_ = pairs, nodes_ = nodes, first_ = first;
  }

  // The host's submit (phase A, Scan, Scatter) and read-back: the total after the scanned counts,
  // the tests after the block tests.
  Compacted Run() {
    DispatchKernel(site_, "Test", pc_.blocks, [&](wg::Workgroup& w) { TestBlock(w); });
    DispatchKernel(site_, "Scan", 1, [&](wg::Workgroup& w) { ScanBlocks(w); });
    DispatchKernel(site_, "Scatter", pc_.blocks, [&](wg::Workgroup& w) { ScatterBlock(w); });
    const std::uint32_t total = counts_[pc_.blocks];
    RS_CHECK_MSG(total <= pc_.count, "traverse.compact: {} survivors of {} slots", total, pc_.count);
    Compacted r;
    r.pairs.assign(out_.begin(), out_.begin() + total);
    r.tested = tested_[pc_.blocks];
    return r;
  }

 private:
  // traverse.comp's object-mask rule: a slot whose triangle's object the node misses runs no test.
  bool Tested(std::uint32_t row, std::uint32_t tri) const {
    return pc_.use_mask == 0u || mask_[std::size_t{row} * pc_.objects + info_[tri].ids.y] != 0u;
  }

  // TestTopSlots: slots [s0, s1) as (row, col), top node t0 + row against triangle b0 + col; the column
  // steps and a row's node is fetched once, as in the kernel.
  std::uint32_t TestTopSlots(std::uint32_t s0, std::uint32_t s1, std::uint32_t& tests, Kept& kept) const {
    std::uint32_t row = s0 / pc_.tris, col = s0 - row * pc_.tris, n = 0;
    layout::ConeNode node = nodes_[pc_.t0 + row];
    tests = 0;
    for (std::uint32_t s = s0; s < s1; ++s) {
      const std::uint32_t tri = pc_.b0 + col;
      if (Tested(row, tri)) {
        ++tests;
        if (cone::Test(node, tri_spheres_[tri], pc_.eps)) kept[n++] = ((pc_.t0 + row - pc_.id_base) << kPairTriangleBits) | col;
      }
      if (++col == pc_.tris && s + 1u < s1) {
        col = 0;
        ++row;
        node = nodes_[pc_.t0 + row];
      }
    }
    return n;
  }

  // TestLevelSlots: slots [s0, s1) as (pair, child), visiting only the slots that hold a child.
  std::uint32_t TestLevelSlots(std::uint32_t s0, std::uint32_t s1, std::uint32_t& tests, Kept& kept) const {
    std::uint32_t n = 0;
    tests = 0;
    for (std::uint32_t p = s0 / pc_.children_max; p * pc_.children_max < s1; ++p) {
      const std::uint32_t parent = pc_.base_up + (pairs_[p] >> kPairTriangleBits), tri_local = pairs_[p] & kPairTriangleMask;
      const std::uint32_t c0 = first_[parent], c1 = first_[parent + 1u];
      const std::uint32_t row0 = p * pc_.children_max, k1 = std::min(std::min(s1, row0 + pc_.children_max) - row0, c1 - c0);
      const glm::vec4 sphere = tri_spheres_[pc_.b0 + tri_local];
      for (std::uint32_t k = std::max(s0, row0) - row0; k < k1; ++k) {
        ++tests;
        if (cone::Test(nodes_[c0 + k], sphere, pc_.eps)) kept[n++] = ((c0 + k - pc_.base) << kPairTriangleBits) | tri_local;
      }
    }
    return n;
  }

  // Phase A for block w.id(): every invocation runs every round (the scan's barriers are uniform).
  // The kernel's `run` and `tests` are locals of each invocation, equal in all of them.
  void TestBlock(wg::Workgroup& w) {
    auto& tile = WorkgroupTile(w);
    const std::uint32_t g = w.id(), first = g * kCompactBlock, end = std::min(pc_.count, first + kCompactBlock);
    const std::uint32_t round = w.local_size() * kCompactRun;
    wg::Private<Kept> kept = w.Private<Kept>();
    wg::Private<std::uint32_t> n = w.Private<std::uint32_t>(), packed = w.Private<std::uint32_t>();
    wg::Private<std::uint32_t> sums = w.Private<std::uint32_t>(), run = w.Private<std::uint32_t>(), tests = w.Private<std::uint32_t>();
    for (std::uint32_t r0 = first; r0 < end; r0 += round) {
      w.Phase([&](wg::Inv& i) {
        const std::uint32_t s0 = std::min(r0 + i.local_id * kCompactRun, end), s1 = std::min(s0 + kCompactRun, end);
        std::uint32_t t = 0;
        n[i] = 0;
        if (s0 < s1)
          n[i] = pc_.phase == layout::kTraverseCompactPhaseTop ? TestTopSlots(s0, s1, t, kept[i]) : TestLevelSlots(s0, s1, t, kept[i]);
        packed[i] = n[i] | (t << 16);  // survivors and tests in one scan, 16 bits each
      });
      const wg::Private<std::uint32_t> inclusive = WorkgroupInclusiveAdd(w, tile, packed, sums, site_.fault);
      w.Phase([&](wg::Inv& i) {
        const std::uint32_t before = (inclusive[i] & 0xFFFFu) - n[i];
        // Fault 3: every round starts at the block's start (the carry between rounds is dropped).
        const std::uint32_t at = first + (site_.fault == 3u ? 0u : run[i]) + before;
        // A store past the buffer (only a planted fault makes one) is dropped, as robust buffer
        // access drops the kernel's.
        for (std::uint32_t j = 0; j < n[i]; ++j)
          if (at + j < pc_.count) scratch_[at + j] = kept[i][j];
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
    const std::uint32_t total = WorkgroupScanInPlace(w, tile, counts_.data(), pc_.blocks, site_.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id == 0) counts_[pc_.blocks] = total;
    });
    const wg::Private<std::uint32_t> sum = WorkgroupSum(
        w, tile, [&](std::uint32_t k) { return tested_[k]; }, 0u, pc_.blocks, site_.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id == 0) tested_[pc_.blocks] = sum[i];
    });
  }

  // Phase Scatter for block w.id(): its survivors from its scratch region to its offset.
  void ScatterBlock(wg::Workgroup& w) {
    const std::uint32_t g = w.id(), at = counts_[g], n = counts_[g + 1u] - at;
    // Fault 1: the block lands at the next block's offset (the scan read as inclusive).
    const std::uint32_t dst = site_.fault == 1u ? counts_[g + 1u] : at;
    w.Phase([&](wg::Inv& i) {
      for (std::uint32_t k = i.local_id; k < n; k += w.local_size())
        if (dst + k < pc_.count && g * kCompactBlock + k < pc_.count)  // the bounds hold but for faults
          out_[dst + k] = scratch_[g * kCompactBlock + k];
    });
  }

  KernelSite site_;
  layout::TraverseCompactPush pc_;
  In<glm::vec4> tri_spheres_;
  In<layout::TriangleInfo> info_;
  In<std::uint8_t> mask_;  // the object mask's rows from top node t0
  In<std::uint32_t> pairs_, first_;
  In<layout::ConeNode> nodes_;
  std::vector<std::uint32_t> scratch_, counts_, tested_, out_;
};

// The push constants of a part of `count` slots. The rounds' slot arithmetic is 32-bit, as in the
// kernel: the last round must not wrap.
layout::TraverseCompactPush Push(std::uint32_t phase, std::size_t count, float eps) {
  RS_CHECK_MSG(count <= 0xffffffffu - layout::kMaxLocalSize * kCompactRun, "traverse.compact: {} slots exceed 32-bit slot numbers",
               count);
  layout::TraverseCompactPush pc{};
  pc.phase = phase;
  pc.count = static_cast<std::uint32_t>(count);
  pc.blocks = (pc.count + kCompactBlock - 1) / kCompactBlock;
  pc.eps = eps;
  return pc;
}

}  // namespace

Compacted TraverseTopCompactedWorkgroups(const call::TraverseTop& c) {
  const std::uint32_t T = c.b1 - c.b0, objects = static_cast<std::uint32_t>(c.scene->objects.size());
  layout::TraverseCompactPush pc = Push(layout::kTraverseCompactPhaseTop, std::size_t{c.t1 - c.t0} * T, c.eps);
  pc.t0 = c.t0;
  pc.b0 = c.b0;
  pc.tris = T;
  pc.objects = objects;
  pc.use_mask = c.object_mask.empty() ? 0u : 1u;
  pc.id_base = c.t0;
  CompactKernel k(pc, c.tri_spheres);
  k.BindTop(c.top, c.scene->info, pc.use_mask ? c.object_mask.subspan(std::size_t{c.t0} * objects) : In<std::uint8_t>{});
  return k.Run();
}

Compacted TraverseLevelCompactedWorkgroups(const call::TraverseLevel& c) {
  layout::TraverseCompactPush pc = Push(layout::kTraverseCompactPhaseLevel, c.pairs.size() * c.children_max, c.eps);
  pc.b0 = c.b0;
  pc.base_up = c.base_up;
  pc.base = c.base;
  pc.children_max = c.children_max;
  CompactKernel k(pc, c.tri_spheres);
  k.BindLevel(c.pairs, c.nodes, c.first);
  return k.Run();
}

}  // namespace rayspace::emu
