#include <array>
#include <cstring>
#include <deque>
#include <span>

#include <fmt/format.h>

#include "kernel_table.h"
#include "raster_frag.spv.h"
#include "raster_vert.spv.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/error.h"
#include "rayspace/gpu/raster.h"
#include "rayspace/pass_registry.h"

namespace rayspace::gpu_backend {
namespace {

#define RS_TRY(expr)              \
  do {                            \
    vk::Status rs_s = (expr);     \
    if (!rs_s) return rs_s;       \
  } while (0)


// A buffer holding `v` (at least one element: an empty input still needs something to bind).
template <typename T>
vk::Status MakeFrom(vk::Context& c, std::span<const T> v, vk::Buffer& b) {
  RS_TRY(c.CreateBuffer(std::max<std::size_t>(v.size(), 1) * sizeof(T), b));
  std::memset(b.data(), 0, b.size());
  if (!v.empty()) std::memcpy(b.data(), v.data(), v.size_bytes());
  return vk::Status::Ok();
}

// Records one dispatch, submits it and waits.
vk::Status RunKernel(vk::Context& c, const vk::Kernel& k, std::span<const vk::Buffer* const> buffers, const void* push,
                     std::size_t push_size, std::uint32_t invocations) {
  vk::Recorder rec(c);
  RS_TRY(rec.Dispatch(k, buffers, push, push_size, invocations));
  return rec.Submit();
}

// An array read or written at any index, bound as gpu::kBufferPages consecutive bindings of `page`
// elements each (gpu/shaders/paged.glsl). Pages are as large as one binding may be.
struct Paged {
  std::array<vk::Buffer, gpu::kBufferPages> pages;
  std::uint32_t page = 1;  // elements per page
  template <typename T>
  void Read(std::span<T> out) const {
    for (std::size_t p = 0, at = 0; p < pages.size() && at < out.size(); ++p, at += page)
      std::memcpy(out.data() + at, pages[p].data(), std::min<std::size_t>(page, out.size() - at) * sizeof(T));
  }
};
static_assert(gpu::kBufferPages == 4, "paged.glsl declares four bindings per paged array");

// The buffers of one dispatch, each placed at its binding number from rayspace/contract.h.
template <std::uint32_t N>
class Bindings {
 public:
  Bindings& Set(std::uint32_t binding, const vk::Buffer* b) {
    RS_CHECK(binding < N && b);
    bufs_[binding] = b;
    return *this;
  }
  Bindings& Set(std::uint32_t first, const Paged& p) {
    for (std::uint32_t k = 0; k < gpu::kBufferPages; ++k) Set(first + k, &p.pages[k]);
    return *this;
  }
  // Every binding must have been set.
  std::span<const vk::Buffer* const> All() const {
    for (const vk::Buffer* b : bufs_) RS_CHECK(b != nullptr);
    return bufs_;
  }

 private:
  std::array<const vk::Buffer*, N> bufs_{};
};

// `multi` counts the arrays that needed more than one page (for reports and tests).
template <typename T>
vk::Status MakePaged(vk::Context& c, std::span<const T> v, const char* what, Paged& out, std::size_t& multi) {
  const std::size_t per = std::min<std::size_t>(std::max<VkDeviceSize>(1, c.storage_limit() / sizeof(T)), 0x80000000u);
  if (v.size() > per * gpu::kBufferPages)
    return vk::Status::Fail(fmt::format("{}: {} elements of {} bytes need more than {} bindings of {} bytes", what, v.size(),
                                        sizeof(T), gpu::kBufferPages, c.storage_limit()));
  out.page = static_cast<std::uint32_t>(per);
  if (v.size() > per) ++multi;
  for (std::size_t p = 0; p < gpu::kBufferPages; ++p) {
    const std::size_t at = std::min(v.size(), p * per);
    RS_TRY(MakeFrom(c, v.subspan(at, std::min(per, v.size() - at)), out.pages[p]));
  }
  return vk::Status::Ok();
}

// Buffers that must live until a recorder's submit.
class Keep {
 public:
  template <typename T>
  vk::Status From(vk::Context& c, std::span<const T> v, const vk::Buffer*& out) {
    vk::Buffer& b = New();
    RS_TRY(MakeFrom(c, v, b));
    out = &b;
    return vk::Status::Ok();
  }
  // An output buffer of `bytes` whose contents CopyBack() copies to `dst` (null: none).
  vk::Status Output(vk::Context& c, std::size_t bytes, const vk::Buffer*& out, void* dst = nullptr) {
    vk::Buffer& b = New();
    RS_TRY(c.CreateBuffer(std::max<std::size_t>(bytes, 4), b));
    out = &b;
    if (dst && bytes) back_.push_back({&b, dst, bytes});
    return vk::Status::Ok();
  }
  // After the submit.
  void CopyBack() const {
    for (const Back& k : back_) std::memcpy(k.dst, k.buf->data(), k.bytes);
  }

