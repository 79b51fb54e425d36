// The passes that run as Vulkan kernels so far, with the same inputs and outputs as their emulated
// counterparts in emu/passes.h.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/gpu/vulkan.h"

namespace rayspace::gpu_backend {

// Planted faults: pass name -> fault number (1 = the pass's first fault), compiled into the kernel
// through a specialization constant.
using Faults = std::map<std::string, std::uint32_t>;

// Names of the passes with kernels, in pipeline order, and how many faults each can plant.
const std::vector<std::pair<std::string, std::uint32_t>>& KernelPasses();

class VulkanPasses {
 public:
  // local_size: invocations per workgroup for every compute kernel (results must not depend on it).
  static vk::Status Create(int device, const Faults& faults, std::unique_ptr<VulkanPasses>& out,
                           std::uint32_t local_size = 64);
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
  vk::Status Trim(const emu::SparseRays& in, emu::Trimmed& out, bool reflection = false);
  vk::Status Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum, std::vector<std::uint8_t>& out);
  const vk::Context& context() const { return *ctx_; }
  // Passes whose buffers grow with the pair streams (traverse, reduce) split their dispatches so no
  // binding exceeds the device's maxStorageBufferRange, or this many bytes when smaller (tests).
  void SetSplitBytes(std::size_t bytes) { split_bytes_ = bytes; }
  std::size_t SplitBytes() const;
  // Dispatches the split-aware passes issued so far beyond one per call (for reports and tests).
  std::size_t extra_dispatches() const { return extra_dispatches_; }

 private:
  vk::Status ReduceInParts(const std::vector<std::uint32_t>& flags, const std::vector<std::uint32_t>& values, std::uint32_t s,
                           bool scan, std::vector<std::uint32_t>& out);
  vk::Status Raygen(const vk::Kernel& k, const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                    const SceneBuffers& scene, emu::SparseRays& out);
  std::unique_ptr<vk::Context> ctx_;
  std::uint32_t raster_fault_ = 0;
  std::size_t split_bytes_ = 0, extra_dispatches_ = 0;
  vk::Kernel surfaces_, surfaces_hits_, raygen_shadow_, raygen_reflection_, trim_, trim_reflection_, shade_, resolve_, hash_, compress_, sort_, decompress_, build_, traverse_, reduce_, intersect_, raygen_refraction_;
};

}  // namespace rayspace::gpu_backend
