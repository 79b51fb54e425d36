#include <cstring>
#include <span>

#include <fmt/format.h>

#include "build.spv.h"
#include "hash.spv.h"
#include "raster_frag.spv.h"
#include "raster_vert.spv.h"
#include "rayspace/gpu/raster.h"
#include "intersect.spv.h"
#include "reduce.spv.h"
#include "traverse.spv.h"
#include "raygen_reflection.spv.h"
#include "raygen_refraction.spv.h"
#include "sort.spv.h"
#include "raygen_shadow.spv.h"
#include "shade.spv.h"
#include "surfaces.spv.h"
#include "surfaces_hits.spv.h"
#include "rayspace/gpu/passes.h"
#include "resolve.spv.h"
#include "trim.spv.h"

namespace rayspace::gpu_backend {
namespace {

#define RS_TRY(expr)              \
  do {                            \
    vk::Status rs_s = (expr);     \
    if (!rs_s) return rs_s;       \
  } while (0)

template <typename T>
vk::Status Make(vk::Context& c, const std::vector<T>& v, vk::Buffer& b) {
  RS_TRY(c.CreateBuffer(v.size() * sizeof(T), b));
  b.Upload(v);
  return vk::Status::Ok();
}

// A buffer holding `v` (at least one element: an empty input still needs something to bind).
template <typename T>
vk::Status MakeFrom(vk::Context& c, std::span<const T> v, vk::Buffer& b) {
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(v.size(), 1) * sizeof(T), b));
  std::memset(b.data(), 0, b.size());
  if (!v.empty()) std::memcpy(b.data(), v.data(), v.size_bytes());
  return vk::Status::Ok();
}

constexpr std::uint32_t kTrimBlock = 4096;

// Records one dispatch, submits it and waits.
vk::Status RunKernel(vk::Context& c, const vk::Kernel& k, std::span<const vk::Buffer* const> buffers, const void* push,
                     std::size_t push_size, std::uint32_t invocations) {
  vk::Recorder rec(c);
  RS_TRY(rec.Dispatch(k, buffers, push, push_size, invocations));
  return rec.Submit();
}

}  // namespace

const std::vector<std::pair<std::string, std::uint32_t>>& KernelPasses() {
  static const std::vector<std::pair<std::string, std::uint32_t>> kPasses = {
      {"raster", 1}, {"surfaces", 1}, {"raygen.shadow", 2}, {"trim", 1}, {"hash", 1}, {"compress", 1}, {"sort", 1},
      {"decompress", 1}, {"build", 1}, {"traverse", 1}, {"reduce", 2}, {"intersect", 1}, {"shade", 1},
      {"raygen.reflection", 1}, {"raygen.refraction", 1}, {"surfaces.hits", 1}, {"resolve", 1}};
  return kPasses;
}

