// Launches of the traverse kernel (gpu/shaders/traverse.comp): CRSH's object mask, the top level of a
// block and one level down. The kernel writes 32-bit flags; the calls' results hold bytes. Also the
// fused traverse.compact kernel (gpu/shaders/traverse_compact.comp), which reads the same inputs.
#include <algorithm>
#include <vector>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

namespace {

// The traverse.comp (or traverse_compact.comp) inputs one pass call reads whole, uploaded once and
// bound by every part of the call: the level's nodes and child offsets (paged, read by node id),
// spheres and triangle info (empty spans bind a zeroed placeholder).
class Traverser {
 public:
  Traverser(vk::Context& c, const vk::Kernel& k) : c_(c), k_(k) {}
  vk::Status Upload(std::span<const layout::ConeNode> nodes, std::span<const std::uint32_t> first, std::span<const glm::vec4> spheres,
                    std::span<const layout::TriangleInfo> info, std::size_t& multi) {
    RS_TRY(MakePaged(c_, nodes, "traverse: nodes", nodes_, multi));
    RS_TRY(MakePaged(c_, first, "traverse: child offsets", first_, multi));
    RS_TRY(MakeFrom(c_, spheres, spheres_));
    RS_TRY(MakeFrom(c_, info, info_));
    return vk::Status::Ok();
  }
  // One part, in a submit of its own (its output buffers are freed before the next part): `mask`
  // and `pairs` are this part's. The kernel's 32-bit flags (`slots` words) and tested counts (`tested`
  // words) are narrowed to bytes at the given pointers as they are read back (`what` and `at`, the
  // part's first element in the call, name an element that is neither); values go to `values_out` (null: not read back).
  // `invocations`: push.count unless the phase says otherwise.
  vk::Status Part(layout::TraversePush push, std::span<const std::uint32_t> mask, std::span<const std::uint32_t> pairs, std::size_t slots,
                  std::size_t tested, const char* what, std::size_t at, std::uint8_t* flags_out, std::uint32_t* values_out, std::uint8_t* tested_out,
                  std::uint32_t invocations) const {
    Keep keep;
    const vk::Buffer *bm = nullptr, *bp = nullptr, *bfl = nullptr, *bv = nullptr, *bt = nullptr;
    RS_TRY(keep.From(c_, mask, bm));
    RS_TRY(keep.From(c_, pairs, bp));
    RS_TRY(keep.Output(c_, slots * 4, bfl));
    RS_TRY(keep.Output(c_, slots * 4, bv, values_out));
    RS_TRY(keep.Output(c_, tested * 4, bt));
    push.node_page = nodes_.page;
    push.first_page = first_.page;
    Bindings<layout::kTraverseBindings> b;
    b.Set(layout::kTraverseBindTriSpheres, &spheres_).Set(layout::kTraverseBindInfo, &info_).Set(layout::kTraverseBindMask, bm);
    b.Set(layout::kTraverseBindPairs, bp).Set(layout::kTraverseBindFlags, bfl).Set(layout::kTraverseBindValues, bv);
    b.Set(layout::kTraverseBindTested, bt).Set(layout::kTraverseBindNodes, nodes_).Set(layout::kTraverseBindFirst, first_);
    RS_TRY(RunKernel(c_, k_, b.All(), &push, sizeof push, invocations));
    RS_TRY(keep.CopyBack());
    if (flags_out) RS_TRY(NarrowBack(*bfl, slots, what, at, flags_out));
    if (tested_out) RS_TRY(NarrowBack(*bt, tested, what, at, tested_out));
    return vk::Status::Ok();
  }
  // One part of traverse.compact (`push.count` slots; `mask` and `pairs` are this part's): phases A, B
  // and C in one submit; the part's survivors are appended to out.pairs and its tests added.
  vk::Status CompactPart(layout::TraverseCompactPush push, std::span<const std::uint32_t> mask, std::span<const std::uint32_t> pairs,
                         emu::Compacted& out) const {
    Keep keep;
    const bool top = push.phase == layout::kTraverseCompactPhaseTop;
    push.blocks = top ? (push.tris ? push.count / push.tris : 0)
                      : static_cast<std::uint32_t>((std::uint64_t{push.count} + layout::kCompactBlock - 1) / layout::kCompactBlock);
    push.region = top ? push.tris : layout::kCompactBlock;
    // The top phase's uvec4 tile holds one entry per subgroup.
    if (k_.local_size() > c_.subgroup_size() * (layout::kMaxLocalSize / 4))
      return vk::Status::Fail(fmt::format("traverse.compact: local size {} has more than {} subgroups of {}", k_.local_size(),
                                          layout::kMaxLocalSize / 4, c_.subgroup_size()));
    push.node_page = nodes_.page;
    push.first_page = first_.page;
    const vk::Buffer *bm = nullptr, *bp = nullptr, *bs = nullptr, *bc = nullptr, *bt = nullptr, *bo = nullptr;
    RS_TRY(keep.From(c_, mask, bm));
    RS_TRY(keep.From(c_, pairs, bp));
    RS_TRY(keep.Output(c_, std::size_t{push.count} * 4, bs));  // slot-indexed: a block's survivors fit its slots
    RS_TRY(keep.Output(c_, (std::size_t{push.blocks} + 1) * 4, bc));
    RS_TRY(keep.Output(c_, (std::size_t{push.blocks} + 1) * 4, bt));
    RS_TRY(keep.Output(c_, std::size_t{push.count} * 4, bo));
    // Top: per round, a group sphere per subgroup (at most one subgroup per invocation) and an object
    // word per invocation, kCompactGroupWords words an invocation.
    constexpr std::uint32_t kRound = layout::kCompactCols;  // triangles per invocation and round
    const std::uint32_t rounds = top ? static_cast<std::uint32_t>((std::uint64_t{push.tris} + k_.local_size() * kRound - 1) /
                                                                  (std::uint64_t{k_.local_size()} * kRound))
                                     : 0u;
    const vk::Buffer* bg = nullptr;
    RS_TRY(keep.Output(c_, std::max<std::size_t>(1, std::size_t{rounds} * k_.local_size()) * layout::kCompactGroupWords * 4, bg));
    Bindings<layout::kTraverseCompactBindings> b;
    b.Set(layout::kTraverseCompactBindTriSpheres, &spheres_).Set(layout::kTraverseCompactBindInfo, &info_);
    b.Set(layout::kTraverseCompactBindMask, bm).Set(layout::kTraverseCompactBindPairs, bp).Set(layout::kTraverseCompactBindScratch, bs);
    b.Set(layout::kTraverseCompactBindCounts, bc).Set(layout::kTraverseCompactBindTested, bt).Set(layout::kTraverseCompactBindOut, bo);
    b.Set(layout::kTraverseCompactBindNodes, nodes_).Set(layout::kTraverseCompactBindFirst, first_);
    b.Set(layout::kTraverseCompactBindGroups, bg);
    vk::Recorder rec(c_);
    std::vector<std::uint32_t> phases{push.phase, layout::kTraverseCompactPhaseScan, layout::kTraverseCompactPhaseScatter};
    if (top) phases.insert(phases.begin(), layout::kTraverseCompactPhaseGroups);
    for (const std::uint32_t phase : phases) {
      layout::TraverseCompactPush p = push;
      p.phase = phase;
      // A workgroup per round (Groups) or per tile of rows (Top); Level and Scatter at most
      // kCompactStrideGroups, which stride over the blocks (lavapipe pays for every workgroup it
      // starts); the scan of the block counts is one workgroup.
      const std::uint32_t groups = phase == layout::kTraverseCompactPhaseScan     ? 1
                                   : phase == layout::kTraverseCompactPhaseGroups ? rounds
                                   : phase == layout::kTraverseCompactPhaseTop ? (push.blocks + layout::kCompactRows - 1) / layout::kCompactRows
                                                                                : std::min(push.blocks, layout::kCompactStrideGroups);
      RS_TRY(rec.DispatchGroups(k_, b.All(), &p, sizeof p, groups));
    }
    RS_TRY(rec.Submit());
    return AppendSurvivors(*bc, *bt, *bo, push, out);
  }