 private:
  struct Back {
    const vk::Buffer* buf = nullptr;
    void* dst;
    std::size_t bytes;
  };
  vk::Buffer& New() { return bufs_.emplace_back(); }
  std::deque<vk::Buffer> bufs_;  // a deque: addresses stay valid as it grows
  std::vector<Back> back_;
};

// Calls part(i0, i1) for consecutive ranges covering [0, n) of at most `per` elements (once for an
// empty stream); every range after the first counts as an extra dispatch.
template <typename F>
vk::Status ForParts(std::size_t n, std::size_t per, std::size_t& extra, F&& part) {
  per = std::max<std::size_t>(1, std::min<std::size_t>(per, 0x40000000u));
  std::size_t i0 = 0;
  do {
    const std::size_t i1 = std::min(n, i0 + per);
    if (i0 != 0) ++extra;
    RS_TRY(part(i0, i1));
    i0 = i1;
  } while (i0 < n);
  return vk::Status::Ok();
}

// Blocks of a blocked scan over n elements (one invocation each).
std::uint32_t Blocks(std::size_t n) { return static_cast<std::uint32_t>((n + gpu::kScanBlock - 1) / gpu::kScanBlock); }

template <typename T>
std::span<const T> Slice(const std::vector<T>& v, std::size_t i0, std::size_t i1) {
  return std::span<const T>(v).subspan(i0, i1 - i0);
}

}  // namespace

std::span<const std::uint32_t> BuiltinKernel(std::string_view kernel) {
  for (const BuiltinSpirv& k : kBuiltinKernels)
    if (k.name == kernel) return k.spirv;
  return {};
}

std::vector<std::string_view> BuiltinKernelNames() {
  std::vector<std::string_view> names;
  for (const BuiltinSpirv& k : kBuiltinKernels) names.push_back(k.name);
  return names;
}

// One pipeline per registered compute pass, named by the pass (a planted fault stays in its pass even
// where passes share a kernel file, as compress, sort and decompress do).
vk::Status VulkanPasses::Create(int device, const Faults& faults, std::unique_ptr<VulkanPasses>& out,
                                std::uint32_t local_size, const KernelOverrides& overrides) {
  auto p = std::make_unique<VulkanPasses>();
  RS_TRY(vk::Context::Create(device, p->ctx_));
  auto fault = [&](std::string_view pass) {
    auto it = faults.find(std::string(pass));
    return it == faults.end() ? 0u : it->second;
  };
  for (const PassSpec& spec : kPasses) {
    if (spec.graphics) continue;
    std::span<const std::uint32_t> spirv = BuiltinKernel(spec.kernel);
    if (auto it = overrides.find(std::string(spec.name)); it != overrides.end()) spirv = it->second;
    if (spirv.empty()) return vk::Status::Fail(fmt::format("pass '{}': no kernel '{}.comp' was built", spec.name, spec.kernel));
    RS_TRY(p->ctx_->CreateKernel(std::string(spec.name), spirv, spec.bindings, fault(spec.name),
                                 p->kernels_[static_cast<std::size_t>(spec.id)], local_size));
  }
  p->raster_fault_ = fault(Pass(PassId::kRaster).name);
  out = std::move(p);
  return vk::Status::Ok();
}

std::size_t VulkanPasses::PerPart(std::size_t bytes_per_element) const {
  return std::max<std::size_t>(1, SplitBytes() / std::max<std::size_t>(bytes_per_element, 1));
}

// Element-wise passes run over consecutive parts of their per-element buffers, each part within one
// binding, all parts in one submit; outputs are copied back part by part.
vk::Status VulkanPasses::RaygenShadow(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                      const SceneBuffers& scene, emu::SparseRays& out) {
  vk::Context& c = *ctx_;
  const std::size_t lights = scene.lights.size(), slots = surfaces.size() * lights;
  if (lights * sizeof(gpu::Ray) > SplitBytes())
    return vk::Status::Fail(fmt::format("{} lights: one surface's {} bytes of shadow-ray slots exceed one binding of {} bytes",
                                        lights, lights * sizeof(gpu::Ray), SplitBytes()));
  out.rays.assign(slots, gpu::Ray{});
  out.flags.assign(slots, 0);
  Keep keep;
  const vk::Buffer *bl = nullptr, *bf = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::Light>(scene.lights), bl));
  RS_TRY(keep.From(c, std::span<const gpu::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(surfaces.size(), PerPart(std::max(sizeof(gpu::Surface), lights * sizeof(gpu::Ray))), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bs = nullptr, *br = nullptr, *bflags = nullptr;
                    RS_TRY(keep.From(c, Slice(surfaces, i0, i1), bs));
                    RS_TRY(keep.Output(c, (i1 - i0) * lights * sizeof(gpu::Ray), br, out.rays.data() + i0 * lights));
                    RS_TRY(keep.Output(c, (i1 - i0) * lights * 4, bflags, out.flags.data() + i0 * lights));
                    const gpu::RaygenShadowPush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(lights)};
                    Bindings<gpu::kRaygenBindings> b;
                    b.Set(gpu::kRaygenBindSurfaces, bs).Set(gpu::kRaygenBindLightsOrMaterials, bl).Set(gpu::kRaygenBindFrame, bf);
                    b.Set(gpu::kRaygenBindRays, br).Set(gpu::kRaygenBindFlags, bflags);
                    return rec.Dispatch(K(PassId::kRaygenShadow), b.All(), &push, sizeof push, push.surface_count);
                  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Surfaces(const gpu::FrameConstants& fc, const emu::GBuffer& g, const SceneBuffers& scene,
                                  std::vector<gpu::Surface>& out) {
  vk::Context& c = *ctx_;
  out.assign(g.prim.size(), gpu::Surface{});
  Keep keep;
  const vk::Buffer *binfo = nullptr, *bf = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::TriangleInfo>(scene.info), binfo));
  RS_TRY(keep.From(c, std::span<const gpu::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(g.prim.size(), PerPart(sizeof(gpu::Surface)), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bp = nullptr, *bn = nullptr, *bprim = nullptr, *bs = nullptr;
                    RS_TRY(keep.From(c, Slice(g.position, i0, i1), bp));
                    RS_TRY(keep.From(c, Slice(g.normal, i0, i1), bn));
                    RS_TRY(keep.From(c, Slice(g.prim, i0, i1), bprim));
                    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(gpu::Surface), bs, out.data() + i0));
                    const gpu::SurfacesPush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(i0)};
                    Bindings<gpu::kSurfacesBindings> b;
                    b.Set(gpu::kSurfacesBindPosition, bp).Set(gpu::kSurfacesBindNormal, bn).Set(gpu::kSurfacesBindPrim, bprim);
                    b.Set(gpu::kSurfacesBindInfo, binfo).Set(gpu::kSurfacesBindFrame, bf).Set(gpu::kSurfacesBindSurfaces, bs);
                    return rec.Dispatch(K(PassId::kSurfaces), b.All(), &push, sizeof push, push.pixels);
                  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  return vk::Status::Ok();
}