vk::Status VulkanPasses::Create(int device, const Faults& faults, std::unique_ptr<VulkanPasses>& out,
                                std::uint32_t local_size) {
  auto p = std::make_unique<VulkanPasses>();
  RS_TRY(vk::Context::Create(device, p->ctx_));
  auto fault = [&](const char* pass) {
    auto it = faults.find(pass);
    return it == faults.end() ? 0u : it->second;
  };
  RS_TRY(p->ctx_->CreateKernel("raygen.shadow", kSpirv_raygen_shadow, 5, fault("raygen.shadow"), p->raygen_shadow_, local_size));
  p->raster_fault_ = fault("raster");
  RS_TRY(p->ctx_->CreateKernel("surfaces", kSpirv_surfaces, 6, fault("surfaces"), p->surfaces_, local_size));
  RS_TRY(p->ctx_->CreateKernel("surfaces.hits", kSpirv_surfaces_hits, 6, fault("surfaces.hits"), p->surfaces_hits_, local_size));
  RS_TRY(p->ctx_->CreateKernel("raygen.reflection", kSpirv_raygen_reflection, 5, fault("raygen.reflection"),
                               p->raygen_reflection_));
  RS_TRY(p->ctx_->CreateKernel("raygen.refraction", kSpirv_raygen_refraction, 5, fault("raygen.refraction"),
                               p->raygen_refraction_, local_size));
  RS_TRY(p->ctx_->CreateKernel("shade", kSpirv_shade, 7, fault("shade"), p->shade_, local_size));
  // One trim kernel serves both ray types; a planted trim fault applies to the type it names.
  RS_TRY(p->ctx_->CreateKernel("trim.shadow", kSpirv_trim, 5, fault("trim"), p->trim_, local_size));
  RS_TRY(p->ctx_->CreateKernel("trim.reflection", kSpirv_trim, 5, fault("trim"), p->trim_reflection_, local_size));
  RS_TRY(p->ctx_->CreateKernel("hash.shadow", kSpirv_hash, 3, fault("hash"), p->hash_, local_size));
  // One kernel, three passes (phases); each pass gets its own pipeline so a fault stays in its pass.
  RS_TRY(p->ctx_->CreateKernel("compress.shadow", kSpirv_sort, 9, fault("compress"), p->compress_, local_size));
  RS_TRY(p->ctx_->CreateKernel("sort.shadow", kSpirv_sort, 9, fault("sort"), p->sort_, local_size));
  RS_TRY(p->ctx_->CreateKernel("decompress.shadow", kSpirv_sort, 9, fault("decompress"), p->decompress_, local_size));
  RS_TRY(p->ctx_->CreateKernel("build.shadow", kSpirv_build, 5, fault("build"), p->build_, local_size));
  RS_TRY(p->ctx_->CreateKernel("traverse.shadow", kSpirv_traverse, 9, fault("traverse"), p->traverse_, local_size));
  RS_TRY(p->ctx_->CreateKernel("reduce.shadow", kSpirv_reduce, 6, fault("reduce"), p->reduce_, local_size));
  RS_TRY(p->ctx_->CreateKernel("intersect.shadow", kSpirv_intersect, 8, fault("intersect"), p->intersect_, local_size));
  RS_TRY(p->ctx_->CreateKernel("resolve", kSpirv_resolve, 2, fault("resolve"), p->resolve_, local_size));
  out = std::move(p);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::RaygenShadow(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                      const SceneBuffers& scene, emu::SparseRays& out) {
  vk::Context& c = *ctx_;
  vk::Buffer bs, bl, bf, br, bflags;
  RS_TRY(Make(c, surfaces, bs));
  RS_TRY(Make(c, scene.lights, bl));
  RS_TRY(Make(c, std::vector<gpu::FrameConstants>{fc}, bf));
  const std::size_t slots = surfaces.size() * scene.lights.size();
  RS_TRY(c.CreateBuffer(slots * sizeof(gpu::Ray), br));
  RS_TRY(c.CreateBuffer(slots * sizeof(std::uint32_t), bflags));
  const std::uint32_t push[2] = {static_cast<std::uint32_t>(surfaces.size()), static_cast<std::uint32_t>(scene.lights.size())};
  const vk::Buffer* bufs[5] = {&bs, &bl, &bf, &br, &bflags};
  RS_TRY(RunKernel(c, raygen_shadow_, bufs, push, sizeof push, static_cast<std::uint32_t>(surfaces.size())));
  out.rays = br.Download<gpu::Ray>(slots);
  out.flags = bflags.Download<std::uint32_t>(slots);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Surfaces(const gpu::FrameConstants& fc, const emu::GBuffer& g, const SceneBuffers& scene,
                                  std::vector<gpu::Surface>& out) {
  vk::Context& c = *ctx_;
  const std::uint32_t n = static_cast<std::uint32_t>(g.prim.size());
  vk::Buffer bp, bn, bprim, binfo, bf, bs;
  RS_TRY(Make(c, g.position, bp));
  RS_TRY(Make(c, g.normal, bn));
  RS_TRY(Make(c, g.prim, bprim));
  RS_TRY(Make(c, scene.info, binfo));
  RS_TRY(Make(c, std::vector<gpu::FrameConstants>{fc}, bf));
  RS_TRY(c.CreateBuffer(n * sizeof(gpu::Surface), bs));
  const vk::Buffer* bufs[6] = {&bp, &bn, &bprim, &binfo, &bf, &bs};
  RS_TRY(RunKernel(c, surfaces_, bufs, &n, sizeof n, n));
  out = bs.Download<gpu::Surface>(n);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::RaygenReflection(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                          const SceneBuffers& scene, emu::SparseRays& out) {
  return Raygen(raygen_reflection_, fc, surfaces, scene, out);
}

vk::Status VulkanPasses::RaygenRefraction(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                          const SceneBuffers& scene, emu::SparseRays& out) {
  return Raygen(raygen_refraction_, fc, surfaces, scene, out);
}

// One ray slot per surface (reflection and refraction share their buffers and launch).
vk::Status VulkanPasses::Raygen(const vk::Kernel& kernel, const gpu::FrameConstants& fc,
                                const std::vector<gpu::Surface>& surfaces, const SceneBuffers& scene,
                                emu::SparseRays& out) {
  vk::Context& c = *ctx_;
  const std::uint32_t n = static_cast<std::uint32_t>(surfaces.size());
  vk::Buffer bs, bm, bf, br, bflags;
  RS_TRY(Make(c, surfaces, bs));
  RS_TRY(Make(c, scene.materials, bm));
  RS_TRY(Make(c, std::vector<gpu::FrameConstants>{fc}, bf));
  RS_TRY(c.CreateBuffer(n * sizeof(gpu::Ray), br));
  RS_TRY(c.CreateBuffer(n * sizeof(std::uint32_t), bflags));
  const vk::Buffer* bufs[5] = {&bs, &bm, &bf, &br, &bflags};
  RS_TRY(RunKernel(c, kernel, bufs, &n, sizeof n, n));
  out.rays = br.Download<gpu::Ray>(n);
  out.flags = bflags.Download<std::uint32_t>(n);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Shade(const std::vector<gpu::Surface>& surfaces, const std::vector<std::uint32_t>& shadow_flags,
                               const std::vector<std::uint32_t>& shadow_offsets, const std::vector<std::uint32_t>& occluded,
                               const SceneBuffers& scene, std::vector<std::uint64_t>& accum) {
  vk::Context& c = *ctx_;
  vk::Buffer bs, bfl, boff, bocc, bm, bl, ba;
  // Empty inputs (no lights) still need a buffer to bind.
  const std::vector<std::uint32_t> none{0u};
  RS_TRY(Make(c, surfaces, bs));
  RS_TRY(Make(c, shadow_flags.empty() ? none : shadow_flags, bfl));
  RS_TRY(Make(c, shadow_offsets.empty() ? none : shadow_offsets, boff));
  RS_TRY(Make(c, occluded.empty() ? none : occluded, bocc));
  RS_TRY(Make(c, scene.materials, bm));
  RS_TRY(Make(c, scene.lights.empty() ? std::vector<gpu::Light>(1) : scene.lights, bl));
  RS_TRY(Make(c, accum, ba));
  const std::uint32_t push[2] = {static_cast<std::uint32_t>(surfaces.size()), static_cast<std::uint32_t>(scene.lights.size())};
  const vk::Buffer* bufs[7] = {&bs, &bfl, &boff, &bocc, &bm, &bl, &ba};
  RS_TRY(RunKernel(c, shade_, bufs, push, sizeof push, push[0]));
  accum = ba.Download<std::uint64_t>(accum.size());
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Trim(const emu::SparseRays& in, emu::Trimmed& out, bool reflection) {
  vk::Context& c = *ctx_;
  const std::uint32_t n = static_cast<std::uint32_t>(in.flags.size());
  const std::uint32_t blocks = (n + kTrimBlock - 1) / kTrimBlock;
  vk::Buffer bflags, bsums, boff, bsparse, bdense;
  RS_TRY(Make(c, in.flags, bflags));
  RS_TRY(c.CreateBuffer((blocks + 1) * sizeof(std::uint32_t), bsums));
  RS_TRY(c.CreateBuffer(n * sizeof(std::uint32_t), boff));
  RS_TRY(Make(c, in.rays, bsparse));
  RS_TRY(c.CreateBuffer(n * sizeof(gpu::Ray), bdense));  // upper bound; the count comes from the scan
  const vk::Buffer* bufs[5] = {&bflags, &bsums, &boff, &bsparse, &bdense};
  vk::Recorder rec(c);
  for (std::uint32_t phase = 0; phase < 3; ++phase) {  // one submit for the three dispatches
    const std::uint32_t push[2] = {n, phase};
    RS_TRY(rec.Dispatch(reflection ? trim_reflection_ : trim_, bufs, push, sizeof push, phase == 1 ? 1 : blocks));
  }
  RS_TRY(rec.Submit());
  const std::uint32_t total = bsums.Download<std::uint32_t>(blocks + 1)[blocks];
  if (total > n) return vk::Status::Fail(fmt::format("trim kernel reported {} rays out of {} slots", total, n));
  out.offsets = boff.Download<std::uint32_t>(n);
  out.rays = bdense.Download<gpu::Ray>(total);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Hash(const std::vector<gpu::Ray>& rays, const gpu::FrameConstants& fc, const emu::HashConfig& h,
                              std::vector<std::uint32_t>& keys, std::uint32_t quad_width, std::uint32_t quad_depth) {
  vk::Context& c = *ctx_;
  const std::uint32_t n = static_cast<std::uint32_t>(rays.size());
  vk::Buffer br, bf, bk;
  RS_TRY(Make(c, rays.empty() ? std::vector<gpu::Ray>(1) : rays, br));
  RS_TRY(Make(c, std::vector<gpu::FrameConstants>{fc}, bf));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * 4, bk));
  const std::int32_t push[8] = {static_cast<std::int32_t>(n), h.light_bits, h.polar_bits, h.azimuth_bits, h.origin_bits,
                                h.direction_bits, static_cast<std::int32_t>(quad_width), static_cast<std::int32_t>(quad_depth)};
  const vk::Buffer* bufs[3] = {&br, &bf, &bk};
  RS_TRY(RunKernel(c, hash_, bufs, push, sizeof push, n));
  keys = bk.Download<std::uint32_t>(n);
  return vk::Status::Ok();
}

namespace {

// Buffers of the sort kernel (see gpu/shaders/sort.comp for their roles).
struct SortBuffers {
  vk::Buffer keys, key, base, size, sorted, order, count, scratch, sums;
};

std::uint32_t Blocks(std::size_t n) { return static_cast<std::uint32_t>((n + kTrimBlock - 1) / kTrimBlock); }

vk::Status MakeSortBuffers(vk::Context& c, std::size_t n, std::size_t chunks, SortBuffers& b) {
  const std::size_t w = std::max<std::size_t>(n, 1) * 4, cw = std::max<std::size_t>(chunks, 1) * 4;
  const std::size_t blocks = std::max<std::size_t>(Blocks(std::max(n, chunks)), 1);
  RS_TRY(c.CreateBuffer(w, b.keys));
  RS_TRY(c.CreateBuffer(cw, b.key));
  RS_TRY(c.CreateBuffer(cw, b.base));
  RS_TRY(c.CreateBuffer(cw, b.size));
  RS_TRY(c.CreateBuffer(2 * cw, b.sorted));
  RS_TRY(c.CreateBuffer(w, b.order));
  RS_TRY(c.CreateBuffer(4, b.count));
  RS_TRY(c.CreateBuffer((2 * std::max(n, chunks) + 256 * blocks + 256 + 16) * 4, b.scratch));
  RS_TRY(c.CreateBuffer((blocks + 1) * 4, b.sums));
  return vk::Status::Ok();
}

struct SortPush {
  std::uint32_t n, phase, shift, src, dst, blocks;
};

vk::Status Phase(vk::Recorder& rec, const vk::Kernel& k, SortBuffers& b, SortPush push, std::uint32_t invocations) {
  const vk::Buffer* bufs[9] = {&b.keys, &b.key, &b.base, &b.size, &b.sorted, &b.order, &b.count, &b.scratch, &b.sums};
  return rec.Dispatch(k, bufs, &push, sizeof push, invocations);
}

}  // namespace

vk::Status VulkanPasses::Compress(const std::vector<std::uint32_t>& keys, emu::Chunks& out) {
  const std::uint32_t n = static_cast<std::uint32_t>(keys.size()), blocks = Blocks(n);
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, n, n, b));
  if (n) b.keys.Upload(keys);
  vk::Recorder rec(*ctx_);
  RS_TRY(Phase(rec, compress_, b, {n, 0, 0, 0, 0, blocks}, n));
  RS_TRY(Phase(rec, compress_, b, {n, 1, 0, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, compress_, b, {n, 2, 0, 0, 0, blocks}, 1));
  RS_TRY(Phase(rec, compress_, b, {n, 3, 0, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, compress_, b, {n, 4, 0, 0, 0, blocks}, n));
  RS_TRY(rec.Submit());
  const std::uint32_t chunks = b.count.Download<std::uint32_t>(1)[0];
  if (chunks > n) return vk::Status::Fail(fmt::format("compress kernel reported {} chunks for {} keys", chunks, n));
  out.key = b.key.Download<std::uint32_t>(chunks);
  out.base = b.base.Download<std::uint32_t>(chunks);
  out.size = b.size.Download<std::uint32_t>(chunks);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::SortChunks(const std::vector<std::uint32_t>& chunk_keys, std::vector<std::uint32_t>& sorted) {
  const std::uint32_t chunks = static_cast<std::uint32_t>(chunk_keys.size()), blocks = Blocks(chunks);
  if (blocks > 65535) return vk::Status::Fail(fmt::format("sort: {} chunks exceed the kernel's limit", chunks));
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, 1, chunks, b));
  if (chunks) b.key.Upload(chunk_keys);
  vk::Recorder rec(*ctx_);
  RS_TRY(Phase(rec, sort_, b, {chunks, 10, 0, 0, 0, blocks}, chunks));
  std::uint32_t src = 0, dst = chunks;
  for (std::uint32_t shift = 0; shift < 32; shift += 8) {
    RS_TRY(Phase(rec, sort_, b, {chunks, 11, shift, src, dst, blocks}, blocks));
    RS_TRY(Phase(rec, sort_, b, {chunks, 12, shift, src, dst, blocks}, 256));
    RS_TRY(Phase(rec, sort_, b, {chunks, 13, shift, src, dst, blocks}, 1));
    RS_TRY(Phase(rec, sort_, b, {chunks, 14, shift, src, dst, blocks}, blocks));
    std::swap(src, dst);
  }
  RS_TRY(rec.Submit());
  sorted = b.sorted.Download<std::uint32_t>(chunks);  // four passes end in the first half
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Decompress(const emu::Chunks& chunks, const std::vector<std::uint32_t>& sorted,
                                    std::vector<std::uint32_t>& order) {
  std::uint64_t n = 0;
  for (std::uint32_t s : chunks.size) n += s;
  const std::uint32_t count = static_cast<std::uint32_t>(chunks.key.size()), blocks = Blocks(count);
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, n, count, b));
  if (count) {
    b.key.Upload(chunks.key);
    b.base.Upload(chunks.base);
    b.size.Upload(chunks.size);
    b.sorted.Upload(sorted);
  }
  const std::uint32_t rays = static_cast<std::uint32_t>(n);
  vk::Recorder rec(*ctx_);
  RS_TRY(Phase(rec, decompress_, b, {count, 20, rays, 0, 0, blocks}, count));
  RS_TRY(Phase(rec, decompress_, b, {count, 21, rays, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, decompress_, b, {count, 22, rays, 0, 0, blocks}, 1));
  RS_TRY(Phase(rec, decompress_, b, {count, 23, rays, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, decompress_, b, {count, 24, rays, 0, 0, blocks}, rays));
  RS_TRY(rec.Submit());
  order = b.order.Download<std::uint32_t>(n);
  return vk::Status::Ok();
}

namespace {

template <typename T>
std::vector<T> NonEmpty(const std::vector<T>& v) {  // a buffer binding needs at least one element
  return v.empty() ? std::vector<T>(1) : v;
}

}  // namespace

vk::Status VulkanPasses::BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                     const std::vector<std::uint32_t>& first, std::vector<gpu::ConeNode>& nodes) {
  vk::Context& c = *ctx_;
  const std::uint32_t count = static_cast<std::uint32_t>(first.size() - 1);
  vk::Buffer br, bo, bf, bb, bn;
  RS_TRY(Make(c, NonEmpty(rays), br));
  RS_TRY(Make(c, NonEmpty(order), bo));
  RS_TRY(Make(c, first, bf));
  RS_TRY(Make(c, std::vector<gpu::ConeNode>(1), bb));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(count, 1) * sizeof(gpu::ConeNode), bn));
  const std::uint32_t push[2] = {count, 0};
  const vk::Buffer* bufs[5] = {&br, &bo, &bf, &bb, &bn};
  RS_TRY(RunKernel(c, build_, bufs, push, sizeof push, count));
  nodes = bn.Download<gpu::ConeNode>(count);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::BuildParents(const std::vector<gpu::ConeNode>& below, const std::vector<std::uint32_t>& first,
                                      std::vector<gpu::ConeNode>& nodes) {
  vk::Context& c = *ctx_;
  const std::uint32_t count = static_cast<std::uint32_t>(first.size() - 1);
  vk::Buffer br, bo, bf, bb, bn;
  RS_TRY(Make(c, std::vector<gpu::Ray>(1), br));
  RS_TRY(Make(c, std::vector<std::uint32_t>(1), bo));
  RS_TRY(Make(c, first, bf));
  RS_TRY(Make(c, NonEmpty(below), bb));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(count, 1) * sizeof(gpu::ConeNode), bn));
  const std::uint32_t push[2] = {count, 1};
  const vk::Buffer* bufs[5] = {&br, &bo, &bf, &bb, &bn};
  RS_TRY(RunKernel(c, build_, bufs, push, sizeof push, count));
  nodes = bn.Download<gpu::ConeNode>(count);
  return vk::Status::Ok();
}