 private:
  // The part's survivors (the scanned counts' total) and tests (the last words of phase B).
  static vk::Status AppendSurvivors(const vk::Buffer& counts, const vk::Buffer& tested, const vk::Buffer& survivors,
                                    const layout::TraverseCompactPush& push, emu::Compacted& out) {
    std::vector<std::uint32_t> c, t;
    RS_TRY(counts.Download(push.blocks + std::size_t{1}, c));
    RS_TRY(tested.Download(push.blocks + std::size_t{1}, t));
    const std::uint32_t total = c[push.blocks];
    if (total > push.count || t[push.blocks] > push.count)
      return vk::Status::Fail(fmt::format("traverse.compact kernel reported {} survivors and {} tests of {} slots", total,
                                          t[push.blocks], push.count));
    const std::size_t at = out.pairs.size();
    out.pairs.resize(at + total);
    if (total) RS_TRY(survivors.Read(out.pairs.data() + at, std::size_t{total} * 4));
    out.tested += t[push.blocks];
    return vk::Status::Ok();
  }

  // The kernel's 32-bit flags or counts (0/1, or a child count of at most 255) as the call's bytes,
  // through a part-sized scratch that the parts reuse (no call-sized 32-bit copy).
  vk::Status NarrowBack(const vk::Buffer& b, std::size_t n, const char* what, std::size_t at, std::uint8_t* out) const {
    scratch_.resize(n);
    RS_TRY(b.Read(scratch_.data(), n * 4));
    for (std::size_t i = 0; i < n; ++i) {
      if (scratch_[i] > 0xFFu)
        return vk::Status::Fail(fmt::format("{}: element {} is {}, not a flag or count", what, at + i, scratch_[i]));
      out[i] = static_cast<std::uint8_t>(scratch_[i]);
    }
    return vk::Status::Ok();
  }

