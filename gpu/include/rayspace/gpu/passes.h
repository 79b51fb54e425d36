// The passes that run as Vulkan kernels so far, with the same inputs and outputs as their emulated
// counterparts in emu/passes.h.
#pragma once
#include <array>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/gpu/vulkan.h"
#include "rayspace/pass_registry.h"

namespace rayspace::gpu_backend {

// Planted faults: pass name -> fault number (1 = the pass's first fault), compiled into the kernel
// through a specialization constant.
using Faults = std::map<std::string, std::uint32_t>;

// A user's SPIR-V for a pass, by pass name, run in place of the built-in kernel (`--kernel`).
using KernelOverrides = std::map<std::string, std::vector<std::uint32_t>>;

// The SPIR-V of a built-in compute kernel by file name (gpu/shaders/<kernel>.comp), or empty.
std::span<const std::uint32_t> BuiltinKernel(std::string_view kernel);
// The file names of every built-in compute kernel (gpu/shaders/*.comp), sorted.
std::vector<std::string_view> BuiltinKernelNames();

class VulkanPasses {
 public:
  // local_size: invocations per workgroup for every compute kernel (results must not depend on it).
  // One compute pipeline per registered pass (rayspace/pass_registry.h).
  static vk::Status Create(int device, const Faults& faults, std::unique_ptr<VulkanPasses>& out,
                           std::uint32_t local_size = 64, const KernelOverrides& overrides = {});
  // The raster as a graphics pipeline with all G-buffer targets.
  vk::Status Raster(const gpu::FrameConstants& fc, const SceneBuffers& scene, emu::GBuffer& out);
  vk::Status Surfaces(const gpu::FrameConstants& fc, const emu::GBuffer& g, const SceneBuffers& scene,
                      std::vector<gpu::Surface>& out);
  vk::Status RaygenReflection(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                              const SceneBuffers& scene, emu::SparseRays& out);
  vk::Status RaygenRefraction(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                              const SceneBuffers& scene, emu::SparseRays& out);
  // Adds the surfaces' shading into `accum` (in place, like the emulated pass).
  vk::Status Shade(const std::vector<gpu::Surface>& surfaces, const std::vector<std::uint32_t>& shadow_flags,
                   const std::vector<std::uint32_t>& shadow_offsets, const std::vector<std::uint32_t>& occluded,
                   const SceneBuffers& scene, std::vector<std::uint64_t>& accum);
  // quad_width > 0: Roger's quadtree keys (emu PassHashQuadtree).
  vk::Status Hash(const std::vector<gpu::Ray>& rays, const gpu::FrameConstants& fc, const emu::HashConfig& h,
                  std::vector<std::uint32_t>& keys, std::uint32_t quad_width = 0, std::uint32_t quad_depth = 0);
  vk::Status SurfacesFromHits(const std::vector<gpu::Ray>& rays, const std::vector<std::uint64_t>& hits,
                              const SceneBuffers& scene, std::vector<gpu::Surface>& out);
  // CRSH's culling mask (emu PassObjectMask), one word per (top node, object).
  vk::Status ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres, float eps,
                        std::vector<std::uint32_t>& mask);
  vk::Status Compress(const std::vector<std::uint32_t>& keys, emu::Chunks& out);
  vk::Status SortChunks(const std::vector<std::uint32_t>& chunk_keys, std::vector<std::uint32_t>& sorted);
  vk::Status Decompress(const emu::Chunks& chunks, const std::vector<std::uint32_t>& sorted, std::vector<std::uint32_t>& order);
  vk::Status BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                         const std::vector<std::uint32_t>& first, std::vector<gpu::ConeNode>& nodes);
  vk::Status BuildParents(const std::vector<gpu::ConeNode>& below, const std::vector<std::uint32_t>& first,
                          std::vector<gpu::ConeNode>& nodes);
  // Traversal of one block (see emu PassTraverseTop / PassTraverseLevel); flags and tested as uint32.
  vk::Status TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                         std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene, float eps,
                         const std::vector<std::uint32_t>& object_mask, std::vector<std::uint32_t>& flags, std::vector<std::uint32_t>& values, std::vector<std::uint32_t>& tested);
  vk::Status TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                           const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                           std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres, float eps,
                           std::vector<std::uint32_t>& flags, std::vector<std::uint32_t>& values, std::vector<std::uint32_t>& tested);
  // Roger et al.'s hierarchical stream reduction with components of `s` slots.
  vk::Status Reduce(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values, std::uint32_t s,
                    std::vector<std::uint32_t>& out);
  // The scan-based stream reduction (emu ReduceScan).
  vk::Status ReduceScan(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values,
                        std::vector<std::uint32_t>& out);
  vk::Status Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1, std::uint32_t base1,
                       std::uint32_t b0, const std::vector<std::uint32_t>& order, const std::vector<gpu::Ray>& rays,
                       const SceneBuffers& scene, bool shadow, std::vector<std::uint64_t>& hits,
                       std::vector<std::uint32_t>& occluded, std::vector<std::uint32_t>& tests);
  vk::Status RaygenShadow(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                          const SceneBuffers& scene, emu::SparseRays& out);
  vk::Status Trim(const emu::SparseRays& in, emu::Trimmed& out);
  vk::Status Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum, std::vector<std::uint8_t>& out);
  const vk::Context& context() const { return *ctx_; }
  // Buffers that grow with the frame never exceed one binding: element-wise passes run over parts
  // of their streams, and arrays read at any index are paged (gpu/shaders/paged.glsl). This is the
  // most bytes one binding gets: maxStorageBufferRange, or less after LimitForTesting.
  std::size_t SplitBytes() const;
  // Test hook: behave like a device whose bindings hold at most `storage_bytes` and whose launches
  // have at most `groups_x` workgroups per row (0 keeps the device's limit).
  void LimitForTesting(std::size_t storage_bytes, std::uint32_t groups_x) { ctx_->LimitForTesting(storage_bytes, groups_x); }
  // Dispatches beyond one per pass call, from parts and splits (for reports and tests).
  std::size_t extra_dispatches() const { return extra_dispatches_; }
  // Arrays bound over more than one page so far (for reports and tests).
  std::size_t paged_arrays() const { return paged_arrays_; }

 private:
  vk::Status ReduceInParts(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values, std::uint32_t s,
                           bool scan, std::vector<std::uint32_t>& out);
  vk::Status Build(std::uint32_t phase, std::span<const gpu::Ray> rays, std::span<const std::uint32_t> order,
                   std::span<const gpu::ConeNode> below, const std::vector<std::uint32_t>& first,
                   std::vector<gpu::ConeNode>& nodes);
  // Elements per part when each element takes `bytes_per_element` in the largest per-part binding.
  std::size_t PerPart(std::size_t bytes_per_element) const;
  vk::Status Raygen(const vk::Kernel& k, const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                    const SceneBuffers& scene, emu::SparseRays& out);
  const vk::Kernel& K(PassId id) const { return kernels_[static_cast<std::size_t>(id)]; }
  std::unique_ptr<vk::Context> ctx_;
  std::uint32_t raster_fault_ = 0;
  std::size_t extra_dispatches_ = 0, paged_arrays_ = 0;
  std::array<vk::Kernel, kPassCount> kernels_;  // by PassId; the raster's stays empty (a graphics pipeline)
};

}  // namespace rayspace::gpu_backend