namespace {

struct TraversePush {
  std::uint32_t phase, count, t0, b0, tris, objects, use_mask, base_up, base, children_max;
  float eps;
  std::uint32_t id_base;  // top level: packed node ids are relative to this node
};

// One traverse.comp dispatch: its bindings (empty spans bind a zeroed placeholder) and where its
// outputs go (flags and values: `slots` words, tested: `tested` words; null to skip).
struct TraverseIo {
  std::span<const gpu::ConeNode> nodes;
  std::span<const glm::vec4> spheres;
  std::span<const gpu::TriangleInfo> info;
  std::span<const std::uint32_t> mask, pairs, first;
  std::size_t slots = 0, tested = 0;
  std::uint32_t *flags_out = nullptr, *values_out = nullptr, *tested_out = nullptr;
};

vk::Status RunTraverse(vk::Context& c, const vk::Kernel& k, const TraversePush& push, const TraverseIo& io) {
  vk::Buffer bn, bs, bi, bm, bp, bf, bfl, bv, bt;
  RS_TRY(MakeFrom(c, io.nodes, bn));
  RS_TRY(MakeFrom(c, io.spheres, bs));
  RS_TRY(MakeFrom(c, io.info, bi));
  RS_TRY(MakeFrom(c, io.mask, bm));
  RS_TRY(MakeFrom(c, io.pairs, bp));
  RS_TRY(MakeFrom(c, io.first, bf));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(io.slots, 1) * 4, bfl));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(io.slots, 1) * 4, bv));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(io.tested, 1) * 4, bt));
  const vk::Buffer* bufs[9] = {&bn, &bs, &bi, &bm, &bp, &bf, &bfl, &bv, &bt};
  RS_TRY(RunKernel(c, k, bufs, &push, sizeof push, push.count));
  if (io.flags_out) std::memcpy(io.flags_out, bfl.data(), io.slots * 4);
  if (io.values_out) std::memcpy(io.values_out, bv.data(), io.slots * 4);
  if (io.tested_out) std::memcpy(io.tested_out, bt.data(), io.tested * 4);
  return vk::Status::Ok();
}


}  // namespace