  vk::Context& c_;
  const vk::Kernel& k_;
  mutable std::vector<std::uint32_t> scratch_;
  Paged nodes_, first_;
  vk::Buffer spheres_, info_;
};

}  // namespace

vk::Status VulkanPasses::Run(const emu::call::TraverseTop& call, emu::PairSlots& out) {
  const std::uint32_t t0 = call.t0, t1 = call.t1, b0 = call.b0, b1 = call.b1;
  const SceneBuffers& scene = *call.scene;
  const std::vector<std::uint32_t> object_mask(call.object_mask.begin(), call.object_mask.end());  // 32-bit words
  const std::size_t T = b1 - b0, count = static_cast<std::size_t>(t1 - t0) * T;
  out.flags.resize(count);
  out.values.resize(count);
  out.tested.resize(count);
  Traverser tr(*ctx_, K(PassId::kTraverse));
  RS_TRY(tr.Upload(call.top, {}, call.tri_spheres, scene.info, paged_arrays_));
  // Parts are rows of top nodes, so that the flags/values/tested bindings and the object mask's rows
  // for those nodes stay within one binding.
  const std::size_t objects = scene.objects.size(), row_words = std::max<std::size_t>({T, object_mask.empty() ? 1 : objects, 1});
  RS_TRY(ForParts(t1 - t0, StreamPerPart(4 * row_words), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t r0 = t0 + static_cast<std::uint32_t>(i0), r1 = t0 + static_cast<std::uint32_t>(i1);
    const std::size_t at = i0 * T, n = (i1 - i0) * T;
    const layout::TraversePush push{layout::kTraversePhaseTop, static_cast<std::uint32_t>(n), r0, b0, static_cast<std::uint32_t>(T),
                                 static_cast<std::uint32_t>(objects), object_mask.empty() ? 0u : 1u, 0, 0, 0, call.eps, t0, 0, 0, call.cone_test};
    const std::span<const std::uint32_t> mask_rows =
        object_mask.empty() ? std::span<const std::uint32_t>() : std::span(object_mask).subspan(r0 * objects, (r1 - r0) * objects);
    // A run of kTraverseTopRun slots of one row per invocation (rayspace/contract.h).
    const std::size_t runs = (i1 - i0) * ((T + layout::kTraverseTopRun - 1) / layout::kTraverseTopRun);
    return tr.Part(push, mask_rows, {}, n, n, "traverse.top", at, out.flags.data() + at, out.values.data() + at, out.tested.data() + at,
                   static_cast<std::uint32_t>(runs));
  }));
  return vk::Status::Ok();
}

// Parts are ranges of pairs, so that the slot bindings (pairs x children) stay within one binding.
vk::Status VulkanPasses::Run(const emu::call::TraverseLevel& call, emu::PairSlots& out) {
  const std::uint32_t children_max = call.children_max;
  const std::size_t count = call.pairs.size();
  out.flags.resize(count * children_max);
  out.values.resize(count * children_max);
  out.tested.resize(count);
  Traverser tr(*ctx_, K(PassId::kTraverse));
  RS_TRY(tr.Upload(call.nodes, call.first, call.tri_spheres, {}, paged_arrays_));
  RS_TRY(ForParts(count, StreamPerPart(4 * std::size_t{children_max}), extra_dispatches_, [&](std::size_t p0, std::size_t p1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>(p1 - p0);
    const layout::TraversePush push{layout::kTraversePhaseLevel, n, 0, call.b0, 0, 0, 0, call.base_up, call.base, children_max,
                                 call.eps, 0, 0, 0, call.cone_test};
    return tr.Part(push, {}, Slice(call.pairs, p0, p1), std::size_t{n} * children_max, n, "traverse.level", p0 * children_max,
                   out.flags.data() + p0 * children_max, out.values.data() + p0 * children_max, out.tested.data() + p0, n);
  }));
  return vk::Status::Ok();
}