vk::Status VulkanPasses::RaygenReflection(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                          const SceneBuffers& scene, emu::SparseRays& out) {
  return Raygen(K(PassId::kRaygenReflection), fc, surfaces, scene, out);
}

vk::Status VulkanPasses::RaygenRefraction(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                                          const SceneBuffers& scene, emu::SparseRays& out) {
  return Raygen(K(PassId::kRaygenRefraction), fc, surfaces, scene, out);
}

// One ray slot per surface (reflection and refraction share their buffers and launch).
vk::Status VulkanPasses::Raygen(const vk::Kernel& kernel, const gpu::FrameConstants& fc,
                                const std::vector<gpu::Surface>& surfaces, const SceneBuffers& scene,
                                emu::SparseRays& out) {
  vk::Context& c = *ctx_;
  out.rays.assign(surfaces.size(), gpu::Ray{});
  out.flags.assign(surfaces.size(), 0);
  Keep keep;
  const vk::Buffer *bm = nullptr, *bf = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::Material>(scene.materials), bm));
  RS_TRY(keep.From(c, std::span<const gpu::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(surfaces.size(), PerPart(sizeof(gpu::Surface)), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bs = nullptr, *br = nullptr, *bflags = nullptr;
                    RS_TRY(keep.From(c, Slice(surfaces, i0, i1), bs));
                    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(gpu::Ray), br, out.rays.data() + i0));
                    RS_TRY(keep.Output(c, (i1 - i0) * 4, bflags, out.flags.data() + i0));
                    const gpu::RaygenPush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(i0)};
                    Bindings<gpu::kRaygenBindings> b;
                    b.Set(gpu::kRaygenBindSurfaces, bs).Set(gpu::kRaygenBindLightsOrMaterials, bm).Set(gpu::kRaygenBindFrame, bf);
                    b.Set(gpu::kRaygenBindRays, br).Set(gpu::kRaygenBindFlags, bflags);
                    return rec.Dispatch(kernel, b.All(), &push, sizeof push, push.surface_count);
                  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Shade(const std::vector<gpu::Surface>& surfaces, const std::vector<std::uint32_t>& shadow_flags,
                               const std::vector<std::uint32_t>& shadow_offsets, const std::vector<std::uint32_t>& occluded,
                               const SceneBuffers& scene, std::vector<std::uint64_t>& accum) {
  vk::Context& c = *ctx_;
  const std::size_t lights = scene.lights.size();
  Keep keep;
  const vk::Buffer *bm = nullptr, *bl = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::Material>(scene.materials), bm));
  RS_TRY(keep.From(c, std::span<const gpu::Light>(scene.lights), bl));
  // Occlusion is read by dense shadow ray and the accumulator added to by pixel, in any order.
  Paged occ, acc;
  RS_TRY(MakePaged(c, std::span<const std::uint32_t>(occluded), "shade: occlusion flags", occ, paged_arrays_));
  RS_TRY(MakePaged(c, std::span<const std::uint64_t>(accum), "shade: colour accumulator", acc, paged_arrays_));
  vk::Recorder rec(c);
  RS_TRY(ForParts(surfaces.size(), PerPart(std::max(sizeof(gpu::Surface), lights * 4)), extra_dispatches_,
                  [&](std::size_t i0, std::size_t i1) -> vk::Status {
                    const vk::Buffer *bs = nullptr, *bfl = nullptr, *boff = nullptr;
                    RS_TRY(keep.From(c, Slice(surfaces, i0, i1), bs));
                    RS_TRY(keep.From(c, Slice(shadow_flags, i0 * lights, i1 * lights), bfl));
                    RS_TRY(keep.From(c, Slice(shadow_offsets, i0 * lights, i1 * lights), boff));
                    const gpu::ShadePush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(lights), occ.page,
                                              acc.page};
                    Bindings<gpu::kShadeBindings> b;
                    b.Set(gpu::kShadeBindSurfaces, bs).Set(gpu::kShadeBindShadowFlags, bfl).Set(gpu::kShadeBindShadowOffsets, boff);
                    b.Set(gpu::kShadeBindMaterials, bm).Set(gpu::kShadeBindLights, bl);
                    b.Set(gpu::kShadeBindOccluded, occ).Set(gpu::kShadeBindAccum, acc);
                    return rec.Dispatch(K(PassId::kShade), b.All(), &push, sizeof push, push.surface_count);
                  }));
  RS_TRY(rec.Submit());
  acc.Read(std::span<std::uint64_t>(accum));
  return vk::Status::Ok();
}