std::size_t VulkanPasses::SplitBytes() const {
  const std::size_t device = static_cast<std::size_t>(ctx_->max_storage_buffer_range());
  return split_bytes_ ? std::min(split_bytes_, device) : device;
}

// Rows of top nodes per dispatch so that the flags/values/tested bindings stay within the split size.
vk::Status VulkanPasses::TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1,
                                     std::uint32_t b0, std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres,
                                     const SceneBuffers& scene, float eps, const std::vector<std::uint32_t>& object_mask,
                                     std::vector<std::uint32_t>& flags, std::vector<std::uint32_t>& values,
                                     std::vector<std::uint32_t>& tested) {
  const std::size_t T = b1 - b0, count = static_cast<std::size_t>(t1 - t0) * T;
  flags.assign(count, 0);
  values.assign(count, 0);
  tested.assign(count, 0);
  const std::uint32_t rows = static_cast<std::uint32_t>(std::max<std::size_t>(1, SplitBytes() / 4 / std::max<std::size_t>(T, 1)));
  for (std::uint32_t r0 = t0; r0 < t1; r0 += rows) {
    const std::uint32_t r1 = std::min(t1, r0 + rows);
    const std::size_t at = static_cast<std::size_t>(r0 - t0) * T;
    if (r0 != t0) ++extra_dispatches_;
    const std::uint32_t count = static_cast<std::uint32_t>(static_cast<std::size_t>(r1 - r0) * T);
    const TraversePush push{0, count, r0, b0, static_cast<std::uint32_t>(T), static_cast<std::uint32_t>(scene.objects.size()),
                            object_mask.empty() ? 0u : 1u, 0, 0, 0, eps, t0};
    RS_TRY(RunTraverse(*ctx_, traverse_, push,
                       {top, tri_spheres, scene.info, object_mask, {}, {}, count, count, flags.data() + at, values.data() + at,
                        tested.data() + at}));
  }
  return vk::Status::Ok();
}

