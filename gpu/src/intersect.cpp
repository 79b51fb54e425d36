// Launch of the intersect kernel (gpu/shaders/intersect.comp): final ray-triangle tests of the
// surviving pairs, merged into the caller's closest hits or occlusion flags.
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

#include <algorithm>

namespace rayspace::gpu_backend {

// intersect.comp strides over its pairs from a grid of at most this many workgroups. lavapipe pays
// for every workgroup it starts: Sponza 512x512's final tests took 1,895-2,025 ms with a workgroup
// per 64 pairs and 1,274-1,368 ms with 256 (docs/performance.md, "Workgroups that stride").
constexpr std::uint32_t kIntersectGroups = 256;
using namespace detail;

vk::Status VulkanPasses::Run(const emu::call::Intersect& call, std::vector<std::uint32_t>& tests) {
  const std::span<const std::uint32_t> pairs = call.pairs, first1 = call.first1, order = call.order;
  const std::span<const layout::Ray> rays = call.rays;
  const SceneBuffers& scene = *call.scene;
  const std::uint32_t base1 = call.base1, b0 = call.b0;
  const bool shadow = call.occluded != nullptr;
  if (shadow == (call.hits != nullptr)) return vk::Status::Fail("intersect: exactly one of hits and occlusion is needed");
  std::vector<std::uint64_t> hits;
  std::vector<std::uint32_t> occluded;
  vk::Context& c = *ctx_;
  // Pairs go in parts (their tests with them); everything indexed by leaf, sorted position or ray is
  // paged, and the hit or occlusion pages stay bound across the parts, which all go in one submit.
  // A batch writes only hits (closest hit) or only occlusion (shadow): the other stays as initialised
  // and is bound as a placeholder.
  hits.assign(shadow ? 0 : rays.size(), ~std::uint64_t{0});
  occluded.assign(shadow ? rays.size() : 0, 0);
  tests.assign(pairs.size(), 0);
  Paged pf, po, pr, ph, pocc;
  RS_TRY(MakePaged(c, std::span<const std::uint32_t>(first1), "intersect: leaf offsets", pf, paged_arrays_));
  RS_TRY(MakePaged(c, std::span<const std::uint32_t>(order), "intersect: sorted order", po, paged_arrays_));
  RS_TRY(MakePaged(c, std::span<const layout::Ray>(rays), "intersect: rays", pr, paged_arrays_));
  RS_TRY(MakePaged(c, shadow ? std::span<const std::uint64_t>() : std::span<const std::uint64_t>(hits), "intersect: closest hits",
                   ph, paged_arrays_));
  RS_TRY(MakePaged(c, shadow ? std::span<const std::uint32_t>(occluded) : std::span<const std::uint32_t>(),
                   "intersect: occlusion flags", pocc, paged_arrays_));
  Keep keep;
  const vk::Buffer *bt = nullptr, *bs = nullptr;
  RS_TRY(keep.From(c, std::span<const layout::Triangle>(scene.triangles), bt));
  // The node test reads no sphere: a placeholder word stands in.
  static const glm::vec4 kNoSphere(0.0f);
  const std::span<const glm::vec4> spheres =
      call.leaf_test == layout::kLeafTestRaySphere ? std::span<const glm::vec4>(call.tri_spheres) : std::span<const glm::vec4>(&kNoSphere, 1);
  RS_TRY(keep.From(c, spheres, bs));
  vk::Recorder rec(c);
  RS_TRY(ForParts(pairs.size(), PerPart(4), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *bp = nullptr, *btests = nullptr;
    RS_TRY(keep.From(c, Slice(pairs, i0, i1), bp));
    RS_TRY(keep.Output(c, (i1 - i0) * 4, btests, tests.data() + i0));
    const layout::IntersectPush push{static_cast<std::uint32_t>(i1 - i0), base1, b0, shadow ? 1u : 0u, pf.page, po.page,
                                  pr.page, ph.page, pocc.page, call.leaf_test, call.eps};
    Bindings<layout::kIntersectBindings> b;
    b.Set(layout::kIntersectBindPairs, bp).Set(layout::kIntersectBindTriangles, bt).Set(layout::kIntersectBindTests, btests);
    b.Set(layout::kIntersectBindFirst, pf).Set(layout::kIntersectBindOrder, po).Set(layout::kIntersectBindRays, pr);
    b.Set(layout::kIntersectBindHits, ph).Set(layout::kIntersectBindOccluded, pocc).Set(layout::kIntersectBindTriSpheres, bs);
    // The kernel strides over the pairs: a grid of at most kIntersectGroups workgroups.
    const std::size_t invocations = std::min<std::size_t>(push.count, std::size_t{kIntersectGroups} * K(PassId::kIntersect).local_size());
    return rec.Dispatch(K(PassId::kIntersect), b.All(), &push, sizeof push, invocations);
  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  // The kernel starts from empty results; merge into the caller's (min for hits, or for occlusion).
  if (shadow) {
    RS_TRY(pocc.Read(std::span<std::uint32_t>(occluded)));
    for (std::size_t i = 0; i < occluded.size(); ++i) (*call.occluded)[i] |= occluded[i];
  } else {
    RS_TRY(ph.Read(std::span<std::uint64_t>(hits)));
    for (std::size_t i = 0; i < hits.size(); ++i) (*call.hits)[i] = std::min((*call.hits)[i], hits[i]);
  }
  return vk::Status::Ok();
}


// intersect.tree (gpu/shaders/intersect_tree.comp): the final tests of `--objects tree`'s final
// pairs, each array in one binding (a call whose array outgrows it fails).
vk::Status VulkanPasses::Run(const emu::call::IntersectTree& call, std::vector<std::uint32_t>& tests) {
  const bool shadow = call.occluded != nullptr;
  if (shadow == (call.hits != nullptr)) return vk::Status::Fail("intersect.tree: exactly one of hits and occlusion is needed");
  vk::Context& c = *ctx_;
  const std::size_t n = call.pair_cone.size(), rays = call.rays.size();
  std::vector<std::uint64_t> hits(shadow ? 0 : rays, ~std::uint64_t{0});
  std::vector<std::uint32_t> occluded(shadow ? rays : 0, 0);
  tests.assign(n, 0);
  Keep keep;
  Bindings<layout::kIntersectTreeBindings> b;
  const vk::Buffer *x = nullptr, *bh = nullptr, *bocc = nullptr;
  RS_TRY(keep.From(c, call.pair_cone, x)); b.Set(layout::kIntersectTreeBindPairCone, x);
  RS_TRY(keep.From(c, call.pair_item, x)); b.Set(layout::kIntersectTreeBindPairItem, x);
  RS_TRY(keep.From(c, call.first1, x)); b.Set(layout::kIntersectTreeBindFirst, x);
  RS_TRY(keep.From(c, call.tree_triangles, x)); b.Set(layout::kIntersectTreeBindTreeTriangles, x);
  RS_TRY(keep.From(c, call.order, x)); b.Set(layout::kIntersectTreeBindOrder, x);
  RS_TRY(keep.From(c, call.rays, x)); b.Set(layout::kIntersectTreeBindRays, x);
  RS_TRY(keep.From(c, std::span<const layout::Triangle>(call.scene->triangles), x)); b.Set(layout::kIntersectTreeBindTriangles, x);
  RS_TRY(keep.Output(c, n * 4, x, tests.data())); b.Set(layout::kIntersectTreeBindTests, x);
  RS_TRY(keep.From(c, std::span<const std::uint64_t>(hits), bh)); b.Set(layout::kIntersectTreeBindHits, bh);
  RS_TRY(keep.From(c, std::span<const std::uint32_t>(occluded), bocc)); b.Set(layout::kIntersectTreeBindOccluded, bocc);
  const layout::IntersectTreePush push{static_cast<std::uint32_t>(n), shadow ? 1u : 0u};
  if (n) RS_TRY(RunKernel(c, K(PassId::kIntersectTree), b.All(), &push, sizeof push, push.count));
  RS_TRY(keep.CopyBack());
  // The kernel starts from empty results; merge into the caller's (min for hits, or for occlusion).
  if (shadow) {
    RS_TRY(bocc->Read(occluded.data(), occluded.size() * 4));
    for (std::size_t i = 0; i < rays; ++i) (*call.occluded)[i] |= occluded[i];
  } else {
    RS_TRY(bh->Read(hits.data(), hits.size() * 8));
    for (std::size_t i = 0; i < rays; ++i) (*call.hits)[i] = std::min((*call.hits)[i], hits[i]);
  }
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