// A stream larger than one binding is trimmed in consecutive parts, one submit each: the part's
// offsets start at the flagged count of the parts before it (read back from the GPU), and the dense
// rays of the parts are concatenated, which is what order-preserving compaction of the whole gives.
vk::Status VulkanPasses::Trim(const emu::SparseRays& in, emu::Trimmed& out) {
  vk::Context& c = *ctx_;
  out.offsets.assign(in.flags.size(), 0);
  out.rays.clear();
  std::uint32_t carry = 0;
  return ForParts(in.flags.size(), PerPart(sizeof(gpu::Ray)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>(i1 - i0), blocks = Blocks(n);
    vk::Buffer bflags, bsums, boff, bsparse, bdense;
    RS_TRY(MakeFrom(c, Slice(in.flags, i0, i1), bflags));
    RS_TRY(c.CreateBuffer((blocks + 1) * sizeof(std::uint32_t), bsums));
    RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * sizeof(std::uint32_t), boff));
    RS_TRY(MakeFrom(c, Slice(in.rays, i0, i1), bsparse));
    RS_TRY(c.CreateBuffer(std::max<std::size_t>(n, 1) * sizeof(gpu::Ray), bdense));  // upper bound; the scan gives the count
    Bindings<gpu::kTrimBindings> b;
    b.Set(gpu::kTrimBindFlags, &bflags).Set(gpu::kTrimBindSums, &bsums).Set(gpu::kTrimBindOffsets, &boff);
    b.Set(gpu::kTrimBindSparse, &bsparse).Set(gpu::kTrimBindDense, &bdense);
    vk::Recorder rec(c);
    // One submit for the three dispatches; the scan of the block sums runs on one invocation.
    for (std::uint32_t phase : {gpu::kTrimPhaseBlockSums, gpu::kTrimPhaseScanSums, gpu::kTrimPhaseScatter}) {
      const gpu::TrimPush push{n, phase, carry};
      RS_TRY(rec.Dispatch(K(PassId::kTrim), b.All(), &push, sizeof push, phase == gpu::kTrimPhaseScanSums ? 1 : blocks));
    }
    RS_TRY(rec.Submit());
    const std::uint32_t total = bsums.Download<std::uint32_t>(blocks + 1)[blocks];
    if (total > n) return vk::Status::Fail(fmt::format("trim kernel reported {} rays out of {} slots", total, n));
    if (n) std::memcpy(out.offsets.data() + i0, boff.data(), std::size_t{n} * 4);
    const std::size_t at = out.rays.size();
    out.rays.resize(at + total);
    if (total) std::memcpy(out.rays.data() + at, bdense.data(), std::size_t{total} * sizeof(gpu::Ray));
    carry += total;
    return vk::Status::Ok();
  });
}