// Pairs per dispatch so that the slot bindings (pairs x children) stay within the split size.
vk::Status VulkanPasses::TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                                       const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                                       std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                                       float eps, std::vector<std::uint32_t>& flags, std::vector<std::uint32_t>& values,
                                       std::vector<std::uint32_t>& tested) {
  const std::size_t count = pairs.size();
  flags.assign(count * children_max, 0);
  values.assign(count * children_max, 0);
  tested.assign(count, 0);
  const std::size_t per = std::max<std::size_t>(1, SplitBytes() / 4 / children_max);
  for (std::size_t p0 = 0; p0 < count; p0 += per) {
    const std::uint32_t n = static_cast<std::uint32_t>(std::min(count - p0, per));
    if (p0 != 0) ++extra_dispatches_;
    const TraversePush push{1, n, 0, b0, 0, 0, 0, base_up, base, children_max, eps, 0};
    RS_TRY(RunTraverse(*ctx_, traverse_, push,
                       {nodes, tri_spheres, {}, {}, std::span(pairs).subspan(p0, n), first, std::size_t{n} * children_max, n,
                        flags.data() + p0 * children_max, values.data() + p0 * children_max, tested.data() + p0}));
  }
  return vk::Status::Ok();
}

vk::Status VulkanPasses::ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres,
                                    float eps, std::vector<std::uint32_t>& mask) {
  const std::uint32_t objects = static_cast<std::uint32_t>(object_spheres.size());
  const std::uint32_t count = static_cast<std::uint32_t>(top.size()) * objects;
  mask.assign(count, 0);
  const TraversePush push{2, count, 0, 0, 0, objects, 0, 0, 0, 0, eps, 0};
  return RunTraverse(*ctx_, traverse_, push, {top, object_spheres, {}, {}, {}, {}, count, 0, mask.data(), nullptr, nullptr});
}

