// Launch of the build kernel (gpu/shaders/build.comp): cone-sphere nodes level by level.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

// One build.comp launch over the level's nodes, in parts of the node array (each dispatch gets its
// slice of `first`, one longer, and of the output); rays, order and the level below are paged.
vk::Status VulkanPasses::Build(std::uint32_t phase, std::span<const layout::Ray> rays, std::span<const std::uint32_t> order,
                               std::span<const layout::ConeNode> below, std::span<const std::uint32_t> first,
                               std::vector<layout::ConeNode>& nodes, std::uint32_t child_merge) {
  vk::Context& c = *ctx_;
  if (first.empty()) return vk::Status::Fail("build: empty node offsets");
  const std::size_t count = first.size() - 1;
  nodes.assign(count, layout::ConeNode{});
  Paged pr, po, pb;
  RS_TRY(MakePaged(c, rays, "build: rays", pr, paged_arrays_));
  RS_TRY(MakePaged(c, order, "build: sorted order", po, paged_arrays_));
  RS_TRY(MakePaged(c, below, "build: nodes of the level below", pb, paged_arrays_));
  Keep keep;
  vk::Recorder rec(c);
  RS_TRY(ForParts(count, PerPart(sizeof(layout::ConeNode)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *bf = nullptr, *bn = nullptr;
    RS_TRY(keep.From(c, Slice(first, i0, i1 + 1), bf));
    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(layout::ConeNode), bn, nodes.data() + i0));
    const layout::BuildPush push{static_cast<std::uint32_t>(i1 - i0), phase, pr.page, po.page, pb.page, child_merge};
    Bindings<layout::kBuildBindings> b;
    b.Set(layout::kBuildBindFirst, bf).Set(layout::kBuildBindNodes, bn);
    b.Set(layout::kBuildBindRays, pr).Set(layout::kBuildBindOrder, po).Set(layout::kBuildBindBelow, pb);
    // one subgroup per node (build.comp's SubgroupSlots() per workgroup)
    const vk::Kernel& k = K(PassId::kBuild);
    const std::uint64_t per_group = (k.local_size() + c.subgroup_size() - 1) / c.subgroup_size();
    return rec.DispatchGroups(k, b.All(), &push, sizeof push, (push.count + per_group - 1) / per_group);
  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Run(const emu::call::BuildLeaves& call, std::vector<layout::ConeNode>& nodes) {
  return Build(layout::kBuildPhaseLeaves, call.rays, call.order, {}, call.first, nodes);
}

vk::Status VulkanPasses::Run(const emu::call::BuildParents& call, std::vector<layout::ConeNode>& nodes) {
  return Build(layout::kBuildPhaseParents, {}, {}, call.below, call.first, nodes, call.child_merge);
}


}  // namespace rayspace::gpu_backend