vk::Status VulkanPasses::Hash(const std::vector<gpu::Ray>& rays, const gpu::FrameConstants& fc, const emu::HashConfig& h,
                              std::vector<std::uint32_t>& keys, std::uint32_t quad_width, std::uint32_t quad_depth) {
  vk::Context& c = *ctx_;
  keys.assign(rays.size(), 0);
  Keep keep;
  const vk::Buffer* bf = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::FrameConstants>(&fc, 1), bf));
  vk::Recorder rec(c);
  RS_TRY(ForParts(rays.size(), PerPart(sizeof(gpu::Ray)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *br = nullptr, *bk = nullptr;
    RS_TRY(keep.From(c, Slice(rays, i0, i1), br));
    RS_TRY(keep.Output(c, (i1 - i0) * 4, bk, keys.data() + i0));
    const gpu::HashPush push{static_cast<std::uint32_t>(i1 - i0), h.light_bits, h.polar_bits, h.azimuth_bits, h.origin_bits,
                             h.direction_bits, quad_width, quad_depth};
    Bindings<gpu::kHashBindings> b;
    b.Set(gpu::kHashBindRays, br).Set(gpu::kHashBindFrame, bf).Set(gpu::kHashBindKeys, bk);
    return rec.Dispatch(K(PassId::kHash), b.All(), &push, sizeof push, push.n);
  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  return vk::Status::Ok();
}

namespace {

// Buffers of the sort kernel (see gpu/shaders/sort.comp for their roles).
struct SortBuffers {
  vk::Buffer keys, key, base, size, sorted, order, count, scratch, sums;
};

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

vk::Status Phase(vk::Recorder& rec, const vk::Kernel& k, SortBuffers& sb, gpu::SortPush push, std::uint32_t invocations) {
  Bindings<gpu::kSortBindings> b;
  b.Set(gpu::kSortBindKeys, &sb.keys).Set(gpu::kSortBindChunkKey, &sb.key).Set(gpu::kSortBindChunkBase, &sb.base);
  b.Set(gpu::kSortBindChunkSize, &sb.size).Set(gpu::kSortBindSorted, &sb.sorted).Set(gpu::kSortBindOrder, &sb.order);
  b.Set(gpu::kSortBindCount, &sb.count).Set(gpu::kSortBindScratch, &sb.scratch).Set(gpu::kSortBindSums, &sb.sums);
  return rec.Dispatch(k, b.All(), &push, sizeof push, invocations);
}

}  // namespace

vk::Status VulkanPasses::Compress(const std::vector<std::uint32_t>& keys, emu::Chunks& out) {
  const std::uint32_t n = static_cast<std::uint32_t>(keys.size()), blocks = Blocks(n);
  SortBuffers b;
  RS_TRY(MakeSortBuffers(*ctx_, n, n, b));
  if (n) b.keys.Upload(keys);
  vk::Recorder rec(*ctx_);
  const vk::Kernel& k = K(PassId::kCompress);
  RS_TRY(Phase(rec, k, b, {n, gpu::kCompressPhaseHeads, 0, 0, 0, blocks}, n));
  RS_TRY(Phase(rec, k, b, {n, gpu::kCompressPhaseBlockSums, 0, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, k, b, {n, gpu::kCompressPhaseScanSums, 0, 0, 0, blocks}, 1));
  RS_TRY(Phase(rec, k, b, {n, gpu::kCompressPhaseChunks, 0, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, k, b, {n, gpu::kCompressPhaseSizes, 0, 0, 0, blocks}, n));
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
  const vk::Kernel& k = K(PassId::kSort);
  RS_TRY(Phase(rec, k, b, {chunks, gpu::kSortPhaseInit, 0, 0, 0, blocks}, chunks));
  std::uint32_t src = 0, dst = chunks;
  for (std::uint32_t shift = 0; shift < 32; shift += 8) {
    RS_TRY(Phase(rec, k, b, {chunks, gpu::kSortPhaseHistograms, shift, src, dst, blocks}, blocks));
    RS_TRY(Phase(rec, k, b, {chunks, gpu::kSortPhaseBinScan, shift, src, dst, blocks}, 256));
    RS_TRY(Phase(rec, k, b, {chunks, gpu::kSortPhaseTotalScan, shift, src, dst, blocks}, 1));
    RS_TRY(Phase(rec, k, b, {chunks, gpu::kSortPhaseScatter, shift, src, dst, blocks}, blocks));
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
  const vk::Kernel& k = K(PassId::kDecompress);
  RS_TRY(Phase(rec, k, b, {count, gpu::kDecompressPhaseSizes, rays, 0, 0, blocks}, count));
  RS_TRY(Phase(rec, k, b, {count, gpu::kDecompressPhaseBlockSums, rays, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, k, b, {count, gpu::kDecompressPhaseScanSums, rays, 0, 0, blocks}, 1));
  RS_TRY(Phase(rec, k, b, {count, gpu::kDecompressPhaseStarts, rays, 0, 0, blocks}, blocks));
  RS_TRY(Phase(rec, k, b, {count, gpu::kDecompressPhaseRays, rays, 0, 0, blocks}, rays));
  RS_TRY(rec.Submit());
  order = b.order.Download<std::uint32_t>(n);
  return vk::Status::Ok();
}


// One build.comp launch over the level's nodes, in parts of the node array (each dispatch gets its
// slice of `first`, one longer, and of the output); rays, order and the level below are paged.
vk::Status VulkanPasses::Build(std::uint32_t phase, std::span<const gpu::Ray> rays, std::span<const std::uint32_t> order,
                               std::span<const gpu::ConeNode> below, const std::vector<std::uint32_t>& first,
                               std::vector<gpu::ConeNode>& nodes) {
  vk::Context& c = *ctx_;
  if (first.empty()) return vk::Status::Fail("build: empty node offsets");
  const std::size_t count = first.size() - 1;
  nodes.assign(count, gpu::ConeNode{});
  Paged pr, po, pb;
  RS_TRY(MakePaged(c, rays, "build: rays", pr, paged_arrays_));
  RS_TRY(MakePaged(c, order, "build: sorted order", po, paged_arrays_));
  RS_TRY(MakePaged(c, below, "build: nodes of the level below", pb, paged_arrays_));
  Keep keep;
  vk::Recorder rec(c);
  RS_TRY(ForParts(count, PerPart(sizeof(gpu::ConeNode)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *bf = nullptr, *bn = nullptr;
    RS_TRY(keep.From(c, Slice(first, i0, i1 + 1), bf));
    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(gpu::ConeNode), bn, nodes.data() + i0));
    const gpu::BuildPush push{static_cast<std::uint32_t>(i1 - i0), phase, pr.page, po.page, pb.page};
    Bindings<gpu::kBuildBindings> b;
    b.Set(gpu::kBuildBindFirst, bf).Set(gpu::kBuildBindNodes, bn);
    b.Set(gpu::kBuildBindRays, pr).Set(gpu::kBuildBindOrder, po).Set(gpu::kBuildBindBelow, pb);
    return rec.Dispatch(K(PassId::kBuild), b.All(), &push, sizeof push, push.count);
  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  return vk::Status::Ok();
}

vk::Status VulkanPasses::BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                     const std::vector<std::uint32_t>& first, std::vector<gpu::ConeNode>& nodes) {
  return Build(gpu::kBuildPhaseLeaves, rays, order, {}, first, nodes);
}

vk::Status VulkanPasses::BuildParents(const std::vector<gpu::ConeNode>& below, const std::vector<std::uint32_t>& first,
                                      std::vector<gpu::ConeNode>& nodes) {
  return Build(gpu::kBuildPhaseParents, {}, {}, below, first, nodes);
}

namespace {

// The traverse.comp inputs one pass call reads whole, uploaded once and bound by every part of the
// call: the level's nodes and child offsets (paged, read by node id), spheres and triangle info
// (empty spans bind a zeroed placeholder).
class Traverser {
 public:
  Traverser(vk::Context& c, const vk::Kernel& k) : c_(c), k_(k) {}
  vk::Status Upload(std::span<const gpu::ConeNode> nodes, std::span<const std::uint32_t> first, std::span<const glm::vec4> spheres,
                    std::span<const gpu::TriangleInfo> info, std::size_t& multi) {
    RS_TRY(MakePaged(c_, nodes, "traverse: nodes", nodes_, multi));
    RS_TRY(MakePaged(c_, first, "traverse: child offsets", first_, multi));
    RS_TRY(MakeFrom(c_, spheres, spheres_));
    RS_TRY(MakeFrom(c_, info, info_));
    return vk::Status::Ok();
  }
  // One part, in a submit of its own (its output buffers are freed before the next part): `mask`
  // and `pairs` are this part's; flags and values (`slots` words) and tested (`tested` words) go to
  // the given pointers (null: not read back).
  vk::Status Part(gpu::TraversePush push, std::span<const std::uint32_t> mask, std::span<const std::uint32_t> pairs, std::size_t slots,
                  std::size_t tested, std::uint32_t* flags_out, std::uint32_t* values_out, std::uint32_t* tested_out) const {
    Keep keep;
    const vk::Buffer *bm = nullptr, *bp = nullptr, *bfl = nullptr, *bv = nullptr, *bt = nullptr;
    RS_TRY(keep.From(c_, mask, bm));
    RS_TRY(keep.From(c_, pairs, bp));
    RS_TRY(keep.Output(c_, slots * 4, bfl, flags_out));
    RS_TRY(keep.Output(c_, slots * 4, bv, values_out));
    RS_TRY(keep.Output(c_, tested * 4, bt, tested_out));
    push.node_page = nodes_.page;
    push.first_page = first_.page;
    Bindings<gpu::kTraverseBindings> b;
    b.Set(gpu::kTraverseBindTriSpheres, &spheres_).Set(gpu::kTraverseBindInfo, &info_).Set(gpu::kTraverseBindMask, bm);
    b.Set(gpu::kTraverseBindPairs, bp).Set(gpu::kTraverseBindFlags, bfl).Set(gpu::kTraverseBindValues, bv);
    b.Set(gpu::kTraverseBindTested, bt).Set(gpu::kTraverseBindNodes, nodes_).Set(gpu::kTraverseBindFirst, first_);
    RS_TRY(RunKernel(c_, k_, b.All(), &push, sizeof push, push.count));
    keep.CopyBack();
    return vk::Status::Ok();
  }

 private:
  vk::Context& c_;
  const vk::Kernel& k_;
  Paged nodes_, first_;
  vk::Buffer spheres_, info_;
};

}  // namespace

std::size_t VulkanPasses::SplitBytes() const { return static_cast<std::size_t>(ctx_->storage_limit()); }

vk::Status VulkanPasses::TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1,
                                     std::uint32_t b0, std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres,
                                     const SceneBuffers& scene, float eps, const std::vector<std::uint32_t>& object_mask,
                                     std::vector<std::uint32_t>& flags, std::vector<std::uint32_t>& values,
                                     std::vector<std::uint32_t>& tested) {
  const std::size_t T = b1 - b0, count = static_cast<std::size_t>(t1 - t0) * T;
  flags.assign(count, 0);
  values.assign(count, 0);
  tested.assign(count, 0);
  Traverser tr(*ctx_, K(PassId::kTraverse));
  RS_TRY(tr.Upload(top, {}, tri_spheres, scene.info, paged_arrays_));
  // Parts are rows of top nodes, so that the flags/values/tested bindings and the object mask's rows
  // for those nodes stay within one binding.
  const std::size_t objects = scene.objects.size(), row_words = std::max<std::size_t>({T, object_mask.empty() ? 1 : objects, 1});
  return ForParts(t1 - t0, PerPart(4 * row_words), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t r0 = t0 + static_cast<std::uint32_t>(i0), r1 = t0 + static_cast<std::uint32_t>(i1);
    const std::size_t at = i0 * T, n = (i1 - i0) * T;
    const gpu::TraversePush push{gpu::kTraversePhaseTop, static_cast<std::uint32_t>(n), r0, b0, static_cast<std::uint32_t>(T),
                                 static_cast<std::uint32_t>(objects), object_mask.empty() ? 0u : 1u, 0, 0, 0, eps, t0, 0, 0};
    const std::span<const std::uint32_t> mask_rows =
        object_mask.empty() ? std::span<const std::uint32_t>() : std::span(object_mask).subspan(r0 * objects, (r1 - r0) * objects);
    return tr.Part(push, mask_rows, {}, n, n, flags.data() + at, values.data() + at, tested.data() + at);
  });
}

// Parts are ranges of pairs, so that the slot bindings (pairs x children) stay within one binding.
vk::Status VulkanPasses::TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                                       const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                                       std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                                       float eps, std::vector<std::uint32_t>& flags, std::vector<std::uint32_t>& values,
                                       std::vector<std::uint32_t>& tested) {
  const std::size_t count = pairs.size();
  flags.assign(count * children_max, 0);
  values.assign(count * children_max, 0);
  tested.assign(count, 0);
  Traverser tr(*ctx_, K(PassId::kTraverse));
  RS_TRY(tr.Upload(nodes, first, tri_spheres, {}, paged_arrays_));
  return ForParts(count, PerPart(4 * std::size_t{children_max}), extra_dispatches_, [&](std::size_t p0, std::size_t p1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>(p1 - p0);
    const gpu::TraversePush push{gpu::kTraversePhaseLevel, n, 0, b0, 0, 0, 0, base_up, base, children_max, eps, 0, 0, 0};
    return tr.Part(push, {}, Slice(pairs, p0, p1), std::size_t{n} * children_max, n, flags.data() + p0 * children_max,
                   values.data() + p0 * children_max, tested.data() + p0);
  });
}

// Parts of the mask (top nodes x objects), each within one binding; t0 carries the part's first
// element.
vk::Status VulkanPasses::ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres,
                                    float eps, std::vector<std::uint32_t>& mask) {
  const std::uint32_t objects = static_cast<std::uint32_t>(object_spheres.size());
  const std::size_t count = top.size() * objects;
  if (count > 0xFFFFFFFFu) return vk::Status::Fail(fmt::format("object mask: {} top nodes x {} objects exceed 2^32", top.size(), objects));
  mask.assign(count, 0);
  Traverser tr(*ctx_, K(PassId::kTraverse));
  RS_TRY(tr.Upload(top, {}, object_spheres, {}, paged_arrays_));
  return ForParts(count, PerPart(4), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const std::uint32_t n = static_cast<std::uint32_t>(i1 - i0);
    const gpu::TraversePush push{gpu::kTraversePhaseObjects, n, static_cast<std::uint32_t>(i0), 0, 0, objects, 0, 0, 0, 0, eps, 0, 0, 0};
    return tr.Part(push, {}, {}, n, 0, mask.data() + i0, nullptr, nullptr);
  });
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
  Bindings<gpu::kReduceBindings> b;
  b.Set(gpu::kReduceBindFlags, &bf).Set(gpu::kReduceBindValues, &bv).Set(gpu::kReduceBindLocal, &bl);
  b.Set(gpu::kReduceBindCounts, &bc).Set(gpu::kReduceBindSums, &bs).Set(gpu::kReduceBindOut, &bo);
  static constexpr std::uint32_t kHierPhases[5] = {gpu::kReducePhaseLocal, gpu::kReducePhaseBlockSums, gpu::kReducePhaseScanSums,
                                                   gpu::kReducePhaseOffsets, gpu::kReducePhaseConcat};
  static constexpr std::uint32_t kScanPhases[3] = {gpu::kReducePhaseFlagSums, gpu::kReducePhaseScanSums, gpu::kReducePhaseScatter};
  const std::span<const std::uint32_t> phases = scan ? std::span<const std::uint32_t>(kScanPhases) : std::span<const std::uint32_t>(kHierPhases);
  vk::Recorder rec(c);
  for (std::uint32_t phase : phases) {
    // Invocations: one per component (Local, Concat), one (ScanSums), else one per block.
    const std::uint32_t invocations = phase == gpu::kReducePhaseScanSums                                ? 1
                                      : (phase == gpu::kReducePhaseLocal || phase == gpu::kReducePhaseConcat) ? comps
                                                                                                            : blocks;
    const gpu::ReducePush push{n, phase, scan ? 1u : s, comps, blocks};
    RS_TRY(rec.Dispatch(k, b.All(), &push, sizeof push, invocations));
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
    RS_TRY(RunReduce(*ctx_, K(PassId::kReduce), std::span(flags).subspan(p0, len), std::span(values).subspan(p0, len), s, scan, part));
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
  out.assign(rays.size(), gpu::Surface{});
  Keep keep;
  const vk::Buffer *bt = nullptr, *bn = nullptr, *bi = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::Triangle>(scene.triangles), bt));
  RS_TRY(keep.From(c, std::span<const gpu::TriangleNormals>(scene.normals), bn));
  RS_TRY(keep.From(c, std::span<const gpu::TriangleInfo>(scene.info), bi));
  vk::Recorder rec(c);
  RS_TRY(ForParts(rays.size(), PerPart(sizeof(gpu::Surface)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *br = nullptr, *bh = nullptr, *bs = nullptr;
    RS_TRY(keep.From(c, Slice(rays, i0, i1), br));
    RS_TRY(keep.From(c, Slice(hits, i0, i1), bh));
    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(gpu::Surface), bs, out.data() + i0));
    const std::uint32_t n = static_cast<std::uint32_t>(i1 - i0);
    const gpu::SurfacesHitsPush push{n};
    Bindings<gpu::kSurfacesHitsBindings> b;
    b.Set(gpu::kSurfacesHitsBindRays, br).Set(gpu::kSurfacesHitsBindHits, bh).Set(gpu::kSurfacesHitsBindTriangles, bt);
    b.Set(gpu::kSurfacesHitsBindNormals, bn).Set(gpu::kSurfacesHitsBindInfo, bi).Set(gpu::kSurfacesHitsBindSurfaces, bs);
    return rec.Dispatch(K(PassId::kSurfacesHits), b.All(), &push, sizeof push, n);
  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  return vk::Status::Ok();
}

vk::Status VulkanPasses::Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                   std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                   const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, bool shadow,
                                   std::vector<std::uint64_t>& hits, std::vector<std::uint32_t>& occluded,
                                   std::vector<std::uint32_t>& tests) {
  vk::Context& c = *ctx_;
  // Pairs go in parts (their tests with them); everything indexed by leaf, sorted position or ray is
  // paged, and the hit or occlusion pages stay bound across the parts, which all go in one submit.
  // A batch writes only hits (closest hit) or only occlusion (shadow): the other stays as initialised
  // and is bound as a placeholder.
  hits.assign(rays.size(), ~std::uint64_t{0});
  occluded.assign(rays.size(), 0);
  tests.assign(pairs.size(), 0);
  Paged pf, po, pr, ph, pocc;
  RS_TRY(MakePaged(c, std::span<const std::uint32_t>(first1), "intersect: leaf offsets", pf, paged_arrays_));
  RS_TRY(MakePaged(c, std::span<const std::uint32_t>(order), "intersect: sorted order", po, paged_arrays_));
  RS_TRY(MakePaged(c, std::span<const gpu::Ray>(rays), "intersect: rays", pr, paged_arrays_));
  RS_TRY(MakePaged(c, shadow ? std::span<const std::uint64_t>() : std::span<const std::uint64_t>(hits), "intersect: closest hits",
                   ph, paged_arrays_));
  RS_TRY(MakePaged(c, shadow ? std::span<const std::uint32_t>(occluded) : std::span<const std::uint32_t>(),
                   "intersect: occlusion flags", pocc, paged_arrays_));
  Keep keep;
  const vk::Buffer* bt = nullptr;
  RS_TRY(keep.From(c, std::span<const gpu::Triangle>(scene.triangles), bt));
  vk::Recorder rec(c);
  RS_TRY(ForParts(pairs.size(), PerPart(4), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *bp = nullptr, *btests = nullptr;
    RS_TRY(keep.From(c, Slice(pairs, i0, i1), bp));
    RS_TRY(keep.Output(c, (i1 - i0) * 4, btests, tests.data() + i0));
    const gpu::IntersectPush push{static_cast<std::uint32_t>(i1 - i0), base1, b0, shadow ? 1u : 0u, pf.page, po.page,
                                  pr.page, ph.page, pocc.page};
    Bindings<gpu::kIntersectBindings> b;
    b.Set(gpu::kIntersectBindPairs, bp).Set(gpu::kIntersectBindTriangles, bt).Set(gpu::kIntersectBindTests, btests);
    b.Set(gpu::kIntersectBindFirst, pf).Set(gpu::kIntersectBindOrder, po).Set(gpu::kIntersectBindRays, pr);
    b.Set(gpu::kIntersectBindHits, ph).Set(gpu::kIntersectBindOccluded, pocc);
    return rec.Dispatch(K(PassId::kIntersect), b.All(), &push, sizeof push, push.count);
  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  if (shadow)
    pocc.Read(std::span<std::uint32_t>(occluded));
  else
    ph.Read(std::span<std::uint64_t>(hits));
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
  const std::size_t n = static_cast<std::size_t>(fc.dims.x) * fc.dims.y * 3;
  if (accum.size() != n) return vk::Status::Fail(fmt::format("resolve: {} accumulator channels for {} pixel channels", accum.size(), n));
  std::vector<std::uint32_t> wide(n);
  Keep keep;
  vk::Recorder rec(c);
  RS_TRY(ForParts(n, PerPart(sizeof(std::uint64_t)), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    const vk::Buffer *ba = nullptr, *brgb = nullptr;
    RS_TRY(keep.From(c, Slice(accum, i0, i1), ba));
    RS_TRY(keep.Output(c, (i1 - i0) * 4, brgb, wide.data() + i0));
    const gpu::ResolvePush push{static_cast<std::uint32_t>(i1 - i0)};
    Bindings<gpu::kResolveBindings> b;
    b.Set(gpu::kResolveBindAccum, ba).Set(gpu::kResolveBindRgb, brgb);
    return rec.Dispatch(K(PassId::kResolve), b.All(), &push, sizeof push, push.n);
  }));
  RS_TRY(rec.Submit());
  keep.CopyBack();
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(wide[i]);
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