namespace {

// One stream reduction in reduce.comp: hierarchical with components of s slots (phases 0-4), or
// scan-based (phases 10, 2, 11) when `scan`.
vk::Status RunReduce(vk::Context& c, const vk::Kernel& k, std::span<const std::uint32_t> flags,
                     std::span<const std::uint32_t> values, std::uint32_t s, bool scan, std::vector<std::uint32_t>& out) {
  const std::uint32_t n = static_cast<std::uint32_t>(flags.size());
  const std::uint32_t comps = scan ? 0 : (n + s - 1) / s, blocks = Blocks(scan ? n : comps);
  vk::Buffer bf, bv, bl, bc, bs, bo;
  RS_TRY(MakeFrom(c, flags, bf));
  RS_TRY(MakeFrom(c, values, bv));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(scan ? 1 : n, 1) * 4, bl));      // per-component values
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(comps, 1) * 4, bc));              // per-component counts
  RS_TRY(c.CreateBuffer((blocks + 1) * 4, bs));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * 4, bo));
  const vk::Buffer* bufs[6] = {&bf, &bv, &bl, &bc, &bs, &bo};
  static const std::uint32_t kHierPhases[5] = {0, 1, 2, 3, 4}, kScanPhases[3] = {10, 2, 11};
  const std::span<const std::uint32_t> phases = scan ? std::span<const std::uint32_t>(kScanPhases) : std::span<const std::uint32_t>(kHierPhases);
  vk::Recorder rec(c);
  for (std::uint32_t phase : phases) {
    // Invocations: one per component (0, 4), per block (1, 3, 10, 11), or one (2).
    const std::uint32_t invocations = phase == 2 ? 1 : (phase == 0 || phase == 4) ? comps : blocks;
    const std::uint32_t push[5] = {n, phase, scan ? 1u : s, comps, blocks};
    RS_TRY(rec.Dispatch(k, bufs, push, sizeof push, invocations));
  }
  RS_TRY(rec.Submit());
  const std::uint32_t total = bs.Download<std::uint32_t>(blocks + 1)[blocks];
  if (total > n) return vk::Status::Fail(fmt::format("reduce kernel reported {} of {} slots", total, n));
  out = bo.Download<std::uint32_t>(total);
  return vk::Status::Ok();
}

}  // namespace

