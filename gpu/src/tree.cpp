// Launches of the joint descent's kernels (`--objects tree`): tree_roots, tree_expand, tree_test and
// the fused tree_step (gpu/shaders/tree*.comp, sharing rayspace/contract.h's kTreeBind* bindings),
// each array in one binding (a call whose array outgrows it fails).
#include <algorithm>

#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

namespace {

std::uint32_t Depths(std::span<const std::uint32_t> depth) {
  std::uint32_t d = 0;
  for (const std::uint32_t x : depth) d = std::max(d, x + 1);
  return d;
}

// The bindings of one tree call: the hierarchies, the round's pairs and the outputs.
struct TreeCall {
  Keep keep;
  Bindings<layout::kTreeBindings> b;
  layout::TreePush push{};
  std::vector<std::uint32_t> counters;

  vk::Status Upload(vk::Context& c, const emu::ConeTreeView& cones, const emu::ObjectTreeView& tree, std::span<const std::uint32_t> pair_cone,
                    std::span<const std::uint32_t> pair_item, std::span<const std::uint32_t> offsets) {
    const vk::Buffer* x = nullptr;
    RS_TRY(keep.From(c, cones.cone_nodes, x)); b.Set(layout::kTreeBindConeNodes, x);
    RS_TRY(keep.From(c, cones.cone_base, x)); b.Set(layout::kTreeBindConeBase, x);
    RS_TRY(keep.From(c, cones.cone_first, x)); b.Set(layout::kTreeBindConeFirst, x);
    RS_TRY(keep.From(c, tree.tree_spheres, x)); b.Set(layout::kTreeBindSpheres, x);
    RS_TRY(keep.From(c, tree.tree_links, x)); b.Set(layout::kTreeBindLinks, x);
    RS_TRY(keep.From(c, tree.tree_depth, x)); b.Set(layout::kTreeBindDepth, x);
    RS_TRY(keep.From(c, tree.tree_roots, x)); b.Set(layout::kTreeBindRoots, x);
    RS_TRY(keep.From(c, tree.tree_tri_spheres, x)); b.Set(layout::kTreeBindTriSpheres, x);
    RS_TRY(keep.From(c, pair_cone, x)); b.Set(layout::kTreeBindPairCone, x);
    RS_TRY(keep.From(c, pair_item, x)); b.Set(layout::kTreeBindPairItem, x);
    RS_TRY(keep.From(c, offsets, x)); b.Set(layout::kTreeBindOffsets, x);
    offsets_ = x;
    push.levels = static_cast<std::uint32_t>(cones.Depth() + 1);
    push.depths = Depths(tree.tree_depth);
    counters.assign(2 * push.levels + 2 * push.depths + 2, 0);
    RS_TRY(keep.From(c, std::span<const std::uint32_t>(counters), x)); b.Set(layout::kTreeBindCounters, x);
    counters_ = x;
    return vk::Status::Ok();
  }
  // A zeroed output of `words` at `binding`, copied back to dst (null: not copied).
  vk::Status Output(vk::Context& c, std::uint32_t binding, std::size_t words, std::uint32_t* dst) {
    const vk::Buffer* x = nullptr;
    RS_TRY(keep.Output(c, words * 4, x, dst));
    RS_TRY(const_cast<vk::Buffer*>(x)->Zero());
    b.Set(binding, x);
    return vk::Status::Ok();
  }
  // The per-slot outputs of tree.roots and tree.test: flags, and each slot's pair.
  vk::Status SlotOutputs(vk::Context& c, std::size_t slots, std::vector<std::uint32_t>& flags, emu::TreeSlots& out) {
    flags.assign(slots, 0);
    out.pairs.cone.assign(slots, 0);
    out.pairs.item.assign(slots, 0);
    RS_TRY(Output(c, layout::kTreeBindFlags, slots, flags.data()));
    RS_TRY(Output(c, layout::kTreeBindOutCone, slots, out.pairs.cone.data()));
    return Output(c, layout::kTreeBindOutItem, slots, out.pairs.item.data());
  }
  vk::Status Counts(emu::TreeCounts& out) {
    RS_TRY(counters_->Read(counters.data(), counters.size() * 4));
    const std::uint32_t L = push.levels, D = push.depths;
    out.Resize(static_cast<int>(L), D);
    for (std::uint32_t l = 0; l < L; ++l) out.cone_tests[l] = counters[l], out.cone_hits[l] = counters[L + l];
    for (std::uint32_t d = 0; d < D; ++d) out.node_tests[d] = counters[2 * L + d], out.node_hits[d] = counters[2 * L + D + d];
    out.tri_tests = counters[2 * L + 2 * D], out.tri_hits = counters[2 * L + 2 * D + 1];
    return vk::Status::Ok();
  }

 private:
  const vk::Buffer* counters_ = nullptr;

 public:
  const vk::Buffer* offsets_ = nullptr;
};

// The kernel's 32-bit slot flags as the call's bytes.
vk::Status ToSlots(const std::vector<std::uint32_t>& flags, emu::TreeSlots& out) {
  out.flags.resize(flags.size());
  for (std::size_t i = 0; i < flags.size(); ++i) {
    if (flags[i] > 2) return vk::Status::Fail(fmt::format("tree: slot {} has flag {}", i, flags[i]));
    out.flags[i] = static_cast<std::uint8_t>(flags[i]);
  }
  return vk::Status::Ok();
}

}  // namespace