// Parts of the mask (top nodes x objects), each within one binding; t0 carries the part's first
// element.
vk::Status VulkanPasses::Run(const emu::call::ObjectMask& call, std::vector<std::uint8_t>& out) {
  const std::uint32_t objects = static_cast<std::uint32_t>(call.object_spheres.size());
  const std::size_t count = call.top.size() * objects;
  if (count > 0xFFFFFFFFu)
    return vk::Status::Fail(fmt::format("object mask: {} top nodes x {} objects exceed 2^32", call.top.size(), objects));
  out.resize(count);
  Traverser tr(*ctx_, K(PassId::kTraverse));
  RS_TRY(tr.Upload(call.top, {}, call.object_spheres, {}, paged_arrays_));
  RS_TRY(ForParts(count, PerPart(4), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>(i1 - i0);
    const layout::TraversePush push{layout::kTraversePhaseObjects, n, static_cast<std::uint32_t>(i0), 0, 0, objects, 0, 0, 0, 0, call.eps,
                                 0, 0, 0, call.cone_test};
    return tr.Part(push, {}, {}, n, 0, "traverse.objects", i0, out.data() + i0, nullptr, nullptr, n);
  }));
  return vk::Status::Ok();
}

// traverse.compact at the top level: parts are rows of top nodes, as for traverse.top, so that the
// scratch and survivor bindings (one word per slot) and the mask rows stay within one binding; the
// parts' survivors concatenate in slot order.
vk::Status VulkanPasses::Run(const emu::call::TraverseTopCompacted& call, emu::Compacted& out) {
  out = {};
  const std::uint32_t t0 = call.t0, b0 = call.b0, T = call.b1 - call.b0;
  const std::span<const std::uint8_t> object_mask = call.object_mask;
  const std::uint32_t objects = static_cast<std::uint32_t>(call.scene->objects.size());
  Traverser tr(*ctx_, K(PassId::kTraverseCompact));
  RS_TRY(tr.Upload(call.top, {}, call.tri_spheres, call.scene->info, paged_arrays_));
  // A row also holds a survivor count and a test count (one word each, in bindings of their own): at
  // least two words a row keeps those within one binding too.
  const std::size_t row_words = std::max<std::size_t>({T, object_mask.empty() ? 1 : objects, 2});
  return ForParts(call.t1 - t0, StreamPerPart(4 * row_words), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t r0 = t0 + static_cast<std::uint32_t>(i0), n = static_cast<std::uint32_t>((i1 - i0) * T);
    const layout::TraverseCompactPush push{layout::kTraverseCompactPhaseTop, n, 0, 0, r0, b0, T, objects, object_mask.empty() ? 0u : 1u,
                                        0, 0, 0, call.eps, t0, 0, 0, call.cone_test};
    // The part's rows packed a word per tile of kCompactRows rows and object (the kernel's RowBits).
    const std::vector<std::uint32_t> mask_tiles =
        object_mask.empty() ? std::vector<std::uint32_t>() : emu::PackMaskTiles(object_mask.subspan(std::size_t{r0} * objects), i1 - i0, objects);
    return tr.CompactPart(push, mask_tiles, {}, out);
  });
}

// traverse.compact one level down: parts are ranges of pairs, as for traverse.level.
vk::Status VulkanPasses::Run(const emu::call::TraverseLevelCompacted& call, emu::Compacted& out) {
  out = {};
  const std::uint32_t children_max = call.children_max;
  Traverser tr(*ctx_, K(PassId::kTraverseCompact));
  RS_TRY(tr.Upload(call.nodes, call.first, call.tri_spheres, {}, paged_arrays_));
  const std::size_t per = StreamPerPart(4 * std::size_t{std::max(children_max, 1u)});
  return ForParts(call.pairs.size(), per, extra_dispatches_, [&](std::size_t p0, std::size_t p1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>((p1 - p0) * children_max);
    const layout::TraverseCompactPush push{layout::kTraverseCompactPhaseLevel, n, 0, 0, 0, call.b0, 0, 0, 0, call.base_up, call.base,
                                        children_max, call.eps, 0, 0, 0, call.cone_test};
    return tr.CompactPart(push, {}, Slice(call.pairs, p0, p1), out);
  });
}

}  // namespace rayspace::gpu_backend