// Order-preserving compaction composes: reducing consecutive parts and concatenating their outputs
// gives the whole stream's result, so big streams are reduced in parts that fit the split size
// (hierarchical parts end on component boundaries).
vk::Status VulkanPasses::ReduceInParts(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values,
                                       std::uint32_t s, bool scan, std::vector<std::uint32_t>& out) {
  out.clear();
  const std::size_t n = flags.size(), per = scan ? std::max<std::size_t>(1, SplitBytes() / 4)
                                                 : std::max<std::size_t>(1, SplitBytes() / 4 / s) * s;
  std::size_t p0 = 0;
  do {
    const std::size_t len = std::min(n - p0, per);
    std::vector<std::uint32_t> part;
    if (p0 != 0) ++extra_dispatches_;
    RS_TRY(RunReduce(*ctx_, reduce_, std::span(flags).subspan(p0, len), std::span(values).subspan(p0, len), s, scan, part));
    out.insert(out.end(), part.begin(), part.end());
    p0 += len;
  } while (p0 < n);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Reduce(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values,
                                std::uint32_t s, std::vector<std::uint32_t>& out) {
  return ReduceInParts(flags, values, s, false, out);
}

vk::Status VulkanPasses::ReduceScan(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values,
                                    std::vector<std::uint32_t>& out) {
  return ReduceInParts(flags, values, 1, true, out);
}

vk::Status VulkanPasses::SurfacesFromHits(const std::vector<gpu::Ray>& rays, const std::vector<std::uint64_t>& hits,
                                          const SceneBuffers& scene, std::vector<gpu::Surface>& out) {
  vk::Context& c = *ctx_;
  const std::uint32_t n = static_cast<std::uint32_t>(rays.size());
  vk::Buffer br, bh, bt, bn, bi, bs;
  RS_TRY(Make(c, NonEmpty(rays), br));
  RS_TRY(Make(c, NonEmpty(hits), bh));
  RS_TRY(Make(c, scene.triangles, bt));
  RS_TRY(Make(c, scene.normals, bn));
  RS_TRY(Make(c, scene.info, bi));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * sizeof(gpu::Surface), bs));
  const vk::Buffer* bufs[6] = {&br, &bh, &bt, &bn, &bi, &bs};
  RS_TRY(RunKernel(c, surfaces_hits_, bufs, &n, sizeof n, n));
  out = bs.Download<gpu::Surface>(n);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                   std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                   const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, bool shadow,
                                   std::vector<std::uint64_t>& hits, std::vector<std::uint32_t>& occluded,
                                   std::vector<std::uint32_t>& tests) {
  vk::Context& c = *ctx_;
  const std::uint32_t count = static_cast<std::uint32_t>(pairs.size());
  vk::Buffer bp, bf, bo, br, bt, bh, bocc, btests;
  RS_TRY(Make(c, NonEmpty(pairs), bp));
  RS_TRY(Make(c, first1, bf));
  RS_TRY(Make(c, NonEmpty(order), bo));
  RS_TRY(Make(c, NonEmpty(rays), br));
  RS_TRY(Make(c, scene.triangles, bt));
  RS_TRY(Make(c, std::vector<std::uint64_t>(std::max<std::size_t>(rays.size(), 1), ~std::uint64_t{0}), bh));
  RS_TRY(Make(c, std::vector<std::uint32_t>(std::max<std::size_t>(rays.size(), 1), 0u), bocc));
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(count, 1) * 4, btests));
  const std::uint32_t push[4] = {count, base1, b0, shadow ? 1u : 0u};
  const vk::Buffer* bufs[8] = {&bp, &bf, &bo, &br, &bt, &bh, &bocc, &btests};
  RS_TRY(RunKernel(c, intersect_, bufs, push, sizeof push, count));
  hits = bh.Download<std::uint64_t>(rays.size());
  occluded = bocc.Download<std::uint32_t>(rays.size());
  tests = btests.Download<std::uint32_t>(count);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Raster(const gpu::FrameConstants& fc, const SceneBuffers& scene, emu::GBuffer& out) {
  RasterTargets t;
  RS_TRY(RasterGBuffer(*ctx_, kSpirv_raster_vert, kSpirv_raster_frag, fc, scene, raster_fault_, t));
  out.width = static_cast<int>(fc.dims.x);
  out.height = static_cast<int>(fc.dims.y);
  out.diffuse = std::move(t.diffuse);
  out.specular = std::move(t.specular);
  out.position = std::move(t.position);
  out.normal = std::move(t.normal);
  out.prim = std::move(t.prim);
  out.depth = std::move(t.depth);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum,
                                 std::vector<std::uint8_t>& out) {
  vk::Context& c = *ctx_;
  const std::uint32_t n = static_cast<std::uint32_t>(static_cast<std::size_t>(fc.dims.x) * fc.dims.y * 3);
  vk::Buffer ba, brgb;
  RS_TRY(Make(c, accum, ba));
  RS_TRY(c.CreateBuffer(n * sizeof(std::uint32_t), brgb));
  const vk::Buffer* bufs[2] = {&ba, &brgb};
  RS_TRY(RunKernel(c, resolve_, bufs, &n, sizeof n, n));
  const std::vector<std::uint32_t> wide = brgb.Download<std::uint32_t>(n);
  out.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(wide[i]);
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