vk::Status VulkanPasses::Run(const emu::call::TreeRoots& call, emu::TreeSlots& out) {
  const std::size_t roots = call.tree.tree_roots.size(), slots = std::size_t{call.t1 - call.t0} * roots;
  TreeCall t;
  RS_TRY(t.Upload(*ctx_, call.cones, call.tree, {}, {}, {}));
  std::vector<std::uint32_t> flags;
  RS_TRY(t.SlotOutputs(*ctx_, slots, flags, out));
  t.push.count = static_cast<std::uint32_t>(slots);
  t.push.level = call.level, t.push.t0 = call.t0, t.push.roots = static_cast<std::uint32_t>(roots), t.push.eps = call.eps;
  if (slots) RS_TRY(RunKernel(*ctx_, K(PassId::kTreeRoots), t.b.All(), &t.push, sizeof t.push, t.push.count));
  RS_TRY(t.keep.CopyBack());
  RS_TRY(t.Counts(out.counts));
  return ToSlots(flags, out);
}

vk::Status VulkanPasses::Run(const emu::call::TreeExpand& call, std::vector<std::uint32_t>& out) {
  const std::size_t n = call.pair_cone.size();
  TreeCall t;
  RS_TRY(t.Upload(*ctx_, call.cones, call.tree, call.pair_cone, call.pair_item, {}));
  out.assign(n, 0);
  RS_TRY(t.Output(*ctx_, layout::kTreeBindFlags, n, out.data()));
  RS_TRY(t.Output(*ctx_, layout::kTreeBindOutCone, 0, nullptr));
  RS_TRY(t.Output(*ctx_, layout::kTreeBindOutItem, 0, nullptr));
  t.push.count = static_cast<std::uint32_t>(n);
  if (n) RS_TRY(RunKernel(*ctx_, K(PassId::kTreeExpand), t.b.All(), &t.push, sizeof t.push, t.push.count));
  return t.keep.CopyBack();
}

vk::Status VulkanPasses::Run(const emu::call::TreeTest& call, emu::TreeSlots& out) {
  const std::size_t n = call.pair_cone.size(), slots = call.slots;
  TreeCall t;
  RS_TRY(t.Upload(*ctx_, call.cones, call.tree, call.pair_cone, call.pair_item, call.offsets));
  std::vector<std::uint32_t> flags;
  RS_TRY(t.SlotOutputs(*ctx_, slots, flags, out));
  t.push.count = static_cast<std::uint32_t>(n), t.push.slots = call.slots, t.push.eps = call.eps;
  if (n) RS_TRY(RunKernel(*ctx_, K(PassId::kTreeTest), t.b.All(), &t.push, sizeof t.push, t.push.count));
  RS_TRY(t.keep.CopyBack());
  RS_TRY(t.Counts(out.counts));
  return ToSlots(flags, out);
}

// Two submits: the block counts and their scan, then (outputs sized by the totals) the scatter.
vk::Status VulkanPasses::Run(const emu::call::TreeStep& call, emu::TreeRound& out) {
  out = {};
  const std::size_t n = call.pair_cone.size();
  const std::uint32_t blocks = static_cast<std::uint32_t>((n + layout::kTreeStepBlock - 1) / layout::kTreeStepBlock);
  TreeCall t;
  std::vector<std::uint32_t> offsets(2 * std::size_t{blocks} + 2, 0);
  RS_TRY(t.Upload(*ctx_, call.cones, call.tree, call.pair_cone, call.pair_item, offsets));
  t.push.count = static_cast<std::uint32_t>(n), t.push.eps = call.eps, t.push.blocks = blocks;
  const vk::Kernel& k = K(PassId::kTreeStep);
  std::vector<std::uint32_t> outputs;
  // The first submit binds placeholders where the scatter's outputs go.
  RS_TRY(t.Output(*ctx_, layout::kTreeBindFlags, 0, nullptr));
  RS_TRY(t.Output(*ctx_, layout::kTreeBindOutCone, 0, nullptr));
  RS_TRY(t.Output(*ctx_, layout::kTreeBindOutItem, 0, nullptr));
  if (blocks) {
    vk::Recorder rec(*ctx_);
    for (const std::uint32_t phase : {layout::kTreeStepPhaseCount, layout::kTreeStepPhaseScan}) {
      layout::TreePush p = t.push;
      p.phase = phase;
      RS_TRY(rec.DispatchGroups(k, t.b.All(), &p, sizeof p, phase == layout::kTreeStepPhaseScan ? 1u : blocks));
    }
    RS_TRY(rec.Submit());
  }
  if (!blocks) return t.Counts(out.counts);
  RS_TRY(t.offsets_->Read(offsets.data(), offsets.size() * 4));
  const std::uint32_t next = offsets[blocks], final = offsets[2 * std::size_t{blocks} + 1];
  outputs.assign(std::size_t{next} + final, 0);
  std::vector<std::uint32_t> items(outputs.size(), 0);
  RS_TRY(t.Output(*ctx_, layout::kTreeBindOutCone, outputs.size(), outputs.data()));
  RS_TRY(t.Output(*ctx_, layout::kTreeBindOutItem, items.size(), items.data()));
  layout::TreePush p = t.push;
  p.phase = layout::kTreeStepPhaseScatter;
  p.slots = next;
  vk::Recorder rec(*ctx_);
  RS_TRY(rec.DispatchGroups(k, t.b.All(), &p, sizeof p, blocks));
  RS_TRY(rec.Submit());
  RS_TRY(t.keep.CopyBack());
  RS_TRY(t.Counts(out.counts));
  out.next.cone.assign(outputs.begin(), outputs.begin() + next);
  out.next.item.assign(items.begin(), items.begin() + next);
  out.final.cone.assign(outputs.begin() + next, outputs.end());
  out.final.item.assign(items.begin() + next, items.end());
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
